// state_machine.cpp — the transitions (diagram in state_machine.hpp): by command, at the start
// of a cycle, and from the results of the executor's or the jog's step.
#include "loop/state_machine.hpp"

#include <algorithm>

namespace pcnc {

StateMachine::StateMachine(const MachineConfig& config, Status& status, Setpoint& setpoint, Executor& exec, Jog& jog,
                           FeedOverride& ovr, Drive& drive)
    : cfg_(config), st_(status), sp_(setpoint), exec_(exec), jog_(jog), ovr_(ovr), drive_(drive) {
  st_.state = MachineState::kIdle;
}

void StateMachine::program_start() {
  st_.program_active = 1;
  st_.program_done = 0;
  st_.program_time_s = 0.0;
  st_.blocks_done = 0;
  st_.underruns = 0;
  st_.junction_stops = 0;
  st_.junction_flows = 0;
  st_.max_following_error = {0.0, 0.0, 0.0};
  st_.rot_max_following_error = {0.0, 0.0, 0.0};
  st_.following_error_sq_sum = {0.0, 0.0, 0.0};
  st_.program_cycles = 0;
  st_.contour_error = 0.0;
  st_.max_contour_error = 0.0;
  st_.contour_error_sq_sum = 0.0;
  exec_.start_program();
  discard_ = false;
  hold_ = false;
  st_.state = MachineState::kRunning;
}

void StateMachine::begin_stop(MachineState after) {
  if (jog_.active()) jog_.stop();  // a paused program's jog or its way back: to rest, then flushed
  returning_ = false;
  hold_ = true;
  after_stop_ = after;
  st_.state = MachineState::kStopping;
}

void StateMachine::trip(FaultCode code, int axis, double value, std::uint32_t line, const char* reason,
                        MotionRing* ring) {
  amps_on_ = false;
  if (ring) {
    exec_.flush(*ring);
  } else {
    flush_pending_ = true;
  }
  jog_.cancel();
  st_.state = code == FaultCode::kNone ? MachineState::kEstop : MachineState::kFault;
  st_.fault = code;
  st_.fault_axis = static_cast<std::uint8_t>(axis);
  st_.fault_value = value;
  st_.fault_line = line;
  st_.program_active = 0;
  fault_reason_ = reason;
  discard_ = true;
  hold_ = false;
  paused_jog_ = false;
  returning_ = false;
}

void StateMachine::shut_down() {
  no_jogs_ = true;
  if (st_.state == MachineState::kJogging && !paused_jog_) jog_.stop();
  refuse_programs();
}

void StateMachine::refuse_programs() {
  no_programs_ = true;
  switch (st_.state) {
    case MachineState::kRunning:
    case MachineState::kPaused:
      begin_stop(MachineState::kIdle);
      break;
    case MachineState::kJogging:
      if (paused_jog_) begin_stop(MachineState::kIdle);  // the jog comes to rest, then the program is flushed
      break;
    case MachineState::kStopping:
      break;  // already on its way to rest
    default:
      discard_ = true;  // drop whatever is queued
      break;
  }
}

bool StateMachine::motion_at_rest() const {
  switch (st_.state) {
    case MachineState::kRunning:
    case MachineState::kStopping:
    case MachineState::kJogging:
      return false;
    case MachineState::kPaused:
      if (jog_.active() || exec_.speed() != 0.0) return false;
      break;
    default:
      break;
  }
  return st_.path_speed == 0.0 && sp_.vel[0] == 0.0 && sp_.vel[1] == 0.0 && sp_.vel[2] == 0.0;
}

// The next one-axis move of the way back to the pause point (Z up first when Z must rise,
// then X, then Y, then Z down), at half the axis's maximum velocity. False when none is left.
bool StateMachine::start_return_leg() {
  static constexpr int kLegAxis[4] = {2, 0, 1, 2};
  for (; return_leg_ < 4; ++return_leg_) {
    const int a = kLegAxis[return_leg_];
    const double d = pause_point_[a] - stand_[a];
    if (d == 0.0) continue;
    if (return_leg_ == 0 && d < 0.0) continue;  // Z goes down last
    if (return_leg_ == 3 && d > 0.0) continue;
    const double feed = 0.5 * cfg_.axes[a].max_velocity_mm_s;
    if (jog_.start_increment(stand_, a, d, feed)) {
      ++return_leg_;
      return true;
    }
  }
  return false;
}

// Back on the pause point (exactly: the last leg's target may differ from it by rounding):
// the program continues as a plain resume does.
void StateMachine::arrive_at_pause_point() {
  stand_ = pause_point_;
  sp_.pos = pause_point_;
  paused_jog_ = false;
  returning_ = false;
  hold_ = false;
  resume_pause_ = true;
}

void StateMachine::command(const Command& c) {
  st_.last_command_id = c.id;
  const MachineState s = st_.state;
  switch (c.kind) {
    case CommandKind::kNone:
      break;
    case CommandKind::kProgramStart:
      if (s == MachineState::kIdle && !no_programs_) program_start();
      break;
    case CommandKind::kPause:
      if (s == MachineState::kRunning && returning_) {
        returning_ = false;  // on the way back: stop the move; PAUSED again once at rest
        jog_.stop();
        st_.state = MachineState::kJogging;
      } else if (s == MachineState::kRunning) {
        hold_ = true;
        st_.state = MachineState::kPaused;
      } else if (s == MachineState::kJogging) {
        jog_.stop();
      }
      break;
    case CommandKind::kResume:
      if (s == MachineState::kPaused && host_alive_ && !no_programs_) {
        st_.state = MachineState::kRunning;
        if (paused_jog_) {
          return_leg_ = 0;
          returning_ = start_return_leg();
          if (!returning_) arrive_at_pause_point();
        } else {
          hold_ = false;
          resume_pause_ = true;
        }
      }
      break;
    case CommandKind::kStop:
      if (s == MachineState::kRunning || s == MachineState::kPaused) {
        begin_stop(MachineState::kIdle);
      } else if (s == MachineState::kJogging && paused_jog_) {
        begin_stop(MachineState::kIdle);  // the jog comes to rest, then the program is flushed
      } else if (s == MachineState::kJogging) {
        jog_.stop();
      } else if (s == MachineState::kIdle) {
        discard_ = true;  // nothing moving: drop whatever is queued
      }
      break;
    case CommandKind::kEstop:
      trip(FaultCode::kNone, 0, 0.0, exec_.line(), "e-stop", nullptr);
      break;
    case CommandKind::kReset:
      if (s == MachineState::kFault || s == MachineState::kEstop || s == MachineState::kHostLost) {
        if (!amps_on_) {
          // take up where the axes are (put onto the travel if they coasted a hair past it)
          Vec3 at = drive_.encoder();
          for (int i = 0; i < kAxes; ++i) at[i] = std::clamp(at[i], cfg_.axes[i].travel_min_mm, cfg_.axes[i].travel_max_mm);
          Rot3 rot = drive_.rotary_encoder();
          for (int i = 0; i < kRotaryJoints; ++i) {
            const auto& j = cfg_.rotary[static_cast<std::size_t>(i)];
            if (j && !j->continuous) rot[static_cast<std::size_t>(i)] = std::clamp(rot[static_cast<std::size_t>(i)], j->travel_min_rad, j->travel_max_rad);
          }
          exec_.set_rotary(rot);
          exec_.set_position(at);
          drive_.reset_servo();
          amps_on_ = true;
        }
        sp_.pos = exec_.position();
        sp_.rot = exec_.rotary();
        st_.fault = FaultCode::kNone;
        st_.fault_axis = 0;
        st_.fault_value = 0.0;
        st_.fault_line = 0;
        fault_reason_ = "";
        st_.state = MachineState::kIdle;
      }
      break;
    case CommandKind::kFeedOverride:
      ovr_.set(c.value);
      break;
    case CommandKind::kJogIncrement:
    case CommandKind::kJogContinuous:
      // In PAUSED only at rest: a feed hold still decelerating refuses the jog.
      if (no_jogs_) break;
      if ((s == MachineState::kIdle && !st_.program_active) || s == MachineState::kJogging ||
          (s == MachineState::kPaused && exec_.speed() == 0.0)) {
        const Vec3 from = paused_jog_ ? stand_ : exec_.position();
        // a rotary joint (axis 3..5) jogs only from IDLE: a paused program's jog returns along X Y Z
        if (c.axis >= kAxes && s != MachineState::kIdle && !(s == MachineState::kJogging && !paused_jog_)) break;
        jog_.set_rotary(exec_.rotary());
        const bool ok = c.kind == CommandKind::kJogIncrement ? jog_.start_increment(from, c.axis, c.value, c.feed)
                                                             : jog_.start_continuous(from, c.axis, c.value, c.feed);
        if (ok) {
          if (s == MachineState::kPaused && !paused_jog_) {
            paused_jog_ = true;
            pause_point_ = exec_.position();
            stand_ = pause_point_;
          }
          st_.state = MachineState::kJogging;
        }
      }
      break;
    case CommandKind::kJogStop:
      if (s == MachineState::kJogging) jog_.stop();
      break;
    case CommandKind::kJogKeepAlive:
      jog_.keep_alive();
      break;
  }
  st_.feed_override = ovr_.value();
}

void StateMachine::begin_cycle(MotionRing& ring) {
  if (flush_pending_) {
    exec_.flush(ring);
    flush_pending_ = false;
  }
  if (!host_alive_) {
    if (st_.state == MachineState::kRunning || st_.state == MachineState::kPaused) begin_stop(MachineState::kHostLost);
    if (st_.state == MachineState::kJogging) jog_.stop();
  }
  if (discard_ && !ring.empty()) {
    if (ring.peek(0).seq == 1 && st_.state == MachineState::kIdle && !no_programs_) {
      discard_ = false;  // a new program began without kProgramStart
      exec_.start_program();
    } else {
      exec_.flush(ring);
    }
  }
  if (st_.state == MachineState::kIdle && !ring.empty() && !discard_ && !no_programs_) {
    if (st_.program_active == 0) program_start();
    st_.state = MachineState::kRunning;
  }
}

void StateMachine::move(MotionRing& ring) {
  sp_.vel = {0.0, 0.0, 0.0};
  sp_.acc = {0.0, 0.0, 0.0};
  sp_.rot_vel = {0.0, 0.0, 0.0};
  sp_.rot_acc = {0.0, 0.0, 0.0};
  switch (st_.state) {
    case MachineState::kRunning:
    case MachineState::kPaused:
    case MachineState::kStopping:
      if (jog_.active()) {
        run_jog();  // the way back to the pause point, or a paused jog coming to rest on a stop
      } else {
        run_program(ring);
      }
      break;
    case MachineState::kJogging:
      run_jog();
      break;
    default:
      st_.path_speed = 0.0;
      break;
  }
}

void StateMachine::run_jog() {
  jog_.step();
  sp_.pos = jog_.position();
  sp_.vel = jog_.velocity();
  sp_.acc = jog_.acceleration();
  sp_.rot = jog_.rotary();
  sp_.rot_vel = jog_.rotary_velocity();
  sp_.rot_acc = jog_.rotary_acceleration();
  st_.path_speed = jog_.speed();
  if (jog_.active()) return;
  if (!paused_jog_) {
    exec_.set_rotary(sp_.rot);
    exec_.set_position(sp_.pos);
    st_.state = MachineState::kIdle;
    return;
  }
  // A paused program's jog at rest: the executor keeps its place; the machine stands here.
  stand_ = sp_.pos;
  if (returning_) {
    if (!start_return_leg()) arrive_at_pause_point();
  } else if (st_.state == MachineState::kJogging) {
    st_.state = MachineState::kPaused;
  }
  // STOPPING: the next cycle flushes the program (run_program)
}

void StateMachine::run_program(MotionRing& ring) {
  ExecInput in;
  in.hold = hold_;
  in.feed_override = ovr_.value();
  in.resume_pause = resume_pause_;
  in.probe_input = st_.probe_input != 0;
  resume_pause_ = false;
  ExecResult r;
  exec_.step(ring, in, r);
  if (r.probe_done) {  // the result of a probing block (docs/probe.md)
    st_.probe_outcome = r.probe_outcome;
    st_.probe_latched = r.probe_latched;
    st_.probe_stop = exec_.position();
    st_.probe_line = r.probe_line;
    st_.probe_seq = r.probe_seq;
    ++st_.probe_count;
  }
  if (r.fault != FaultCode::kNone) {
    trip(r.fault, r.fault_axis, r.fault_value, r.fault_line, r.reason, &ring);
    return;
  }
  st_.blocks_done += static_cast<std::uint64_t>(r.blocks_done);
  st_.junction_stops += static_cast<std::uint64_t>(r.junction_stops);
  st_.junction_flows += static_cast<std::uint64_t>(r.junction_flows);
  sp_.pos = exec_.position();
  sp_.vel = exec_.velocity();
  sp_.acc = exec_.acceleration();
  sp_.rot = exec_.rotary();
  sp_.rot_vel = exec_.rotary_velocity();
  sp_.rot_acc = exec_.rotary_acceleration();
  st_.path_speed = exec_.speed();
  if (paused_jog_) {  // held at rest away from the path: the machine stays where it stands
    sp_.pos = stand_;
    sp_.vel = {0.0, 0.0, 0.0};
    sp_.acc = {0.0, 0.0, 0.0};
    st_.path_speed = 0.0;
  }
  if (r.starved && st_.state == MachineState::kRunning) {
    // An underrun is the ring running dry in the middle of a program; before its first
    // block has arrived (the host was descheduled between the start command and the first
    // block) nothing has moved yet, and nothing was waiting on the path.
    if (st_.program_active && st_.blocks_done > 0) {
      if (!r.probe_wait) ++st_.underruns;  // after a probing move the host waits for its result
    } else {
      st_.state = MachineState::kIdle;  // blocks without a program start ran out
    }
  }
  if (r.at_pause && st_.state == MachineState::kRunning) st_.state = MachineState::kPaused;
  if (r.program_end) {
    st_.program_done = 1;
    st_.program_active = 0;
    hold_ = false;
    exec_.start_program();
    if (st_.state == MachineState::kRunning || st_.state == MachineState::kPaused) st_.state = MachineState::kIdle;
  }
  if (st_.state == MachineState::kStopping && exec_.speed() == 0.0) {
    exec_.flush(ring);
    if (paused_jog_) exec_.set_position(stand_);  // take up where the machine stands
    paused_jog_ = false;
    st_.state = after_stop_;
    st_.program_active = 0;
    discard_ = true;
    hold_ = false;
  }
}

}  // namespace pcnc
