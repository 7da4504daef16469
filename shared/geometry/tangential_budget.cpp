// tangential_budget.cpp — the tangential acceleration the axes leave after the normal part
// (see tangential_budget.hpp).
#include "geometry/tangential_budget.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace pcnc {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();
}

AccelRange tangential_accel_range(const Vec3& t, const Vec3& k, double v2, const AxisLimits& accel) {
  AccelRange r{-kInf, kInf};
  for (int i = 0; i < kAxes; ++i) {
    const double normal = k[i] * v2;  // this axis's share of the centripetal acceleration
    const double ti = t[i];
    if (std::abs(ti) <= kAxisShareEps) {
      if (std::abs(normal) > accel[i]) return {kInf, -kInf};  // nothing helps: empty
      continue;
    }
    // −A_i ≤ t_i·a + normal ≤ A_i
    double lo = (-accel[i] - normal) / ti;
    double hi = (accel[i] - normal) / ti;
    if (ti < 0.0) std::swap(lo, hi);
    r.lo = std::max(r.lo, lo);
    r.hi = std::min(r.hi, hi);
  }
  return r;
}

double tangential_budget(const Vec3& t, const Vec3& k, double v2, const AxisLimits& accel) {
  double b = kInf;
  for (int i = 0; i < kAxes; ++i) {
    const double ti = std::abs(t[i]);
    if (ti > kAxisShareEps) b = std::min(b, (accel[i] - std::abs(k[i]) * v2) / ti);
  }
  return b;
}

double reachable_v2(double v2_from, double ds, const Vec3& t, const Vec3& k, const AxisLimits& accel, double share) {
  // x ≤ v2_from + 2·ds·share·(A_i − |k_i|·x)/|t_i|  ⇔  x·(|t_i| + 2·ds·share·|k_i|) ≤ v2_from·|t_i| + 2·ds·share·A_i
  const double q = 2.0 * std::max(0.0, ds) * share;
  double x = kInf;
  for (int i = 0; i < kAxes; ++i) {
    const double ti = std::abs(t[i]);
    if (ti <= kAxisShareEps) continue;
    x = std::min(x, (v2_from * ti + q * accel[i]) / (ti + q * std::abs(k[i])));
  }
  return x;
}

CurveFrame nurbs_frame(const NurbsView& c, double u) {
  int span = c.degree;
  return nurbs_frame(c, u, span);
}

namespace {

// nurbs_frame from the evaluation e at u (span_hint: u's span).
CurveFrame frame_of(const NurbsView& c, double u, NurbsEval e, int span_hint) {
  CurveFrame f;
  f.p = e.p;
  const double scale = (c.u_max() - c.u_min()) * 1e-7;
  if (!(norm(e.d1) > 1e-9 * (norm(e.d2) * scale + 1e-300))) {
    int beside = span_hint;
    e = nurbs_eval(c, u < c.u_max() ? u + scale : u - scale, beside);
  }
  const double sp = norm(e.d1);
  if (!(sp > 0.0)) return f;
  f.ok = true;
  f.t = (1.0 / sp) * e.d1;
  f.k = (1.0 / (sp * sp)) * (e.d2 - dot(e.d2, f.t) * f.t);
  return f;
}

}  // namespace

CurveFrame nurbs_frame(const NurbsView& c, double u, int& span_hint) {
  const NurbsEval e = nurbs_eval(c, u, span_hint);
  return frame_of(c, u, e, span_hint);
}

void nurbs_frame_pair(const NurbsView& c, double ua, double ub, int& span_hint, CurveFrame& fa, CurveFrame& fb) {
  NurbsEval ea, eb;
  nurbs_eval_pair(c, ua, ub, span_hint, ea, eb);
  fa = frame_of(c, ua, ea, span_hint);
  fb = frame_of(c, ub, eb, span_hint);
}

}  // namespace pcnc
