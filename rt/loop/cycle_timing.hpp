// cycle_timing.hpp — wake-up latency and compute-time statistics of the rt loop, kept in
// fixed histograms (no allocation after construction) so the cycle can record every sample.
#pragma once

#include <cstdint>

#include "ipc/latency_histogram.hpp"
#include "ipc/status.hpp"

namespace pcnc {

/// Both histograms of the loop plus the overrun count, summarised into TimingStats.
struct CycleTiming {
  LatencyHistogram wake;
  LatencyHistogram compute;
  std::uint64_t overruns = 0;

  TimingStats summary() const {
    TimingStats t;
    t.wake_min_us = wake.min();
    t.wake_mean_us = wake.mean();
    t.wake_p99_us = wake.quantile(0.99);
    t.wake_max_us = wake.max();
    t.compute_min_us = compute.min();
    t.compute_mean_us = compute.mean();
    t.compute_p99_us = compute.quantile(0.99);
    t.compute_max_us = compute.max();
    t.overruns = overruns;
    return t;
  }
};

}  // namespace pcnc
