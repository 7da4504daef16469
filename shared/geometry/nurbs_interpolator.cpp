// nurbs_interpolator.cpp — Taylor parameter step with Newton correction, and the per-cycle
// speed follower of a NURBS block. See nurbs_interpolator.hpp. No allocation, no I/O.
#include "geometry/nurbs_interpolator.hpp"

#include <algorithm>
#include <cmath>

namespace pcnc {

NurbsStep nurbs_parameter_step(const NurbsView& c, double u, const NurbsEval& at, double ds) {
  NurbsStep out;
  const double u_end = c.u_max();
  if (!(ds > 0.0) || u >= u_end) {
    out.u = std::min(u, u_end);
    out.eval = at;
    out.at_end = u >= u_end;
    return out;
  }
  // Taylor guess for the parameter increment h.
  const double sp = norm(at.d1);
  const double acc = norm(at.d2);
  double h = 0.0;
  if (sp > 1e-12 * (1.0 + acc)) {
    h = ds / sp;
    const double second = ds * ds * dot(at.d1, at.d2) / (2.0 * sp * sp * sp * sp);
    if (h - second > 0.25 * h && h - second < 4.0 * h) h -= second;
  }
  if (!(h > 0.0) || sp < 1e-6 * std::sqrt(acc * ds)) {
    // Parametric speed (nearly) zero, as at a doubled control point: C(u+h) - C(u) ~ C'' h²/2.
    const double h2 = acc > 0.0 ? std::sqrt(2.0 * ds / acc) : (u_end - u);
    h = std::max(h, h2);
  }
  h = std::min(h, u_end - u);

  // Newton on f(h) = |C(u+h) - C(u)| - ds, f'(h) = (chord . C'(u+h)) / |chord|.
  double lo = 0.0;           // f(lo) < 0
  double hi = u_end - u;     // bracket end
  for (int iter = 0; iter < 8; ++iter) {
    out.u = u + h;
    out.eval = nurbs_eval(c, out.u);
    const Vec3 chord = out.eval.p - at.p;
    out.chord = norm(chord);
    const double f = out.chord - ds;
    if (f < 0.0 && h >= u_end - u) {  // the end is within reach
      out.at_end = true;
      return out;
    }
    if (std::fabs(f) <= 1e-10 * ds + 1e-13) return out;  // 1e-13 mm: rounding of mm-sized coordinates
    if (f < 0.0) {
      lo = h;
    } else {
      hi = h;
    }
    const double df = out.chord > 0.0 ? dot(chord, out.eval.d1) / out.chord : 0.0;
    double next = df > 0.0 ? h - f / df : 0.5 * (lo + hi);
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);  // keep inside the bracket
    if (next == h) return out;
    h = next;
  }
  return out;
}

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
  const double a = block.accel;
  const double T = period_s;
  // Target: the schedule a little ahead (where this cycle's step lands), times the override.
  const double sp = norm(at_.d1);
  const double u_ahead = sp > 0.0 ? std::min(c.u_max(), u_ + v_ * T / sp) : u_;
  const double scale = std::clamp(feed_scale, 0.0, 1.0);
  // A schedule value of 0 (a corner at the block end) must not freeze the motion short of
  // the end: the floor of one cycle's speed change lets the end cap below finish the block.
  const double sched = std::max(a * T, std::min(block_schedule_speed(block.nurbs, u_, hint_),
                                                block_schedule_speed(block.nurbs, u_ahead, hint_)));
  // The override (and feed hold) change speed at the block's acceleration; the schedule and
  // the stopping distance are hard limits.
  const double desired = scale * sched;
  double v_next = desired < v_ ? std::max(desired, v_ - a * T) : std::min(desired, v_ + a * T);
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
