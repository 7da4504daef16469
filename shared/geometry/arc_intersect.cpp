// arc_intersect.cpp — closed-form intersections of arcs and segments. See arc_intersect.hpp.
#include "geometry/arc_intersect.hpp"

#include <algorithm>
#include <cmath>

namespace pcnc {
namespace {

constexpr double kEnd = 1e-9;  // fraction slack at the ends

bool inside(double f) { return f >= -kEnd && f <= 1.0 + kEnd; }

// Points of the circle (c, r) on the line p + t d (d not normalised): t values.
int line_circle(Vec2 p, Vec2 d, Vec2 c, double r, double t[2]) {
  const double a = dot(d, d);
  if (!(a > 0.0)) return 0;
  const Vec2 w = p - c;
  const double b = dot(w, d), cc = dot(w, w) - r * r;
  double disc = b * b - a * cc;
  const double scale = std::max(b * b, std::abs(a * cc));
  if (disc < -1e-14 * scale) return 0;
  if (disc <= 1e-14 * scale) {
    t[0] = -b / a;
    return 1;
  }
  disc = std::sqrt(disc);
  t[0] = (-b - disc) / a;
  t[1] = (-b + disc) / a;
  return 2;
}

void add(std::vector<ArcCrossing>& out, const Arc2& a, const Arc2& b, Vec2 q) {
  const double fa = arc_fraction_of(a, q), fb = arc_fraction_of(b, q);
  if (!inside(fa) || !inside(fb)) return;
  // on an arc, the fraction test is angular: the point must also be on the circle
  out.push_back({std::clamp(fa, 0.0, 1.0), std::clamp(fb, 0.0, 1.0), q});
}

}  // namespace

std::vector<ArcCrossing> intersect(const Arc2& a, const Arc2& b) {
  std::vector<ArcCrossing> out;
  if (a.line && b.line) {
    const Vec2 da = a.end - a.start, db = b.end - b.start;
    const double den = cross(da, db);
    if (std::abs(den) <= 1e-15 * norm(da) * norm(db)) return out;  // parallel
    const Vec2 w = b.start - a.start;
    const double fa = cross(w, db) / den, fb = cross(w, da) / den;
    if (inside(fa) && inside(fb)) out.push_back({std::clamp(fa, 0.0, 1.0), std::clamp(fb, 0.0, 1.0), a.start + fa * da});
    return out;
  }
  if (a.line != b.line) {
    const Arc2& l = a.line ? a : b;
    const Arc2& c = a.line ? b : a;
    if (!(c.radius > 0.0)) return out;
    double t[2];
    const int n = line_circle(l.start, l.end - l.start, c.centre, c.radius, t);
    for (int i = 0; i < n; ++i) {
      const Vec2 q = l.start + t[i] * (l.end - l.start);
      add(out, a, b, q);
    }
    return out;
  }
  if (!(a.radius > 0.0) || !(b.radius > 0.0)) return out;
  const Vec2 d = b.centre - a.centre;
  const double dist = norm(d);
  if (!(dist > 1e-12)) return out;  // concentric
  const double ra = a.radius, rb = b.radius;
  if (dist > ra + rb + 1e-12 * (ra + rb) || dist < std::abs(ra - rb) - 1e-12 * (ra + rb)) return out;
  const double x = (dist * dist + ra * ra - rb * rb) / (2.0 * dist);  // along d from a's centre
  const double h2 = ra * ra - x * x;
  const Vec2 u = (1.0 / dist) * d;
  const Vec2 m = a.centre + x * u;
  if (h2 <= 1e-14 * ra * ra) {
    add(out, a, b, m);
    return out;
  }
  const double h = std::sqrt(h2);
  add(out, a, b, m + h * perp(u));
  add(out, a, b, m - h * perp(u));
  return out;
}

}  // namespace pcnc
