// nurbs_follower.cpp — the block schedule's speed and the per-cycle speed follower of a
// NURBS block. See nurbs_follower.hpp. No allocation, no I/O.
#include "motion/nurbs_follower.hpp"

#include <algorithm>
#include <cmath>

namespace pcnc {

double block_schedule_speed(const NurbsGeometry& g, double u, int& hint) {
  const int n = g.schedule_count;
  if (n <= 0) return 0.0;
  if (n == 1 || u <= g.schedule_u[0]) {
    hint = 0;
    return g.schedule_speed[0];
  }
  if (u >= g.schedule_u[n - 1]) {
    hint = n - 1;
    return g.schedule_speed[n - 1];
  }
  int i = std::clamp(hint, 0, n - 2);
  while (i > 0 && u < g.schedule_u[i]) --i;
  while (i + 2 < n && u >= g.schedule_u[i + 1]) ++i;
  hint = i;
  const double a = g.schedule_u[i];
  const double b = g.schedule_u[i + 1];
  const double f = b > a ? (u - a) / (b - a) : 1.0;
  return g.schedule_speed[i] + f * (g.schedule_speed[i + 1] - g.schedule_speed[i]);
}

double block_schedule_accel(const NurbsGeometry& g, double u, int& hint) {
  const int n = g.schedule_count;
  if (n <= 0) return 0.0;
  if (n == 1 || u <= g.schedule_u[0]) {
    hint = 0;
    return g.schedule_accel[0];
  }
  if (u >= g.schedule_u[n - 1]) {
    hint = n - 1;
    return g.schedule_accel[n - 1];
  }
  int i = std::clamp(hint, 0, n - 2);
  while (i > 0 && u < g.schedule_u[i]) --i;
  while (i + 2 < n && u >= g.schedule_u[i + 1]) ++i;
  hint = i;
  return std::min(g.schedule_accel[i], g.schedule_accel[i + 1]);
}

double block_brake_capacity(const NurbsGeometry& g, double s) {
  double c = 0.0;
  for (int i = g.schedule_count - 1; i > 0; --i) {
    const double s0 = g.schedule_s[i - 1], s1 = g.schedule_s[i];
    if (s1 <= s) break;
    c += std::min(g.schedule_accel[i - 1], g.schedule_accel[i]) * (s1 - std::max(s0, s));
    if (s0 <= s) break;
  }
  return c;
}

void BrakeCapacity::start(const NurbsGeometry& g) {
  const int n = std::min<int>(g.schedule_count, kMaxFeedSchedule);
  interval_ = 0;
  rising_ = true;
  for (int i = 1; i < n; ++i) rising_ = rising_ && g.schedule_s[i - 1] <= g.schedule_s[i];
  tail_[std::max(n, 1)] = 0.0;
  for (int i = n - 1; i > 0; --i) {
    tail_[i] = tail_[i + 1] + std::min(g.schedule_accel[i - 1], g.schedule_accel[i]) * (g.schedule_s[i] - g.schedule_s[i - 1]);
  }
}

double BrakeCapacity::at(const NurbsGeometry& g, double s) {
  const int n = g.schedule_count;
  if (!rising_ || n > kMaxFeedSchedule) return block_brake_capacity(g, s);
  if (n < 2) return 0.0;
  // the last interval whose start is at or before s (block_brake_capacity's loop stops there)
  int j = std::clamp(interval_, 0, n - 1);
  while (j < n - 1 && g.schedule_s[j] <= s) ++j;
  while (j > 0 && !(g.schedule_s[j - 1] <= s)) --j;
  interval_ = j;
  if (j == 0) return tail_[1];
  const double s0 = g.schedule_s[j - 1], s1 = g.schedule_s[j];
  if (s1 <= s) return tail_[j + 1];
  return tail_[j + 1] + std::min(g.schedule_accel[j - 1], g.schedule_accel[j]) * (s1 - std::max(s0, s));
}

void NurbsFollower::start(const Block& block, double v_start) {
  const NurbsView c = view_of(block.nurbs);
  u_ = c.u_min();
  at_ = nurbs_eval(c, u_);
  s_ = 0.0;
  v_ = std::max(0.0, v_start);
  // A block without its length (it should carry one) gets it measured here, once.
  length_ = block.length > 0.0 ? block.length : nurbs_arc_length(c, c.u_min(), c.u_max());
  leftover_ = 0.0;
  hint_ = 0;
  done_ = false;
}

Vec3 NurbsFollower::step(const Block& block, double period_s, double v_end, double feed_scale) {
  if (done_) {
    leftover_ = 0.0;
    return at_.p;
  }
  const NurbsView c = view_of(block.nurbs);
  const double a = block.accel;  // braking to the end: the smallest acceleration of the block
  const double T = period_s;
  // Target: the schedule a little ahead (where this cycle's step lands), times the override.
  const double sp = norm(at_.d1);
  const double u_ahead = sp > 0.0 ? std::min(c.u_max(), u_ + v_ * T / sp) : u_;
  const double scale = std::clamp(feed_scale, 0.0, 1.0);
  // A schedule value of 0 (a corner at the block end) must not freeze the motion short of
  // the end: the floor of one cycle's speed change lets the end cap below finish the block.
  const double sched = std::max(a * T, std::min(block_schedule_speed(block.nurbs, u_, hint_),
                                                block_schedule_speed(block.nurbs, u_ahead, hint_)));
  // speeding up and slowing down here: what the schedule allows around the step
  const double a_here = std::max(a, std::min(block_schedule_accel(block.nurbs, u_, hint_),
                                             block_schedule_accel(block.nurbs, u_ahead, hint_)));
  // The override (and feed hold) change speed at the block's acceleration; the schedule and
  // the stopping distance are hard limits.
  const double desired = scale * sched;
  double v_next = desired < v_ ? std::max(desired, v_ - a_here * T) : std::min(desired, v_ + a_here * T);
  // Never faster than what still stops (or slows to v_end) within the remaining path when the
  // next cycle moves at this speed: v^2 + 2 a T v <= v_end^2 + 2 a rem.
  const double rem = remaining();
  const double ve = std::max(0.0, v_end);
  const double cap = -a * T + std::sqrt(a * a * T * T + ve * ve + 2.0 * a * rem);
  v_next = std::max(0.0, std::min({v_next, sched, cap}));
  const double ds = 0.5 * (v_ + v_next) * T;
  v_ = v_next;
  if (!(ds > 0.0)) return at_.p;  // held
  const NurbsStep st = nurbs_parameter_step(c, u_, at_, ds);
  u_ = st.u;
  at_ = st.eval;
  s_ += st.chord;
  if (st.at_end) {
    done_ = true;
    leftover_ = std::max(0.0, ds - st.chord);
    at_.p = block.end;  // exactly the programmed end point
  }
  return at_.p;
}

}  // namespace pcnc
