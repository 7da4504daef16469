// arc2.cpp — arcs and segments in a plane: construction, evaluation, distance, offset.
#include "geometry/arc2.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace pcnc {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;
constexpr double kLineSagitta = 1e-10;  // mm: an arc flatter than this is a segment

// Angle of p about the arc's centre, measured from its start in the arc's direction,
// in [0, 2 pi).
double angle_from_start(const Arc2& a, Vec2 p) {
  const Vec2 u0 = a.start - a.centre, u = p - a.centre;
  double t = std::atan2(cross(u0, u), dot(u0, u));
  if (a.sweep < 0.0) t = -t;
  if (t < 0.0) t += kTwoPi;
  return t;
}

}  // namespace

Arc2 make_segment(Vec2 a, Vec2 b) {
  Arc2 s;
  s.start = a;
  s.end = b;
  s.centre = 0.5 * (a + b);
  s.line = true;
  return s;
}

Arc2 make_arc_about(Vec2 centre, Vec2 start, double sweep) {
  Arc2 a;
  a.line = false;
  a.centre = centre;
  a.start = start;
  a.radius = distance(start, centre);
  a.sweep = sweep;
  const Vec2 u = start - centre;
  const double c = std::cos(sweep), s = std::sin(sweep);
  a.end = std::abs(std::abs(sweep) - kTwoPi) < 1e-15 ? start : centre + Vec2{c * u.x - s * u.y, s * u.x + c * u.y};
  return a;
}

Arc2 make_arc_from_tangent(Vec2 p, Vec2 t, Vec2 q) {
  const Vec2 w = q - p;
  const double len = norm(w);
  if (len == 0.0) return make_segment(p, q);
  const double half = std::atan2(cross(t, w), dot(t, w));  // angle from t to the chord
  // sagitta of the arc on this chord: (len / 2) tan(|half| / 2)
  if (std::abs(half) < 0.5 * std::numbers::pi && 0.5 * len * std::tan(0.5 * std::abs(half)) < kLineSagitta)
    return make_segment(p, q);
  Arc2 a;
  a.line = false;
  a.start = p;
  a.end = q;
  const double signed_r = dot(w, w) / (2.0 * cross(t, w));  // > 0: centre on the left
  a.radius = std::abs(signed_r);
  a.centre = p + signed_r * perp(t);
  a.sweep = 2.0 * half;
  return a;
}

double arc_length(const Arc2& a) { return a.line ? distance(a.start, a.end) : a.radius * std::abs(a.sweep); }

Vec2 arc_point(const Arc2& a, double f) {
  if (f == 0.0) return a.start;
  if (f == 1.0) return a.end;
  if (a.line) return a.start + f * (a.end - a.start);
  const Vec2 u = a.start - a.centre;
  const double c = std::cos(f * a.sweep), s = std::sin(f * a.sweep);
  return a.centre + Vec2{c * u.x - s * u.y, s * u.x + c * u.y};
}

Vec2 arc_tangent(const Arc2& a, double f) {
  if (a.line) return normalized(a.end - a.start);
  const Vec2 r = normalized(arc_point(a, f) - a.centre);
  return a.sweep > 0.0 ? perp(r) : -perp(r);
}

double arc_curvature(const Arc2& a) {
  if (a.line || a.radius <= 0.0) return 0.0;
  return a.sweep > 0.0 ? 1.0 / a.radius : -1.0 / a.radius;
}

double arc_fraction_of(const Arc2& a, Vec2 p) {
  if (a.line) {
    const Vec2 d = a.end - a.start;
    const double dd = dot(d, d);
    return dd > 0.0 ? dot(p - a.start, d) / dd : 0.0;
  }
  if (a.sweep == 0.0) return 0.0;
  const double t = angle_from_start(a, p);
  const double s = std::abs(a.sweep);
  if (t <= s) return t / s;
  // outside: report the nearer end as < 0 or > 1
  const double before = kTwoPi - t;  // angle back from the start
  return (t - s < before) ? t / s : -before / s;
}

double arc_distance(const Arc2& a, Vec2 p, double* fraction) {
  double f = arc_fraction_of(a, p);
  f = std::clamp(f, 0.0, 1.0);
  double d;
  if (!a.line && f > 0.0 && f < 1.0) {
    d = std::abs(distance(p, a.centre) - a.radius);
  } else {
    d = distance(p, arc_point(a, f));
    if (!a.line) {  // an end: the nearer one (the fraction's rounding may pick the far one)
      const double d0 = distance(p, a.start), d1 = distance(p, a.end);
      f = d0 <= d1 ? 0.0 : 1.0;
      d = std::min(d0, d1);
    }
  }
  if (fraction) *fraction = f;
  return d;
}

Arc2 reversed(const Arc2& a) {
  Arc2 r = a;
  r.start = a.end;
  r.end = a.start;
  r.sweep = -a.sweep;
  return r;
}

Arc2 sub_arc(const Arc2& a, double f0, double f1) {
  Arc2 s = a;
  s.start = arc_point(a, f0);
  s.end = arc_point(a, f1);
  if (!a.line) s.sweep = a.sweep * (f1 - f0);
  return s;
}

ArcOffset offset_arc(const Arc2& a, double d) {
  ArcOffset o;
  o.arc = a;
  if (a.line) {
    const Vec2 n = perp(normalized(a.end - a.start));
    o.arc.start = a.start + d * n;
    o.arc.end = a.end + d * n;
    o.arc.centre = 0.5 * (o.arc.start + o.arc.end);
    return o;
  }
  // left of travel is toward the centre on a counter-clockwise arc
  const double k = a.sweep > 0.0 ? a.radius - d : a.radius + d;  // new signed radius
  const double scale = a.radius > 0.0 ? k / a.radius : 0.0;
  o.arc.start = a.centre + scale * (a.start - a.centre);
  o.arc.end = a.centre + scale * (a.end - a.centre);
  o.arc.radius = std::abs(k);
  o.collapsed = k <= 0.0;
  return o;
}

}  // namespace pcnc
