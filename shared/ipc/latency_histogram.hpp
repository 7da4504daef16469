// latency_histogram.hpp — a fixed-size histogram of latencies in microseconds (0.25 µs bins
// up to 10 ms) with min/mean/max and quantiles. No allocation after construction, so the rt
// cycle can record into it; the host and the benchmarks use it too.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

namespace pcnc {

class LatencyHistogram {
 public:
  static constexpr double kBinUs = 0.25;
  static constexpr std::size_t kBins = 40000;  // 0 .. 10 ms in 0.25 µs bins; larger values go to the last

  void add(double us) { add(us, 1); }
  /// `n` samples of the same value (the rt under the virtual clock times runs of cycles and
  /// counts each cycle of a run with the run's mean).
  void add(double us, std::uint32_t n) {
    if (n == 0) return;
    if (us < 0.0) us = 0.0;
    std::size_t bin = static_cast<std::size_t>(us / kBinUs);
    if (bin >= kBins) bin = kBins - 1;
    bins_[bin] += n;
    const bool first = count_ == 0;
    count_ += n;
    sum_ += us * static_cast<double>(n);
    if (first || us < min_) min_ = us;
    if (us > max_) max_ = us;
  }
  std::uint64_t count() const { return count_; }
  double min() const { return count_ ? min_ : 0.0; }
  double max() const { return max_; }
  double mean() const { return count_ ? sum_ / static_cast<double>(count_) : 0.0; }
  /// The q-quantile (0..1), to the bin's upper edge but never outside [min, max]: the bin's
  /// edge may lie above the largest value it holds, and a p99 above the max is no figure.
  double quantile(double q) const {
    if (count_ == 0) return 0.0;
    const auto target = static_cast<std::uint64_t>(q * static_cast<double>(count_ - 1)) + 1;
    std::uint64_t seen = 0;
    for (std::size_t i = 0; i < kBins; ++i) {
      seen += bins_[i];
      if (seen >= target) {
        const double edge = static_cast<double>(i + 1) * kBinUs;
        return edge > max_ ? max_ : edge < min_ ? min_ : edge;
      }
    }
    return max_;
  }
  void clear() { *this = LatencyHistogram(); }

 private:
  std::array<std::uint32_t, kBins> bins_{};
  std::uint64_t count_ = 0;
  double sum_ = 0.0, min_ = 0.0, max_ = 0.0;
};

}  // namespace pcnc
