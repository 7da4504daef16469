// nurbs_rough.cpp — the seed's rough interpolation (step by the feed, bisect where the chord
// error exceeds delta) and the dense deviation measurement. See nurbs_rough.hpp.
#include "gcode/nurbs_rough.hpp"

#include <algorithm>

#include "geometry/nurbs_step.hpp"

namespace pcnc {
namespace {

// Chord error of the step [u0, u1] estimated at the seed's midpoint and the quarter points.
double step_error(const NurbsView& v, double u0, const Vec3& p0, double u1, const Vec3& p1) {
  double worst = 0.0;
  for (const double f : {0.25, 0.5, 0.75}) {
    worst = std::max(worst, distance_to_segment(nurbs_point(v, u0 + f * (u1 - u0)), p0, p1));
  }
  return worst;
}

void emit(const NurbsView& v, double u0, const Vec3& p0, double u1, const Vec3& p1, double tol, int depth,
          RoughPolyline& out) {
  if (depth < 40 && step_error(v, u0, p0, u1, p1) > tol) {
    ++out.bisections;
    const double um = 0.5 * (u0 + u1);
    const Vec3 pm = nurbs_point(v, um);
    emit(v, u0, p0, um, pm, tol, depth + 1, out);
    emit(v, um, pm, u1, p1, tol, depth + 1, out);
    return;
  }
  out.params.push_back(u1);
  out.points.push_back(p1);
}

}  // namespace

double distance_to_segment(const Vec3& q, const Vec3& a, const Vec3& b) {
  const Vec3 d = b - a;
  const double len2 = dot(d, d);
  const double t = len2 > 0.0 ? std::clamp(dot(q - a, d) / len2, 0.0, 1.0) : 0.0;
  return norm(q - (a + t * d));
}

RoughPolyline rough_interpolate(const NurbsCurve& curve, double step_mm, double tolerance_mm) {
  RoughPolyline out;
  const NurbsView v = curve.view();
  double u = v.u_min();
  NurbsEval at = nurbs_eval(v, u);
  out.params.push_back(u);
  out.points.push_back(at.p);
  while (u < v.u_max()) {
    const NurbsStep st = nurbs_parameter_step(v, u, at, step_mm);
    if (!(st.u > u)) break;
    emit(v, u, at.p, st.u, st.eval.p, tolerance_mm, 0, out);
    u = st.u;
    at = st.eval;
    if (st.at_end) break;
  }
  out.segments = out.points.size() - 1;
  out.max_deviation_mm = polyline_deviation(curve, out.params, out.points);
  return out;
}

double polyline_deviation(const NurbsCurve& curve, const std::vector<double>& params,
                          const std::vector<Vec3>& points, int samples) {
  const NurbsView v = curve.view();
  double worst = 0.0;
  for (std::size_t i = 0; i + 1 < params.size(); ++i) {
    for (int k = 1; k < samples; ++k) {
      const double u = params[i] + (params[i + 1] - params[i]) * k / samples;
      worst = std::max(worst, distance_to_segment(nurbs_point(v, u), points[i], points[i + 1]));
    }
  }
  return worst;
}

}  // namespace pcnc
