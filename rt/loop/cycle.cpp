// cycle.cpp — what happens in one 500 µs cycle, in this order:
//   1. machine time advances;
//   2. state: a pending flush, the host's loss, an abandoned program's blocks, a block that
//      starts a program (state_machine.hpp);
//   3. motion: the program's executor or the jog gives this cycle's setpoint, as the state says;
//   4. safety: the setpoint put onto the travel within the block tolerance, or a soft-limit trip;
//      the probe senses at the setpoint (the commanded ball centre, docs/probe.md);
//   5. drive: one PID step per axis on the encoder reading, one plant step (drive/drive.hpp);
//   6. safety: the following-error limit;
//   7. status and the trace sample are published for the loop (rt_loop.cpp) to copy out.
// Mailbox commands were taken before it (Machine::command). Pure computation: no allocation,
// no locks, no system calls, no I/O, no logging.
#include <algorithm>
#include <cmath>

#include "ipc/block_check.hpp"
#include "loop/machine_impl.hpp"
#include "loop/safety.hpp"
#include "motion/contour_error.hpp"

namespace pcnc {

void Machine::Impl::cycle(MotionRing& ring) {
  // 1. time
  ++st.cycle;
  st.time_s = static_cast<double>(st.cycle) * dt;
  if (st.program_active) st.program_time_s += dt;

  // 2. state, 3. motion
  sm.begin_cycle(ring);
  sm.move(ring);

  // 4. the setpoint within the travel
  const Vec3 meas = drive.encoder();
  if (sm.amps_on()) {
    clamp_onto_travel(sp.pos, cfg);
    const int ax = outside_travel(sp.pos, cfg, 0.0);
    if (ax >= 0) {
      sm.trip(FaultCode::kSoftLimit, ax, sp.pos[ax], exec.line(), "setpoint outside the travel", &ring);
      sp.pos = st.commanded;  // never command it
    }
  }
  const Rot3 rmeas = drive.rotary_encoder();
  if (sm.amps_on() && st.rotary_mask != 0) {
    const int j = outside_rotary_travel(sp.rot, cfg, 0.0);
    if (j >= 0) {
      sm.trip(FaultCode::kSoftLimit, kAxes + j, sp.rot[static_cast<std::size_t>(j)], exec.line(),
              "rotary setpoint outside the joint's travel", &ring);
      sp.rot = st.rot_commanded;  // never command it
    }
  }
  if (!sm.amps_on()) {
    sp.pos = meas;  // amplifiers off: the setpoint follows the axes
    sp.rot = rmeas;
  }
  Vec3 probe_dir{};
  if (exec.take_probe_arm(probe_dir)) probe.arm(probe_dir);
  st.probe_input = probe.sense(sp.pos) ? 1 : 0;  // the executor sees it next cycle, as a real input

  // 5. servo and plant
  const Vec3 ferr = sp.pos - meas;
  drive.step(sp.pos, meas, sp.vel, sp.acc, sm.amps_on());
  Rot3 rferr{};
  if (st.rotary_mask != 0) {
    for (int i = 0; i < kRotaryJoints; ++i) rferr[static_cast<std::size_t>(i)] = sp.rot[static_cast<std::size_t>(i)] - rmeas[static_cast<std::size_t>(i)];
    drive.step_rotary(sp.rot, rmeas, sp.rot_vel, sp.rot_acc, sm.amps_on());
  }

  // 6. following error
  if (sm.amps_on()) {
    const int ax = following_error_axis(ferr, cfg);
    if (ax >= 0) sm.trip(FaultCode::kFollowingError, ax, ferr[ax], exec.line(), "following error over the limit", &ring);
    for (int i = 0; i < kRotaryJoints && sm.amps_on(); ++i) {
      const auto& j = cfg.rotary[static_cast<std::size_t>(i)];
      if (j && std::abs(rferr[static_cast<std::size_t>(i)]) > j->following_error_limit_rad) {
        sm.trip(FaultCode::kFollowingError, kAxes + i, rferr[static_cast<std::size_t>(i)], exec.line(),
                "rotary following error over the limit", &ring);
      }
    }
  }

  // 7. status and trace
  st.commanded = sp.pos;
  st.actual = meas;
  st.velocity = sp.vel;
  st.following_error = ferr;
  for (int i = 0; i < kAxes; ++i) {
    st.max_following_error[i] = std::max(st.max_following_error[i], std::abs(ferr[i]));
  }
  st.contour_error = 0.0;
  if (st.program_active && sm.amps_on()) {
    ++st.program_cycles;
    for (int i = 0; i < kAxes; ++i) st.following_error_sq_sum[i] += ferr[i] * ferr[i];
    // off the path on purpose during a paused program's jog
    const double ce = sm.off_path() ? -1.0 : contour_error(exec, meas, cfg.axes[0].following_error_limit_mm);
    if (ce >= 0.0) {
      st.contour_error = ce;
      st.max_contour_error = std::max(st.max_contour_error, ce);
      st.contour_error_sq_sum += ce * ce;
    }
  }
  st.rot_commanded = sp.rot;
  st.rot_actual = rmeas;
  st.rot_velocity = sp.rot_vel;
  st.rot_following_error = rferr;
  for (int i = 0; i < kRotaryJoints; ++i) {
    const auto k = static_cast<std::size_t>(i);
    st.rot_max_following_error[k] = std::max(st.rot_max_following_error[k], std::abs(rferr[k]));
  }
  st.tcp = exec.tcp() ? 1 : 0;
  st.line = exec.line();
  st.block_seq = exec.seq();
  st.contouring = exec.contouring() ? 1 : 0;
  st.ring_fill = static_cast<std::uint8_t>(ring.size());
  st.feed_override = ovr.value();

  ts.t = st.time_s;
  ts.line = st.line;
  ts.state = st.state;
  ts.commanded = sp.pos;
  ts.actual = meas;
  ts.following_error = ferr;
  ts.speed = st.path_speed;
  tj.commanded = sp.rot;
  tj.actual = rmeas;
}

}  // namespace pcnc
