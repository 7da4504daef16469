// nurbs_step.cpp — Taylor parameter step with Newton correction (see nurbs_step.hpp).
#include "geometry/nurbs_step.hpp"

#include <algorithm>
#include <cmath>

namespace pcnc {

namespace {

// The step, the curve evaluated by `eval` (nurbs_eval with or without a span hint).
template <typename Eval>
NurbsStep parameter_step(const NurbsView& c, double u, const NurbsEval& at, double ds, Eval&& eval) {
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
    out.eval = eval(out.u);
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

}  // namespace

NurbsStep nurbs_parameter_step(const NurbsView& c, double u, const NurbsEval& at, double ds) {
  return parameter_step(c, u, at, ds, [&](double x) { return nurbs_eval(c, x); });
}

NurbsStep nurbs_parameter_step(const NurbsView& c, double u, const NurbsEval& at, double ds, int& span_hint) {
  return parameter_step(c, u, at, ds, [&](double x) { return nurbs_eval(c, x, span_hint); });
}

}  // namespace pcnc
