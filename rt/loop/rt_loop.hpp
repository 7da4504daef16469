// rt_loop.hpp — pcnc-rt's timer loop: every period it drains the mailbox, steps the Machine
// once, wakes the host when a ring slot was freed, publishes status and a trace sample.
// Under the real clock it sleeps to absolute deadlines with clock_nanosleep; under the
// virtual clock it runs the same cycle back to back, waiting only for the host's blocks.
#pragma once

#include <atomic>
#include <memory>
#include <string>

#include "config/config.hpp"
#include "loop/cycle_timing.hpp"
#include "loop/machine.hpp"
#include "ipc/segment.hpp"

namespace pcnc {

class TraceWriter;

struct RtLoopOptions {
  bool virtual_clock = false;
  std::string trace_path;  // empty: no trace
};

class RtLoop {
 public:
  RtLoop(const MachineConfig& config, SharedSegment& shm, const RtLoopOptions& options);
  ~RtLoop();

  /// Runs until `stop` becomes true. Returns the number of cycles run.
  std::uint64_t run(const std::atomic<bool>& stop);

  const CycleTiming& timing() const { return *timing_; }
  const Machine& machine() const { return *machine_; }

 private:
  void take_commands(std::uint64_t now_ns);
  void cycle(std::uint64_t now_ns);
  void publish_status();
  // Virtual clock: status is published every kVirtualPublishCycles cycles, whenever the state
  // changes, and before every wait, instead of every cycle (the host cannot tell the
  // difference: it reads status between its own blocks, microseconds apart).
  void publish_status_virtual(bool force);
  bool host_alive(std::uint64_t now_ns) const;

  const MachineConfig& config_;
  SharedSegment& shm_;
  RtLoopOptions options_;
  std::unique_ptr<Machine> machine_;
  std::unique_ptr<CycleTiming> timing_;
  std::unique_ptr<TraceWriter> trace_;  // set when options.trace_path is given
  std::uint64_t host_timeout_ns_;
  TimingStats timing_summary_{};
  int summary_period_;        // cycles between two refreshes of timing_summary_ (0.1 s of machine time)
  int summary_age_ = 0;
  int unpublished_cycles_ = 0;  // virtual clock: cycles run since status was last published
  MachineState published_state_ = MachineState::kIdle;
  std::uint8_t published_done_ = 0;
};

}  // namespace pcnc
