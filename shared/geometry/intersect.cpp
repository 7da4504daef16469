// intersect.cpp — intersections and distances of plane pieces (see intersect.hpp).
#include "geometry/intersect.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace pcnc {

namespace {
constexpr double kFullTurn = 2.0 * std::numbers::pi;

// Parameter along a segment, clamped to [0, 1].
double seg_param(Vec2 a, Vec2 b, Vec2 q) {
  const Vec2 d = b - a;
  const double l2 = dot(d, d);
  if (!(l2 > 0.0)) return 0.0;
  return std::clamp(dot(q - a, d) / l2, 0.0, 1.0);
}

bool on_segment(Vec2 a, Vec2 b, Vec2 q) {
  const Vec2 d = b - a;
  const double l2 = dot(d, d);
  if (!(l2 > 0.0)) return norm(q - a) < 1e-12;
  const double t = dot(q - a, d) / l2;
  return t >= -1e-12 && t <= 1.0 + 1e-12;
}

bool on_piece(const Piece& p, Vec2 q) { return p.arc ? within_sweep(p, q) : on_segment(p.a, p.b, q); }

}  // namespace

Hits intersect_lines(Vec2 a0, Vec2 a1, Vec2 b0, Vec2 b1) {
  Hits h;
  const Vec2 da = a1 - a0, db = b1 - b0;
  const double den = cross(da, db);
  if (std::fabs(den) <= 1e-300) return h;
  const double t = cross(b0 - a0, db) / den;
  h.count = 1;
  h.p[0] = a0 + t * da;
  return h;
}

Hits intersect_line_circle(Vec2 a0, Vec2 a1, Vec2 c, double r) {
  Hits h;
  const Vec2 d = a1 - a0;
  const double l = norm(d);
  if (!(l > 0.0)) return h;
  const Vec2 u = (1.0 / l) * d;
  const double t0 = dot(c - a0, u);
  const Vec2 foot = a0 + t0 * u;
  const double e = norm(c - foot);
  if (e > r) return h;
  const double s = std::sqrt(std::max(0.0, r * r - e * e));
  h.p[h.count++] = foot - s * u;
  if (s > 0.0) h.p[h.count++] = foot + s * u;
  return h;
}

Hits intersect_circles(Vec2 c0, double r0, Vec2 c1, double r1) {
  Hits h;
  const Vec2 d = c1 - c0;
  const double l = norm(d);
  if (!(l > 0.0) || l > r0 + r1 || l < std::fabs(r0 - r1)) return h;
  const double a = (r0 * r0 - r1 * r1 + l * l) / (2.0 * l);
  const double hh = std::sqrt(std::max(0.0, r0 * r0 - a * a));
  const Vec2 u = (1.0 / l) * d;
  const Vec2 m = c0 + a * u;
  h.p[h.count++] = m + hh * left_normal(u);
  if (hh > 0.0) h.p[h.count++] = m - hh * left_normal(u);
  return h;
}

bool within_sweep(const Piece& arc, Vec2 q) {
  if (std::fabs(arc.sweep) >= kFullTurn - 1e-15) return true;
  const double a0 = angle_of(arc.a - arc.c);
  const double aq = angle_of(q - arc.c);
  double t = arc.sweep >= 0.0 ? aq - a0 : a0 - aq;  // how far along the sweep's direction
  while (t < 0.0) t += kFullTurn;
  while (t >= kFullTurn) t -= kFullTurn;
  const double s = std::fabs(arc.sweep);
  return t <= s + 1e-12 || t >= kFullTurn - 1e-12;
}

Vec2 closest_point(const Piece& p, Vec2 q) {
  if (!p.arc) return p.a + seg_param(p.a, p.b, q) * (p.b - p.a);
  const Vec2 d = q - p.c;
  const double n = norm(d);
  if (n > 0.0) {
    const Vec2 on = p.c + (p.r / n) * d;
    if (within_sweep(p, on)) return on;
  }
  return norm(q - p.a) <= norm(q - p.b) ? p.a : p.b;
}

double distance(const Piece& p, Vec2 q) { return norm(q - closest_point(p, q)); }

double distance(const Piece& a, const Piece& b, Vec2* at) {
  // Crossing: distance 0 at an intersection point that lies on both pieces.
  Hits h;
  if (!a.arc && !b.arc) {
    h = intersect_lines(a.a, a.b, b.a, b.b);
  } else if (a.arc && b.arc) {
    h = intersect_circles(a.c, a.r, b.c, b.r);
  } else {
    const Piece& s = a.arc ? b : a;
    const Piece& c = a.arc ? a : b;
    h = intersect_line_circle(s.a, s.b, c.c, c.r);
  }
  for (int i = 0; i < h.count; ++i) {
    if (on_piece(a, h.p[i]) && on_piece(b, h.p[i])) {
      if (at) *at = h.p[i];
      return 0.0;
    }
  }
  // Otherwise the minimum is at an end point of one piece, or at a pair of interior points
  // joined along both normals (through the arcs' centers).
  double best = 1e300;
  Vec2 best_at = a.a;
  const auto consider = [&](Vec2 pa, Vec2 pb) {
    const double d = norm(pa - pb);
    if (d < best) {
      best = d;
      best_at = pa;
    }
  };
  consider(a.a, closest_point(b, a.a));
  consider(a.b, closest_point(b, a.b));
  consider(closest_point(a, b.a), b.a);
  consider(closest_point(a, b.b), b.b);
  const auto radial_points = [](const Piece& arc, Vec2 dir, Vec2 out[2]) {
    out[0] = arc.c + arc.r * dir;
    out[1] = arc.c - arc.r * dir;
  };
  if (a.arc && b.arc) {
    const Vec2 d = b.c - a.c;
    const double l = norm(d);
    if (l > 0.0) {
      const Vec2 u = (1.0 / l) * d;
      Vec2 pa[2], pb[2];
      radial_points(a, u, pa);
      radial_points(b, u, pb);
      for (const Vec2& x : pa) {
        if (!within_sweep(a, x)) continue;
        for (const Vec2& y : pb) {
          if (within_sweep(b, y)) consider(x, y);
        }
      }
    }
  } else if (a.arc != b.arc) {
    const Piece& s = a.arc ? b : a;
    const Piece& c = a.arc ? a : b;
    const Vec2 foot = closest_point(s, c.c);
    const Vec2 d = foot - c.c;
    const double l = norm(d);
    if (l > 0.0 && on_segment(s.a, s.b, foot)) {
      Vec2 pc[2];
      radial_points(c, (1.0 / l) * d, pc);
      for (const Vec2& x : pc) {
        if (!within_sweep(c, x)) continue;
        if (a.arc) {
          consider(x, foot);
        } else {
          consider(foot, x);
        }
      }
    }
  }
  if (at) *at = best_at;
  return best;
}

}  // namespace pcnc
