// machine.hpp — the machine as one object the 2 kHz loop steps: command handling, block
// execution with contouring, servo, simulated plant and safety, in that order each cycle.
//
// The loop (rt_loop.cpp) owns time and the shared segment; Machine owns everything that
// happens inside one cycle and is pure computation: no system calls, no allocation after
// construction, no locks, no I/O. That keeps it testable without processes and deterministic
// under --clock virtual. Inside (machine_impl.hpp): the cycle in order (cycle.cpp), the
// states and their transitions (state_machine.hpp), motion (rt/motion: executor, jog, feed
// override) and the drive (rt/drive: servo and plant).
#pragma once

#include <cstdint>
#include <memory>

#include "ipc/block.hpp"
#include "ipc/command.hpp"
#include "config/config.hpp"
#include "ipc/segment.hpp"
#include "ipc/status.hpp"
#include "ipc/trace_format.hpp"

namespace pcnc {


class Machine {
 public:
  explicit Machine(const MachineConfig& config);
  ~Machine();
  Machine(const Machine&) = delete;
  Machine& operator=(const Machine&) = delete;

  /// Takes one mailbox command; called before cycle() for each pending command.
  void command(const Command& cmd);

  /// Tells the machine whether the host is alive (heartbeat fresh). When it turns false
  /// while a program runs, the machine stops along the path and enters HOST_LOST.
  void set_host_alive(bool alive);

  /// One servo period: takes/peeks blocks from `ring` (pops the ones it finished),
  /// interpolates, runs the servo and plant, checks safety, updates status().
  void cycle(MotionRing& ring);

  /// Under --clock virtual the loop does not advance time while this is true: a program is
  /// active and the ring holds fewer blocks than the look-ahead wants (not full, no End block
  /// queued, the last block not a probing move, after which the host sends nothing until it
  /// has read the result). Under the real clock such cycles run anyway and count as underruns when
  /// the executor actually had nothing to do.
  bool wants_more_blocks(const MotionRing& ring) const;

  /// A paused program standing still (feed hold come to rest, or an M00/M01 reached), no
  /// jog: nothing moves until a command comes. Under --clock virtual the loop then sleeps
  /// like an idle machine instead of racing machine time ahead.
  bool paused_at_rest() const;

  /// Before the first cycle: the axes stand at rest at `at` (machine coordinates, mm, put onto
  /// the travel), the setpoint and the executor's position with them, IDLE. A restarted rt
  /// takes up where its predecessor last measured the axes, as absolute encoders would tell
  /// a drive after a power loss. False (nothing changed) when `at` is not finite.
  bool take_up_position(const Vec3& at);
  /// The same for the rotary joints (rad; a joint with a travel is put onto it).
  bool take_up_rotary(const Rot3& at);

  /// The trace could not be written (the loop's trace writer failed). Published in the status
  /// (trace_failed); with `stop` (process.on_trace_failure = "stop") a running program stops
  /// along the path as on a stop, and no program starts afterwards.
  void trace_failed(bool stop);

  /// pcnc-rt is asked to exit: what moves comes to rest as on a stop (a program decelerates
  /// along the path and is abandoned, a jog decelerates), and nothing starts moving again.
  void begin_shutdown();
  /// No program or jog in motion and the setpoint standing still (the axes may still settle).
  bool motion_at_rest() const;

  const Status& status() const;
  const TraceSample& trace_sample() const;
  /// The rotary joints of the same cycle (the trace file's extra columns).
  const TraceJoints& trace_joints() const;

  /// Why the machine faulted, in words (static text; "" when not faulted). Status carries
  /// the code, axis, value and line; this names the defect, e.g. which block check failed.
  const char* fault_reason() const;

  /// Fault injection for tests and demonstrations: the plant's axis stops moving (a crash or
  /// a jammed guide). The following-error check then trips.
  void set_axis_blocked(int axis, bool blocked);

  /// The simulated axes' true positions (not quantised by the encoders), mm.
  Vec3 true_position() const;
  /// The last cycle's setpoint was inside a corner blend's window (rt/motion/executor.hpp).
  bool blending() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace pcnc
