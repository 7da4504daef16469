// ruled_passes.cpp — the passes of a ball-end mill over a part surface as ruled-surface pieces.
// See ruled_passes.hpp.
#include "geometry/ruled_passes.hpp"

#include <algorithm>
#include <cmath>
#include <memory>

#include "geometry/cusp.hpp"
#include "geometry/hermite_curve.hpp"

namespace pcnc {

PartSurface part_surface(const BSplineSurface& s) {
  auto copy = std::make_shared<const BSplineSurface>(s);
  PartSurface p;
  p.eval = [copy](double u, double v) { return surface_eval(*copy, u, v); };
  p.u_min = s.u_min();
  p.u_max = s.u_max();
  p.v_min = s.v_min();
  p.v_max = s.v_max();
  return p;
}

double example_height(double x, double y) {
  const double h = 3 * y * y - 2 * y * y * y;
  return 4 + 12 * h + 16 * x * (1 - x) * (2 * y - 1);
}

BSplineSurface example_surface(double size, const Vec3& origin) {
  // Bernstein coefficients (degree 3) of the formula's factors: 1 -> (1,1,1,1);
  // 3y^2 - 2y^3 -> (0,0,1,1); x(1 - x) -> (0,1/3,1/3,0); 2y - 1 -> (-1,-1/3,1/3,1); x -> (0,1/3,2/3,1).
  const double h[4] = {0, 0, 1, 1};
  const double q[4] = {0, 1.0 / 3, 1.0 / 3, 0};
  const double l[4] = {-1, -1.0 / 3, 1.0 / 3, 1};
  const double k = size / 200.0;
  BSplineSurface s;
  s.degree = 3;
  s.count_u = 4;
  s.count_v = 4;
  s.knots_u = {0, 0, 0, 0, 1, 1, 1, 1};
  s.knots_v = s.knots_u;
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i)
      s.points.push_back({origin[0] + size * i / 3.0, origin[1] + size * j / 3.0,
                          origin[2] + k * (4 + 12 * h[j] + 16 * q[i] * l[j])});
  return s;
}

PassPoint pass_point(const SurfaceEval& e, const Vec3& dir, double tool_radius, double lead_angle) {
  PassPoint p;
  p.contact = e.p;
  Vec3 n = normalized(cross(e.su, e.sv));
  if (n[2] < 0.0) n = -1.0 * n;
  p.normal = n;
  const Vec3 t = normalized(dir - dot(dir, n) * n);
  p.axis = normalized(std::cos(lead_angle) * n + std::sin(lead_angle) * t);
  p.tip = e.p + tool_radius * n - tool_radius * p.axis;
  return p;
}

double pass_gap(const PartSurface& s, double u0, double u1, int samples) {
  const int m = std::max(samples, 2);
  const double span = s.v_max - s.v_min;
  double worst = 0.0;
  for (int i = 0; i < m; ++i) {
    const double v = s.v_min + span * i / (m - 1);
    const Vec3 p = s.eval(u0, v).p;
    // The nearest point of the curve at u1: Newton on (S - p) . S_v = 0, from the same v.
    double w = v;
    for (int it = 0; it < 30; ++it) {
      const SurfaceEval e = s.eval(u1, w);
      const Vec3 d = e.p - p;
      const double f = dot(d, e.sv), fp = dot(e.sv, e.sv) + dot(d, e.svv);
      if (!(fp > 0.0)) break;
      const double next = std::clamp(w - f / fp, s.v_min, s.v_max);
      const double step = std::abs(next - w);
      w = next;
      if (step <= 1e-15 * span) break;
    }
    // The distance to the curve's tangent line there: the distance to the nearest point inside,
    // and where the foot falls beyond the curve's end (the passes end at the surface's edge),
    // the distance to the curve continued along its end tangent.
    const SurfaceEval e = s.eval(u1, w);
    const Vec3 d = p - e.p, t = normalized(e.sv);
    worst = std::max(worst, norm(d - dot(d, t) * t));
  }
  return worst;
}

double directrix_length(const RuledModel& model) {
  static const double x[5] = {0.0, -0.5384693101056831, 0.5384693101056831, -0.9061798459386640, 0.9061798459386640};
  static const double w[5] = {0.5688888888888889, 0.4786286704993665, 0.4786286704993665, 0.2369268850561891,
                              0.2369268850561891};
  double total = 0.0;
  for (const HermiteSegment& seg : model.directrix)
    for (int k = 0; k < 5; ++k) total += 0.5 * w[k] * norm(hermite_jet(seg, 0.5 + 0.5 * x[k]).d1);
  return total;
}

ModelError pass_model_error(const PartSurface& s, const Pass& pass, const PassOptions& o, int per_segment) {
  ModelError err;
  const RuledCurves c = pass.model.curves();
  auto exact = [&](double v) {
    const SurfaceEval e = s.eval(pass.u, v);
    return pass_point(e, pass.reversed ? -1.0 * e.sv : e.sv, o.tool_radius, o.lead_angle);
  };
  const double g = (std::sqrt(5.0) - 1.0) / 2.0;
  for (std::size_t i = 0; i + 1 < pass.points.size(); ++i) {
    const double va = pass.points[i].v, vb = pass.points[i + 1].v, half = 0.5 * std::abs(vb - va);
    for (int k = 0; k < per_segment; ++k) {
      const RuledJet j = ruled_jet(c, static_cast<double>(i) + (k + 0.5) / per_segment);
      auto dist = [&](double v) { return norm(exact(v).tip - j.c.p); };
      double a = std::max(s.v_min, std::min(va, vb) - half), b = std::min(s.v_max, std::max(va, vb) + half);
      double m1 = b - g * (b - a), m2 = a + g * (b - a), f1 = dist(m1), f2 = dist(m2);
      for (int it = 0; it < 80 && b - a > 1e-13 * (s.v_max - s.v_min); ++it) {
        if (f1 < f2) {
          b = m2, m2 = m1, f2 = f1, m1 = b - g * (b - a), f1 = dist(m1);
        } else {
          a = m1, m1 = m2, f1 = f2, m2 = a + g * (b - a), f2 = dist(m2);
        }
      }
      const PassPoint near = exact(0.5 * (a + b));
      err.tip = std::max(err.tip, norm(near.tip - j.c.p));
      err.axis = std::max(err.axis, std::atan2(norm(cross(near.axis, j.e.p)), dot(near.axis, j.e.p)));
    }
  }
  return err;
}

namespace {

// The next pass's u: the largest u1 in (u0, u_max] with pass_gap(u0, u1) <= P (bisection).
double next_pass(const PartSurface& s, double u0, double P, int samples) {
  if (pass_gap(s, u0, s.u_max, samples) <= P) return s.u_max;
  double lo = u0, hi = s.u_max;
  for (int it = 0; it < 80 && hi - lo > 1e-14 * (s.u_max - s.u_min); ++it) {
    const double mid = 0.5 * (lo + hi);
    (pass_gap(s, u0, mid, samples) <= P ? lo : hi) = mid;
  }
  return lo;
}

}  // namespace

PassPlan plan_passes(const PartSurface& s, const PassOptions& o) {
  PassPlan plan;
  plan.interval = pass_interval(o.cusp_height, o.tool_radius);
  if (!(plan.interval > 0.0)) {
    plan.error = "the tool radius must be > 0 and the cusp height in (0, R]";
    return plan;
  }
  if (!(o.point_spacing > 0.0)) {
    plan.error = "the point spacing must be > 0";
    return plan;
  }
  if (!s.eval || !(s.u_max > s.u_min) || !(s.v_max > s.v_min)) {
    plan.error = "the surface has an empty domain";
    return plan;
  }
  if (!(std::abs(o.lead_angle) < 1.5)) {
    plan.error = "the lead angle must be under 86 degrees";
    return plan;
  }
  std::vector<double> us{s.u_min};
  while (us.back() < s.u_max) {
    const double next = next_pass(s, us.back(), plan.interval, o.spacing_samples);
    if (!(next > us.back()) || us.size() > 200000) {
      plan.error = "the passes do not advance (a degenerate surface?)";
      return plan;
    }
    us.push_back(next);
  }
  for (std::size_t k = 0; k < us.size(); ++k) {
    Pass pass;
    pass.u = us[k];
    pass.reversed = o.zigzag && k % 2 == 1;
    double est = 0.0;
    Vec3 prev = s.eval(pass.u, s.v_min).p;
    for (int i = 1; i <= 200; ++i) {
      const Vec3 p = s.eval(pass.u, s.v_min + (s.v_max - s.v_min) * i / 200.0).p;
      est += norm(p - prev);
      prev = p;
    }
    const int segments = std::max(1, static_cast<int>(std::ceil(est / o.point_spacing - 1e-9)));
    std::vector<Vec3> tips, axes;
    for (int i = 0; i <= segments; ++i) {
      const double f = static_cast<double>(pass.reversed ? segments - i : i) / segments;
      const double v = s.v_min + (s.v_max - s.v_min) * f;
      const SurfaceEval e = s.eval(pass.u, v);
      const double cr = norm(cross(e.su, e.sv));
      if (!(cr > 1e-12 * norm(e.su) * norm(e.sv))) {
        plan.error = "the surface has no normal at u " + std::to_string(pass.u) + ", v " + std::to_string(v) +
                     " (a degenerate point: its partial derivatives are parallel or zero)";
        return plan;
      }
      PassPoint p = pass_point(e, pass.reversed ? -1.0 * e.sv : e.sv, o.tool_radius, o.lead_angle);
      p.u = pass.u;
      p.v = v;
      tips.push_back(p.tip);
      axes.push_back(p.axis);
      pass.points.push_back(p);
    }
    RuledModelResult m = ruled_model_through(tips, axes, o.form);
    if (!m.error.empty()) {
      plan.error = "pass " + std::to_string(k + 1) + ": " + m.error;
      return plan;
    }
    pass.model = std::move(m.model);
    pass.length = directrix_length(pass.model);
    if (k + 1 < us.size()) pass.gap_to_next = pass_gap(s, us[k], us[k + 1], o.spacing_samples);
    plan.passes.push_back(std::move(pass));
  }
  return plan;
}

}  // namespace pcnc
