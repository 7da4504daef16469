// biarc.cpp — one biarc from end conditions, the adaptive fit of a planar NURBS curve
// (the seed's bisection algorithm) and the two-sided deviation measured by Newton
// iteration. See biarc.hpp.
#include "geometry/biarc.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace pcnc {
namespace {

constexpr double kTiny = 1e-12;  // mm: a chord shorter than this is a point

// The curve in plane coordinates.
struct PlaneCurve {
  NurbsView v;
  int normal = 2;

  struct Eval {
    Vec2 p, d1, d2;
  };
  Eval eval(double u) const {
    const NurbsEval e = nurbs_eval(v, u);
    return {to_plane(e.p, normal), to_plane(e.d1, normal), to_plane(e.d2, normal)};
  }
  Vec2 point(double u) const { return to_plane(nurbs_point(v, u), normal); }
  // Unit tangent in the plane; `toward_end` picks the side where the speed vanishes.
  Vec2 tangent(double u, bool toward_end) const {
    return normalized(to_plane(nurbs_tangent(v, u, toward_end), normal));
  }
};

// Exact nearest point of a chain of arcs and its distance.
double nearest_on(const std::vector<Arc2>& arcs, Vec2 p, Vec2* q) {
  double best = std::numeric_limits<double>::infinity();
  for (const Arc2& a : arcs) {
    double f = 0.0;
    const double d = arc_distance(a, p, &f);
    if (d < best) {
      best = d;
      if (q) *q = arc_point(a, f);
    }
  }
  return best;
}

// g(u) = (C(u) - Q(u)) . C'(u): half the derivative of the squared distance from the curve
// point to the arcs (Q moves along the arcs, perpendicular to C - Q, so it drops out).
double distance_slope(const PlaneCurve& c, const std::vector<Arc2>& arcs, double u) {
  const PlaneCurve::Eval e = c.eval(u);
  Vec2 q{};
  nearest_on(arcs, e.p, &q);
  return dot(e.p - q, e.d1);
}

// The largest distance from C(u), u in [a, b], to the arcs near a sampled maximum: the root of
// distance_slope in [a, b] (positive at a, negative at b) by Newton steps on the slope with a
// central-difference derivative, kept inside the bracket (bisection when a step leaves it).
double refine_curve_max(const PlaneCurve& c, const std::vector<Arc2>& arcs, double a, double b) {
  double ga = distance_slope(c, arcs, a), gb = distance_slope(c, arcs, b);
  if (!(ga > 0.0 && gb < 0.0)) return 0.0;  // no interior maximum bracketed
  double u = 0.5 * (a + b);
  const double span = b - a;
  for (int it = 0; it < 60 && (b - a) > 1e-13 * std::max(1.0, std::abs(u)); ++it) {
    const double g = distance_slope(c, arcs, u);
    if (g > 0.0) a = u; else b = u;
    const double h = 1e-7 * span;
    const double dg = (distance_slope(c, arcs, u + h) - distance_slope(c, arcs, u - h)) / (2.0 * h);
    double next = dg < 0.0 ? u - g / dg : 0.5 * (a + b);
    if (!(next > a && next < b)) next = 0.5 * (a + b);
    if (std::abs(next - u) < 1e-15 * std::max(1.0, std::abs(u))) break;
    u = next;
  }
  return nearest_on(arcs, c.point(u), nullptr);
}

// Distance from p to the curve on [u0, u1]: Newton on (C(u) - p) . C'(u) = 0 from u.
double project(const PlaneCurve& c, Vec2 p, double u0, double u1, double& u) {
  for (int it = 0; it < 30; ++it) {
    const PlaneCurve::Eval e = c.eval(u);
    const Vec2 r = e.p - p;
    const double f = dot(r, e.d1);
    const double df = dot(e.d1, e.d1) + dot(r, e.d2);
    if (!(df > 0.0)) break;
    const double next = std::clamp(u - f / df, u0, u1);
    if (distance(c.point(next), p) > norm(r) * (1.0 + 1e-12) + 1e-15) break;  // never move away
    const bool done = std::abs(next - u) < 1e-14 * std::max(1.0, std::abs(u));
    u = next;
    if (done) break;
  }
  return distance(c.point(u), p);
}

}  // namespace

void append_biarc(std::vector<Arc2>& out, const std::vector<Arc2>& arcs) {
  // two collinear segments (a biarc between aligned tangents) are one segment
  if (arcs.size() == 2 && arcs[0].line && arcs[1].line &&
      std::abs(cross(arcs[0].end - arcs[0].start, arcs[1].end - arcs[1].start)) <=
          1e-12 * arc_length(arcs[0]) * arc_length(arcs[1]) &&
      dot(arcs[0].end - arcs[0].start, arcs[1].end - arcs[1].start) >= 0.0) {
    out.push_back(make_segment(arcs[0].start, arcs[1].end));
    return;
  }
  for (const Arc2& a : arcs)
    if (arc_length(a) > 0.0 || arcs.size() == 1) out.push_back(a);
}

std::optional<Biarc> make_biarc(Vec2 p0, Vec2 t0, Vec2 p1, Vec2 t1, double ratio) {
  const Vec2 v = p1 - p0;
  const double vv = dot(v, v);
  if (!(vv > kTiny * kTiny) || !(ratio > 0.0)) return std::nullopt;
  // Q1 = p0 + alpha t0, Q2 = p1 - beta t1, beta = k alpha, |Q2 - Q1| = alpha + beta:
  // a alpha^2 + b alpha - |v|^2 = 0 with a = 2k (1 - t0.t1), b = 2 v.(t0 + k t1).
  const double k = ratio;
  const double a = 2.0 * k * (1.0 - dot(t0, t1));
  const double b = 2.0 * dot(v, t0 + k * t1);
  const double disc = b * b + 4.0 * a * vv;
  if (disc < 0.0) return std::nullopt;
  const double den = b + std::sqrt(disc);
  if (!(den > 1e-300)) return std::nullopt;
  const double alpha = 2.0 * vv / den;  // the positive root, stable form
  const double beta = k * alpha;
  if (!(alpha > 0.0) || !std::isfinite(alpha)) return std::nullopt;
  const Vec2 q1 = p0 + alpha * t0, q2 = p1 - beta * t1;
  const Vec2 j = (1.0 / (alpha + beta)) * (beta * q1 + alpha * q2);
  Biarc bi;
  bi.first = make_arc_from_tangent(p0, t0, j);
  bi.second = reversed(make_arc_from_tangent(p1, -t1, j));
  bi.first.end = j;  // exactly shared
  bi.second.start = j;
  return bi;
}

double nearest_on_arcs(const std::vector<Arc2>& arcs, Vec2 p, Vec2* q) { return nearest_on(arcs, p, q); }

double curve_deviation(const NurbsCurve& curve, int normal_axis, double u0, double u1, const std::vector<Arc2>& arcs) {
  if (arcs.empty() || !(u1 > u0)) return 0.0;
  const PlaneCurve c{curve.view(), normal_axis};
  // samples: uniform in u, plus the knots inside (the curve's smoothness changes there)
  std::vector<double> us;
  constexpr int kSamples = 32;
  for (int i = 0; i <= kSamples; ++i) us.push_back(u0 + (u1 - u0) * i / kSamples);
  for (double t : curve.knots)
    if (t > u0 && t < u1) us.push_back(t);
  std::sort(us.begin(), us.end());
  us.erase(std::unique(us.begin(), us.end()), us.end());
  std::vector<double> d(us.size());
  std::vector<Vec2> pts(us.size());
  for (std::size_t i = 0; i < us.size(); ++i) {
    pts[i] = c.point(us[i]);
    d[i] = nearest_on(arcs, pts[i], nullptr);
  }
  // curve -> arcs: every sampled local maximum refined by Newton on the distance
  double worst = *std::max_element(d.begin(), d.end());
  for (std::size_t i = 1; i + 1 < us.size(); ++i)
    if (d[i] >= d[i - 1] && d[i] >= d[i + 1]) worst = std::max(worst, refine_curve_max(c, arcs, us[i - 1], us[i + 1]));
  // arcs -> curve: arc points projected on the curve by Newton, from the nearest sample
  auto arc_to_curve = [&](Vec2 p, double& u) {
    if (!(u >= u0 && u <= u1)) {
      std::size_t best = 0;
      for (std::size_t i = 1; i < pts.size(); ++i)
        if (distance(pts[i], p) < distance(pts[best], p)) best = i;
      u = us[best];
    }
    return project(c, p, u0, u1, u);
  };
  for (const Arc2& a : arcs) {
    constexpr int kArcSamples = 16;
    double prev_u = std::numeric_limits<double>::quiet_NaN();
    double best_f = 0.0, best_d = -1.0;
    for (int i = 0; i <= kArcSamples; ++i) {
      double u = std::numeric_limits<double>::quiet_NaN();  // fresh start from the samples
      const double f = static_cast<double>(i) / kArcSamples;
      const double dd = arc_to_curve(arc_point(a, f), u);
      prev_u = u;
      if (dd > best_d) best_d = dd, best_f = f;
    }
    (void)prev_u;
    // golden-section refinement of the largest sample between its neighbours
    double lo = std::max(0.0, best_f - 1.0 / kArcSamples), hi = std::min(1.0, best_f + 1.0 / kArcSamples);
    const double g = 0.5 * (std::sqrt(5.0) - 1.0);
    for (int it = 0; it < 24; ++it) {
      const double x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo);
      double ua = std::numeric_limits<double>::quiet_NaN(), ub = ua;
      const double d1 = arc_to_curve(arc_point(a, x1), ua), d2 = arc_to_curve(arc_point(a, x2), ub);
      best_d = std::max({best_d, d1, d2});
      if (d1 > d2) hi = x2; else lo = x1;
    }
    worst = std::max(worst, best_d);
  }
  return worst;
}

namespace {

struct Fitter {
  const NurbsCurve& curve;
  PlaneCurve c;
  int normal;
  BiarcOptions opt;
  BiarcFit out;

  void emit(const std::vector<Arc2>& arcs, double dev) {
    append_biarc(out.arcs, arcs);
    ++out.biarcs;
    out.max_deviation_mm = std::max(out.max_deviation_mm, dev);
  }

  void piece(double ua, double ub, Vec2 pa, Vec2 ta, Vec2 pb, Vec2 tb, int depth) {
    std::vector<Arc2> arcs;
    const double um = 0.5 * (ua + ub);
    const Vec2 pm = c.point(um);
    // a piece whose ends meet: a point (emitted as such) or a closed loop (halved below)
    const bool point = distance(pa, pb) <= kTiny && distance(pa, pm) <= kTiny;
    if (const auto bi = make_biarc(pa, ta, pb, tb)) arcs = {bi->first, bi->second};
    else if (point) arcs = {make_segment(pa, pb)};
    double dev = std::numeric_limits<double>::infinity();
    if (!arcs.empty()) {
      dev = curve_deviation(curve, normal, ua, ub, arcs);
      if (dev <= opt.tolerance_mm || point) return emit(arcs, dev);
    }
    if (depth >= opt.max_depth || std::max(distance(pa, pb), distance(pa, pm)) < opt.min_chord_mm) {
      if (arcs.empty()) arcs = {make_segment(pa, pb)}, dev = curve_deviation(curve, normal, ua, ub, arcs);
      out.within_tolerance = false;
      return emit(arcs, dev);
    }
    const Vec2 tm = c.tangent(um, true);
    piece(ua, um, pa, ta, pm, tm, depth + 1);
    piece(um, ub, pm, tm, pb, tb, depth + 1);
  }
};

}  // namespace

BiarcFit fit_biarcs(const NurbsCurve& curve, int normal_axis, const BiarcOptions& options) {
  Fitter f{curve, PlaneCurve{curve.view(), normal_axis}, normal_axis, options, {}};
  if (!validate(curve).empty()) {
    f.out.within_tolerance = false;
    return f.out;
  }
  std::vector<double> bounds{curve.u_min()};
  for (double t : corner_knots(curve)) bounds.push_back(t);
  bounds.push_back(curve.u_max());
  const Vec2 first = to_plane(curve.points.front(), normal_axis), last = to_plane(curve.points.back(), normal_axis);
  for (std::size_t i = 0; i + 1 < bounds.size(); ++i) {
    const double ua = bounds[i], ub = bounds[i + 1];
    const Vec2 pa = i == 0 ? first : f.c.point(ua);
    const Vec2 pb = i + 2 == bounds.size() ? last : f.c.point(ub);
    const Vec2 ta = f.c.tangent(ua, true);
    // the tangent arriving at ub: at a corner knot, just before it
    const Vec2 tb = f.c.tangent(i + 2 == bounds.size() ? ub : std::nextafter(ub, ua), false);
    // a closed piece (a full circle) has no biarc between equal ends: piece() halves it
    f.piece(ua, ub, pa, ta, pb, tb, 0);
  }
  return f.out;
}

}  // namespace pcnc
