// rt_loop.hpp — pcnc-rt's timer loop: every period it drains the mailbox, steps the Machine
// once, wakes the host when a ring slot was freed, publishes status and a trace sample.
// Under the real clock it sleeps to absolute deadlines with clock_nanosleep; under the
// virtual clock it runs the same cycle back to back, waiting only for the host's blocks.
// Asked to stop (StopRequest: SIGTERM/SIGINT), it brings the machine to rest first: the
// machine stops what moves as a stop command does, and the loop keeps cycling until the
// setpoint and the axes stand still (bounded by RtLoopOptions::shutdown_timeout_s).
#pragma once

#include <atomic>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "config/config.hpp"
#include "loop/cycle_timing.hpp"
#include "loop/machine.hpp"
#include "loop/stop_request.hpp"
#include "ipc/segment.hpp"

namespace pcnc {

class TraceWriter;

struct RtLoopOptions {
  bool virtual_clock = false;
  std::string trace_path;  // empty: no trace
  std::string trace_digest_path;  // the compact trace for the report (ipc/trace_compact.hpp); empty: none
  double shutdown_timeout_s = 5.0;  // a stop request ends the loop after this long even if not at rest
  // Where the axes stand at start (a restarted rt: where its predecessor last measured them).
  std::optional<Vec3> start_position;
  std::optional<Rot3> start_rotary;  // the rotary joints, rad (a restarted rt: where they were measured)
  // Called once, from the trace writer's thread, when the trace cannot be written.
  std::function<void(const std::string&)> on_trace_failure;
};

/// How the loop ended after a stop request (nothing set when it never got one).
struct ShutdownReport {
  bool requested = false;
  bool was_moving = false;   // program or jog in motion, or axes not yet still, at the request
  bool at_rest = false;      // ended because the machine came to rest (the clean way)
  bool timed_out = false;    // ended after shutdown_timeout_s, not at rest
  bool immediate = false;    // ended by a second signal
  int signal = 0;            // the first signal's number
  int second_signal = 0;
  MachineState state_at_request = MachineState::kIdle;
  double speed_at_request = 0.0;   // commanded path speed, mm/s
  double motion_rest_s = 0.0;      // request -> setpoint at rest, machine time
  double settled_s = 0.0;          // request -> axes still too (the loop's end), machine time
  double wall_s = 0.0;             // request -> the loop's end, wall time
  MachineState final_state = MachineState::kIdle;
  double final_speed = 0.0;
};

class RtLoop {
 public:
  RtLoop(const MachineConfig& config, SharedSegment& shm, const RtLoopOptions& options);
  ~RtLoop();

  /// Runs until a stop request has brought the machine to rest (or timed out, or a second
  /// request came). Returns the number of cycles run.
  std::uint64_t run(const StopRequest& stop);

  const CycleTiming& timing() const { return *timing_; }
  const ShutdownReport& shutdown() const { return shutdown_; }

  /// Drains and closes the trace (when there is one). Returns what failed ("" when the trace
  /// is complete, or there is none).
  std::string close_trace();
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
  // Reads the stop request (one atomic load when there is none); on the first look at one,
  // tells the machine to stop; then follows it to rest. True when the loop must end now.
  bool stop_now(const StopRequest& stop);

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
  bool trace_failed_ = false;  // the machine was told
  // stop request: when it came, the cycle last looked at, the axes then, cycles standing still
  ShutdownReport shutdown_{};
  std::uint64_t stop_begin_ns_ = 0, stop_begin_cycle_ = 0, stop_seen_cycle_ = 0, rest_cycle_ = 0;
  Vec3 stop_last_actual_{};
  int still_cycles_ = 0;
  int settle_cycles_;  // cycles the axes must stand still (10 ms)
};

}  // namespace pcnc
