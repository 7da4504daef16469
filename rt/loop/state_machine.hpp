// state_machine.hpp — the machine's states (Status::state) and the transitions between them:
// by mailbox command, by the host's heartbeat, and by what the executor and the jog report
// each cycle. It decides which part moves the axes in a cycle (the program's executor, a
// jog, or nothing) and owns the flags behind the states (feed hold, abandoned program,
// amplifiers, a paused program's jog and its way back).
//
//   IDLE ──kProgramStart / a block arrives──► RUNNING ──End block──► IDLE (program_done)
//   RUNNING ──kPause──► PAUSED (decelerating, then at rest) ──kResume──► RUNNING
//   RUNNING ──M00/M01 block──► PAUSED (at the block end) ──kResume──► RUNNING
//   RUNNING/PAUSED ──kStop──► STOPPING (decelerate on the path) ──at rest──► IDLE, ring flushed
//   RUNNING/PAUSED ──host heartbeat lost──► STOPPING ──at rest──► HOST_LOST (holding)
//   IDLE ──jog──► JOGGING ──at rest──► IDLE
//   PAUSED (at rest) ──jog──► JOGGING ──at rest──► PAUSED (the pause point is remembered; the
//     executor keeps its place in the block). kResume away from the pause point: RUNNING,
//     back to it with one-axis moves (Z up, X, Y, Z down), then the program resumes. kStop
//     after such a jog: the program is flushed and IDLE starts where the machine stands.
//   any ──following error / soft limit / bad block──► FAULT (amplifiers off, ring flushed)
//   any ──kEstop──► ESTOP (amplifiers off);  FAULT/ESTOP/HOST_LOST ──kReset──► IDLE
//   refuse_programs() (the trace failed, rule "stop"): RUNNING/PAUSED ──► STOPPING ──at rest──►
//     IDLE; from then on no program starts or resumes (jogs still do)
//   shut_down() (pcnc-rt asked to exit): the same, and a jog comes to rest; no jog starts either
// After a stop, fault or e-stop, blocks still arriving for the abandoned program are
// discarded until the next kProgramStart (or a block with seq 1).
//
// Like everything the cycle calls: no allocation, no locks, no I/O. It works on parts the
// machine owns (machine_impl.hpp) and never owns them.
#pragma once

#include <cstdint>

#include "config/config.hpp"
#include "drive/drive.hpp"
#include "ipc/command.hpp"
#include "ipc/segment.hpp"
#include "ipc/status.hpp"
#include "motion/executor.hpp"
#include "motion/feed_override.hpp"
#include "motion/jog.hpp"
#include "motion/setpoint.hpp"

namespace pcnc {

class StateMachine {
 public:
  /// Works on the machine's parts: its status (state, fault and program counters), the
  /// setpoint of the cycle, the executor, the jog, the feed override and the drive (only
  /// for a reset: take up where the axes are).
  StateMachine(const MachineConfig& config, Status& status, Setpoint& setpoint, Executor& exec, Jog& jog,
               FeedOverride& ovr, Drive& drive);

  /// Transitions by command: one mailbox command, before the cycle.
  void command(const Command& c);
  /// The host's heartbeat: while it is stale a running program stops along the path.
  void set_host_alive(bool alive) { host_alive_ = alive; }

  /// Cycle step 2: a flush left by a command, the host's loss, blocks of an abandoned program
  /// dropped, a block arriving while IDLE starts a program.
  void begin_cycle(MotionRing& ring);
  /// Cycle step 3: this cycle's setpoint from the program's executor or the jog, as the
  /// state says, and the transitions their results cause (program end, M00, stop complete,
  /// jog at rest, the next leg of the way back to a pause point).
  void move(MotionRing& ring);
  /// Any fault (code kNone: e-stop): amplifiers off, the program abandoned. With `ring` the
  /// ring is flushed at once, without (from a command) at the start of the next cycle.
  void trip(FaultCode code, int axis, double value, std::uint32_t line, const char* reason, MotionRing* ring);
  /// pcnc-rt is asked to exit (SIGTERM): whatever moves comes to rest the way a stop does
  /// (a program decelerates along the path and is abandoned, a jog decelerates), and nothing
  /// starts moving again: program starts, resumes, jogs and newly queued blocks are refused.
  void shut_down();
  /// A running program stops along the path as on a stop (and a paused one's jog comes to
  /// rest first); from then on no program starts or resumes and queued blocks are dropped.
  void refuse_programs();
  /// Nothing is commanded to move: no program or jog in motion, the setpoint at rest.
  bool motion_at_rest() const;

  bool amps_on() const { return amps_on_; }
  /// A paused program's jog: the machine stands away from the path on purpose.
  bool off_path() const { return paused_jog_; }
  /// Blocks in the ring belong to an abandoned program.
  bool discarding() const { return discard_; }
  const char* fault_reason() const { return fault_reason_; }

 private:
  void program_start();
  void begin_stop(MachineState after);
  void run_program(MotionRing& ring);
  void run_jog();
  bool start_return_leg();
  void arrive_at_pause_point();

  const MachineConfig& cfg_;
  Status& st_;
  Setpoint& sp_;
  Executor& exec_;
  Jog& jog_;
  FeedOverride& ovr_;
  Drive& drive_;

  bool amps_on_ = true;
  bool host_alive_ = true;
  bool hold_ = false;          // decelerate the program to rest (feed hold, stop, host lost)
  bool resume_pause_ = false;  // leave the M00/M01 block at the next cycle
  bool discard_ = false;       // drop blocks of an abandoned program
  bool flush_pending_ = false; // a fault/e-stop from a command: flush the ring next cycle
  bool no_programs_ = false;   // refuse_programs(), shut_down(): no program starts or resumes
  bool no_jogs_ = false;       // shut_down(): no jog starts
  MachineState after_stop_ = MachineState::kIdle;
  // Jogs while a program is paused: the machine stands at `stand_`, away from the executor's
  // place on the path (`pause_point_`), while `paused_jog_`; `return_leg_` is the next leg of
  // the way back on resume (0 Z up, 1 X, 2 Y, 3 Z down), `returning_` while on it.
  bool paused_jog_ = false;
  bool returning_ = false;
  int return_leg_ = 0;
  Vec3 pause_point_{}, stand_{};
  const char* fault_reason_ = "";
};

}  // namespace pcnc
