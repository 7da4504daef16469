// machine.cpp — Machine::Impl: one 2 kHz cycle = commands, block execution (or jog),
// soft-limit check, PID per axis, plant step, following-error check, status and trace.
//
// State machine (status.state):
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
// After a stop, fault or e-stop, blocks still arriving for the abandoned program are
// discarded until the next kProgramStart (or a block with seq 1).
#include "loop/machine.hpp"

#include <algorithm>
#include <cmath>

#include "motion/contour_error.hpp"
#include "motion/executor.hpp"
#include "motion/feed_override.hpp"
#include "motion/jog.hpp"
#include "drive/plant.hpp"
#include "ipc/block_check.hpp"
#include "loop/safety.hpp"
#include "drive/servo_pid.hpp"

namespace pcnc {

struct Machine::Impl {
  explicit Impl(const MachineConfig& c)
      : cfg(c),
        dt(c.cycle_period_s()),
        exec(c),
        jog(c),
        pid{AxisPid(c.axes[0], dt), AxisPid(c.axes[1], dt), AxisPid(c.axes[2], dt)},
        plant{make_plant(c, 0), make_plant(c, 1), make_plant(c, 2)} {
    cmd = exec.position();
    reset_servo();
    st.state = MachineState::kIdle;
    st.actual = encoder();
    st.commanded = cmd;
  }

  static AxisPlant make_plant(const MachineConfig& c, int i) {
    const int sub = static_cast<int>(std::lround(c.motion.subsample_steps));
    return AxisPlant(c.axes[i], c.cycle_period_s(), std::max(1, sub), c.axes[i].home_mm);
  }

  // The integrators start holding any gravity load, as a drive does when enabled.
  void reset_servo() {
    for (int i = 0; i < kAxes; ++i) {
      const AxisConfig& a = cfg.axes[i];
      pid[i].reset(a.gravity_load_n / a.force_constant_n_per_a);
    }
  }

  Vec3 encoder() const { return {plant[0].encoder(), plant[1].encoder(), plant[2].encoder()}; }

  void command(const Command& c);
  void cycle(MotionRing& ring);
  void run_program(MotionRing& ring);
  void run_jog();
  bool start_return_leg();
  void arrive_at_pause_point();
  void trip(FaultCode code, int axis, double value, std::uint32_t line, const char* reason, MotionRing* ring);
  void begin_stop(MachineState after);
  void program_start();
  double contour_error(const Vec3& measured) const;

  MachineConfig cfg;
  double dt;
  Executor exec;
  Jog jog;
  FeedOverride ovr;
  std::array<AxisPid, kAxes> pid;
  std::array<AxisPlant, kAxes> plant;

  Status st{};
  TraceSample ts{};
  bool amps_on = true;
  bool host_alive = true;
  bool hold = false;          // decelerate the program to rest (feed hold, stop, host lost)
  bool resume_pause = false;  // leave the M00/M01 block at the next cycle
  bool discard = false;       // drop blocks of an abandoned program
  bool flush_pending = false; // a fault/e-stop from a command: flush the ring next cycle
  MachineState after_stop = MachineState::kIdle;
  // Jogs while a program is paused: the machine stands at `stand`, away from the executor's
  // place on the path (`pause_point`), while `paused_jog`; `return_leg` is the next leg of
  // the way back on resume (0 Z up, 1 X, 2 Y, 3 Z down), `returning` while on it.
  bool paused_jog = false;
  bool returning = false;
  int return_leg = 0;
  Vec3 pause_point{}, stand{};
  const char* fault_reason = "";
  Vec3 cmd{}, cmd_vel{}, cmd_acc{};
};

void Machine::Impl::program_start() {
  st.program_active = 1;
  st.program_done = 0;
  st.program_time_s = 0.0;
  st.blocks_done = 0;
  st.underruns = 0;
  st.junction_stops = 0;
  st.junction_flows = 0;
  st.max_following_error = {0.0, 0.0, 0.0};
  st.following_error_sq_sum = {0.0, 0.0, 0.0};
  st.program_cycles = 0;
  st.contour_error = 0.0;
  st.max_contour_error = 0.0;
  st.contour_error_sq_sum = 0.0;
  exec.start_program();
  discard = false;
  hold = false;
  st.state = MachineState::kRunning;
}

// Distance from the measured position to the programmed path of the feed move in execution
// (lines and arcs; rapids and NURBS are not measured): the nearest point of the current
// block, or of the previous one while the axes, lagging the setpoint, may still be on it
// (not when a rapid follows: leaving a cut at rapid speed is not a contour error).
// −1 when there is no feed move to measure against.
double Machine::Impl::contour_error(const Vec3& measured) const {
  auto feed = [](const PreparedBlock* b) { return b && (b->kind == BlockKind::kLine || b->kind == BlockKind::kArc); };
  double e = -1.0;
  const PreparedBlock* cur = exec.current_motion();
  if (feed(cur)) e = distance_to_path(*cur, measured, exec.progress()).distance;
  const PreparedBlock* prev = exec.previous_motion();
  const double lag = cfg.axes[0].following_error_limit_mm;
  if (feed(prev) && (!cur || (feed(cur) && exec.progress() < lag))) {
    const double d = distance_to_path(*prev, measured, prev->length).distance;
    e = e < 0.0 ? d : std::min(e, d);
  }
  return e;
}

void Machine::Impl::begin_stop(MachineState after) {
  if (jog.active()) jog.stop();  // a paused program's jog or its way back: to rest, then flushed
  returning = false;
  hold = true;
  after_stop = after;
  st.state = MachineState::kStopping;
}

void Machine::Impl::trip(FaultCode code, int axis, double value, std::uint32_t line, const char* reason,
                         MotionRing* ring) {
  amps_on = false;
  if (ring) {
    exec.flush(ring[0]);
  } else {
    flush_pending = true;
  }
  jog.cancel();
  st.state = code == FaultCode::kNone ? MachineState::kEstop : MachineState::kFault;
  st.fault = code;
  st.fault_axis = static_cast<std::uint8_t>(axis);
  st.fault_value = value;
  st.fault_line = line;
  st.program_active = 0;
  fault_reason = reason;
  discard = true;
  hold = false;
  paused_jog = false;
  returning = false;
}

// The next one-axis move of the way back to the pause point (Z up first when Z must rise,
// then X, then Y, then Z down), at half the axis's maximum velocity. False when none is left.
bool Machine::Impl::start_return_leg() {
  static constexpr int kLegAxis[4] = {2, 0, 1, 2};
  for (; return_leg < 4; ++return_leg) {
    const int a = kLegAxis[return_leg];
    const double d = pause_point[a] - stand[a];
    if (d == 0.0) continue;
    if (return_leg == 0 && d < 0.0) continue;  // Z goes down last
    if (return_leg == 3 && d > 0.0) continue;
    const double feed = 0.5 * cfg.axes[a].max_velocity_mm_s;
    if (jog.start_increment(stand, a, d, feed)) {
      ++return_leg;
      return true;
    }
  }
  return false;
}

// Back on the pause point (exactly: the last leg's target may differ from it by rounding):
// the program continues as a plain resume does.
void Machine::Impl::arrive_at_pause_point() {
  stand = pause_point;
  cmd = pause_point;
  paused_jog = false;
  returning = false;
  hold = false;
  resume_pause = true;
}

void Machine::Impl::command(const Command& c) {
  st.last_command_id = c.id;
  const MachineState s = st.state;
  switch (c.kind) {
    case CommandKind::kNone:
      break;
    case CommandKind::kProgramStart:
      if (s == MachineState::kIdle) program_start();
      break;
    case CommandKind::kPause:
      if (s == MachineState::kRunning && returning) {
        returning = false;  // on the way back: stop the move; PAUSED again once at rest
        jog.stop();
        st.state = MachineState::kJogging;
      } else if (s == MachineState::kRunning) {
        hold = true;
        st.state = MachineState::kPaused;
      } else if (s == MachineState::kJogging) {
        jog.stop();
      }
      break;
    case CommandKind::kResume:
      if (s == MachineState::kPaused && host_alive) {
        st.state = MachineState::kRunning;
        if (paused_jog) {
          return_leg = 0;
          returning = start_return_leg();
          if (!returning) arrive_at_pause_point();
        } else {
          hold = false;
          resume_pause = true;
        }
      }
      break;
    case CommandKind::kStop:
      if (s == MachineState::kRunning || s == MachineState::kPaused) {
        begin_stop(MachineState::kIdle);
      } else if (s == MachineState::kJogging && paused_jog) {
        begin_stop(MachineState::kIdle);  // the jog comes to rest, then the program is flushed
      } else if (s == MachineState::kJogging) {
        jog.stop();
      } else if (s == MachineState::kIdle) {
        discard = true;  // nothing moving: drop whatever is queued
      }
      break;
    case CommandKind::kEstop:
      trip(FaultCode::kNone, 0, 0.0, exec.line(), "e-stop", nullptr);
      break;
    case CommandKind::kReset:
      if (s == MachineState::kFault || s == MachineState::kEstop || s == MachineState::kHostLost) {
        if (!amps_on) {
          // take up where the axes are (put onto the travel if they coasted a hair past it)
          Vec3 at = encoder();
          for (int i = 0; i < kAxes; ++i) at[i] = std::clamp(at[i], cfg.axes[i].travel_min_mm, cfg.axes[i].travel_max_mm);
          exec.set_position(at);
          reset_servo();
          amps_on = true;
        }
        cmd = exec.position();
        st.fault = FaultCode::kNone;
        st.fault_axis = 0;
        st.fault_value = 0.0;
        st.fault_line = 0;
        fault_reason = "";
        st.state = MachineState::kIdle;
      }
      break;
    case CommandKind::kFeedOverride:
      ovr.set(c.value);
      break;
    case CommandKind::kJogIncrement:
    case CommandKind::kJogContinuous:
      // In PAUSED only at rest: a feed hold still decelerating refuses the jog.
      if ((s == MachineState::kIdle && !st.program_active) || s == MachineState::kJogging ||
          (s == MachineState::kPaused && exec.speed() == 0.0)) {
        const Vec3 from = paused_jog ? stand : exec.position();
        const bool ok = c.kind == CommandKind::kJogIncrement ? jog.start_increment(from, c.axis, c.value, c.feed)
                                                             : jog.start_continuous(from, c.axis, c.value, c.feed);
        if (ok) {
          if (s == MachineState::kPaused && !paused_jog) {
            paused_jog = true;
            pause_point = exec.position();
            stand = pause_point;
          }
          st.state = MachineState::kJogging;
        }
      }
      break;
    case CommandKind::kJogStop:
      if (s == MachineState::kJogging) jog.stop();
      break;
    case CommandKind::kJogKeepAlive:
      jog.keep_alive();
      break;
  }
  st.feed_override = ovr.value();
}

void Machine::Impl::run_jog() {
  jog.step();
  cmd = jog.position();
  cmd_vel = jog.velocity();
  cmd_acc = jog.acceleration();
  st.path_speed = jog.speed();
  if (jog.active()) return;
  if (!paused_jog) {
    exec.set_position(cmd);
    st.state = MachineState::kIdle;
    return;
  }
  // A paused program's jog at rest: the executor keeps its place; the machine stands here.
  stand = cmd;
  if (returning) {
    if (!start_return_leg()) arrive_at_pause_point();
  } else if (st.state == MachineState::kJogging) {
    st.state = MachineState::kPaused;
  }
  // STOPPING: the next cycle flushes the program (run_program)
}

void Machine::Impl::run_program(MotionRing& ring) {
  ExecInput in;
  in.hold = hold;
  in.feed_override = ovr.value();
  in.resume_pause = resume_pause;
  resume_pause = false;
  ExecResult r;
  exec.step(ring, in, r);
  if (r.fault != FaultCode::kNone) {
    trip(r.fault, r.fault_axis, r.fault_value, r.fault_line, r.reason, &ring);
    return;
  }
  st.blocks_done += static_cast<std::uint64_t>(r.blocks_done);
  st.junction_stops += static_cast<std::uint64_t>(r.junction_stops);
  st.junction_flows += static_cast<std::uint64_t>(r.junction_flows);
  cmd = exec.position();
  cmd_vel = exec.velocity();
  cmd_acc = exec.acceleration();
  st.path_speed = exec.speed();
  if (paused_jog) {  // held at rest away from the path: the machine stays where it stands
    cmd = stand;
    cmd_vel = {0.0, 0.0, 0.0};
    cmd_acc = {0.0, 0.0, 0.0};
    st.path_speed = 0.0;
  }
  if (r.starved && st.state == MachineState::kRunning) {
    // An underrun is the ring running dry in the middle of a program; before its first
    // block has arrived (the host was descheduled between the start command and the first
    // block) nothing has moved yet, and nothing was waiting on the path.
    if (st.program_active && st.blocks_done > 0) {
      ++st.underruns;
    } else {
      st.state = MachineState::kIdle;  // blocks without a program start ran out
    }
  }
  if (r.at_pause && st.state == MachineState::kRunning) st.state = MachineState::kPaused;
  if (r.program_end) {
    st.program_done = 1;
    st.program_active = 0;
    hold = false;
    exec.start_program();
    if (st.state == MachineState::kRunning || st.state == MachineState::kPaused) st.state = MachineState::kIdle;
  }
  if (st.state == MachineState::kStopping && exec.speed() == 0.0) {
    exec.flush(ring);
    if (paused_jog) exec.set_position(stand);  // take up where the machine stands
    paused_jog = false;
    st.state = after_stop;
    st.program_active = 0;
    discard = true;
    hold = false;
  }
}

void Machine::Impl::cycle(MotionRing& ring) {
  ++st.cycle;
  st.time_s = static_cast<double>(st.cycle) * dt;
  if (st.program_active) st.program_time_s += dt;
  if (flush_pending) {
    exec.flush(ring);
    flush_pending = false;
  }

  if (!host_alive) {
    if (st.state == MachineState::kRunning || st.state == MachineState::kPaused) begin_stop(MachineState::kHostLost);
    if (st.state == MachineState::kJogging) jog.stop();
  }
  if (discard && !ring.empty()) {
    if (ring.peek(0).seq == 1 && st.state == MachineState::kIdle) {
      discard = false;  // a new program began without kProgramStart
      exec.start_program();
    } else {
      exec.flush(ring);
    }
  }
  if (st.state == MachineState::kIdle && !ring.empty() && !discard) {
    if (st.program_active == 0) program_start();
    st.state = MachineState::kRunning;
  }

  cmd_vel = {0.0, 0.0, 0.0};
  cmd_acc = {0.0, 0.0, 0.0};
  switch (st.state) {
    case MachineState::kRunning:
    case MachineState::kPaused:
    case MachineState::kStopping:
      if (jog.active()) {
        run_jog();  // the way back to the pause point, or a paused jog coming to rest on a stop
      } else {
        run_program(ring);
      }
      break;
    case MachineState::kJogging:
      run_jog();
      break;
    default:
      st.path_speed = 0.0;
      break;
  }

  // Servo, plant, safety.
  const Vec3 meas = encoder();
  if (amps_on) {
    // Blocks may touch the travel's ends within block_tolerance_mm (rounding, accepted by
    // check_block): such setpoints are put onto the limit. Anything further out trips.
    const double tol = cfg.motion.block_tolerance_mm;
    for (int i = 0; i < kAxes; ++i) {
      const AxisConfig& a = cfg.axes[i];
      if (cmd[i] < a.travel_min_mm && cmd[i] >= a.travel_min_mm - tol) cmd[i] = a.travel_min_mm;
      if (cmd[i] > a.travel_max_mm && cmd[i] <= a.travel_max_mm + tol) cmd[i] = a.travel_max_mm;
    }
    const int ax = outside_travel(cmd, cfg, 0.0);
    if (ax >= 0) {
      trip(FaultCode::kSoftLimit, ax, cmd[ax], exec.line(), "setpoint outside the travel", &ring);
      cmd = st.commanded;  // never command it
    }
  }
  if (!amps_on) cmd = meas;  // amplifiers off: the setpoint follows the axes
  Vec3 ferr = cmd - meas;
  for (int i = 0; i < kAxes; ++i) {
    const double u = amps_on ? pid[i].update(cmd[i], meas[i], cmd_vel[i], cmd_acc[i]) : 0.0;
    plant[i].step(u, amps_on);
  }
  if (amps_on) {
    const int ax = following_error_axis(ferr, cfg);
    if (ax >= 0) trip(FaultCode::kFollowingError, ax, ferr[ax], exec.line(), "following error over the limit", &ring);
  }

  st.commanded = cmd;
  st.actual = meas;
  st.velocity = cmd_vel;
  st.following_error = ferr;
  for (int i = 0; i < kAxes; ++i) {
    st.max_following_error[i] = std::max(st.max_following_error[i], std::abs(ferr[i]));
  }
  st.contour_error = 0.0;
  if (st.program_active && amps_on) {
    ++st.program_cycles;
    for (int i = 0; i < kAxes; ++i) st.following_error_sq_sum[i] += ferr[i] * ferr[i];
    const double ce = paused_jog ? -1.0 : contour_error(meas);  // off the path on purpose
    if (ce >= 0.0) {
      st.contour_error = ce;
      st.max_contour_error = std::max(st.max_contour_error, ce);
      st.contour_error_sq_sum += ce * ce;
    }
  }
  st.line = exec.line();
  st.block_seq = exec.seq();
  st.contouring = exec.contouring() ? 1 : 0;
  st.ring_fill = static_cast<std::uint8_t>(ring.size());
  st.feed_override = ovr.value();

  ts.t = st.time_s;
  ts.line = st.line;
  ts.state = st.state;
  ts.commanded = cmd;
  ts.actual = meas;
  ts.following_error = ferr;
  ts.speed = st.path_speed;
}

Machine::Machine(const MachineConfig& config) : impl_(std::make_unique<Impl>(config)) {}
Machine::~Machine() = default;

void Machine::command(const Command& cmd) { impl_->command(cmd); }
void Machine::set_host_alive(bool alive) { impl_->host_alive = alive; }
void Machine::cycle(MotionRing& ring) { impl_->cycle(ring); }

bool Machine::wants_more_blocks(const MotionRing& ring) const {
  const Status& s = impl_->st;
  if (!s.program_active || impl_->discard) return false;
  if (s.state != MachineState::kRunning && s.state != MachineState::kPaused) return false;
  const std::size_t n = ring.size();
  if (n >= kRingSlots) return false;
  for (std::size_t i = 0; i < n; ++i) {
    if (ring.peek(i).kind == BlockKind::kEnd) return false;
  }
  return true;
}

bool Machine::paused_at_rest() const {
  const Impl& m = *impl_;
  return m.st.state == MachineState::kPaused && !m.jog.active() && m.exec.speed() == 0.0 &&
         m.cmd_vel[0] == 0.0 && m.cmd_vel[1] == 0.0 && m.cmd_vel[2] == 0.0;
}

const Status& Machine::status() const { return impl_->st; }
const TraceSample& Machine::trace_sample() const { return impl_->ts; }
const char* Machine::fault_reason() const { return impl_->fault_reason; }
void Machine::set_axis_blocked(int axis, bool blocked) {
  if (axis >= 0 && axis < kAxes) impl_->plant[static_cast<std::size_t>(axis)].set_blocked(blocked);
}
Vec3 Machine::true_position() const {
  return {impl_->plant[0].position(), impl_->plant[1].position(), impl_->plant[2].position()};
}

}  // namespace pcnc
