// ruled_follower.cpp — the per-cycle interpolation of a ruled-surface piece: speed, Taylor
// step with chord correction, pose and motion, joints with their feed-forward. See
// ruled_follower.hpp. No allocation, no I/O.
#include "motion/ruled_follower.hpp"

#include <algorithm>
#include <cmath>

#include "geometry/kinematics_rates.hpp"

namespace pcnc {

double ruled_schedule_speed(const RuledGeometry& g, double u, int& hint) {
  const int n = std::min(g.schedule_count, kMaxRuledSchedule);  // a bad count cannot read past the arrays
  if (n <= 0) return 0.0;
  if (n == 1 || u <= g.schedule_u[0]) {
    hint = 0;
    return g.schedule_speed[0];
  }
  if (u >= g.schedule_u[n - 1]) {
    hint = n - 2;
    return g.schedule_speed[n - 1];
  }
  int i = std::clamp(hint, 0, n - 2);
  while (i > 0 && u < g.schedule_u[i]) --i;
  while (i + 2 < n && u >= g.schedule_u[i + 1]) ++i;
  hint = i;
  const double a = g.schedule_u[i], b = g.schedule_u[i + 1];
  const double f = b > a ? (u - a) / (b - a) : 1.0;
  return g.schedule_speed[i] + f * (g.schedule_speed[i + 1] - g.schedule_speed[i]);
}

RuledSample ruled_sample_at(const RuledGeometry& g, const Kinematics& kin, const RotaryTravel& travel,
                            const Joints& previous, double u, double feed, double dfeed) {
  RuledSample s;
  s.u = u;
  s.feed = feed;
  s.dfeed = dfeed;
  const RuledJet j = ruled_jet(curves_of(g), u);
  s.motion = tool_motion(j, u, feed, dfeed);
  const ToolPose pose{s.motion.position, s.motion.A};
  s.q = inverse(kin, pose, previous, travel);
  // The Jacobian's rates are linear in the pose's rate: d/dt in, d/dt out.
  s.dq = joint_rates(kin, s.q, PoseRate{s.motion.velocity, s.motion.axis_velocity});
  s.ddq = joint_accels(kin, s.q, s.dq, PoseRate{s.motion.acceleration, s.motion.axis_acceleration});
  return s;
}

void RuledFollower::start(const RuledGeometry& g, const Kinematics& kin, const RotaryTravel& travel,
                          const Joints& q_now, double carry, double speed) {
  kin_ = kin;
  travel_ = travel;
  s_ = 0.0;
  hint_ = 0;
  done_ = g.segment_count <= 0;
  top_speed_ = 0.0;
  for (int i = 0; i < g.schedule_count && i < kMaxRuledSchedule; ++i) top_speed_ = std::max(top_speed_, g.schedule_speed[i]);
  leftover_ = 0.0;
  double u0 = 0.0;
  if (!done_ && carry > 0.0 && carry < g.length) {
    // a chord of length `carry` from u = 0: the Taylor step and its correction in arc length
    const ParameterStep st = advance_parameter(curves_of(g).directrix, 0.0, carry, 0.0, 1.0);
    u0 = st.u_next;
    s_ = st.chord;
  }
  sample_ = ruled_sample_at(g, kin_, travel_, q_now, u0, std::max(0.0, speed < 0.0 ? g.start_speed : speed), 0.0);
  sample_.chord = s_;
}

const RuledSample& RuledFollower::step(const RuledGeometry& g, double period_s, double end_speed, double scale) {
  if (done_) {
    leftover_ = 0.0;
    return sample_;
  }
  leftover_ = 0.0;
  const double T = period_s;
  const double a = g.accel;
  const double u = sample_.u;
  const double v = sample_.feed;
  const double u_end = curves_of(g).u_max();
  // The schedule here and where this cycle lands (so a drop ahead is not overrun); a floor
  // of one cycle's speed change (but never above the schedule's largest speed) so that a
  // schedule of 0 cannot freeze the motion short of the end (the end cap below still brings
  // it to the end speed).
  const double sp = norm(curve_jet(curves_of(g).directrix, u).d1);
  const double u_ahead = sp > 0.0 ? std::min(u_end, u + v * T / sp) : u;
  scale = std::clamp(scale, 0.0, 1.0);
  const double floor = scale > 0.0 ? std::min(a * T, top_speed_) : 0.0;
  const double sched = std::max(floor, scale * std::min(ruled_schedule_speed(g, u, hint_), ruled_schedule_speed(g, u_ahead, hint_)));
  double v_next = sched < v ? std::max(sched, v - a * T) : std::min(sched, v + a * T);
  // Never faster than what still slows to the end speed within the remaining length when
  // the next cycle moves at this speed: v^2 + 2 a T v <= v_end^2 + 2 a rem (no cap below the
  // end speed itself: nothing to slow down for).
  const double rem = std::max(0.0, g.length - s_);
  const double ve = std::clamp(end_speed, 0.0, std::max(0.0, g.end_speed));
  const double cap = -a * T + std::sqrt(a * a * T * T + ve * ve + 2.0 * a * rem);
  v_next = std::max(0.0, std::min(v_next, std::max(cap, ve)));
  const double dfeed = (v_next - v) / T;
  const double target = 0.5 * (v + v_next) * T;  // = v T + dF/dt T^2 / 2
  double u_next = u;
  double chord = 0.0;
  bool last = false;
  if (target >= rem) {
    // The end lies within this cycle: stop exactly there (the cycle is shorter).
    u_next = u_end;
    chord = rem;
    last = true;
    leftover_ = target - rem;
  } else if (target > 0.0) {
    const ParameterStep st = advance_parameter(curves_of(g).directrix, u, v, dfeed, T);
    u_next = st.u_next;
    chord = st.chord;
    last = u_next >= u_end;
  }
  s_ += chord;
  sample_ = ruled_sample_at(g, kin_, travel_, sample_.q, u_next, last ? std::min(ve, v_next) : v_next, dfeed);
  sample_.target = target;
  sample_.chord = chord;
  sample_.last = last;
  done_ = last;
  return sample_;
}

}  // namespace pcnc
