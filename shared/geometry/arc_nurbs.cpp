// arc_nurbs.cpp — a chain of arcs as one rational quadratic NURBS (see arc_nurbs.hpp).
#include "geometry/arc_nurbs.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "geometry/plane.hpp"

namespace pcnc {
namespace {

struct PlaneFrame {
  int a, b;          // the plane's axes, in angle order
  double r, alpha0;  // the start's radius and angle about the center
  double r_end;      // the end's radius (the program's end point may sit a rounding off r)

  // The radius at angle phi: from the start's to the end's, linearly with the angle (the arc as
  // the rt runs it, rt/motion/path.hpp).
  double radius_at(double phi, double sweep) const { return sweep != 0.0 ? r + (r_end - r) * (phi / sweep) : r; }
};

PlaneFrame frame_of(const PlaneArc& arc) {
  const auto ax = plane_axes(arc.normal_axis);
  const auto a = static_cast<std::size_t>(ax[0]), b = static_cast<std::size_t>(ax[1]);
  const double da = arc.start[a] - arc.center[a], db = arc.start[b] - arc.center[b];
  const double r_end = std::hypot(arc.end[a] - arc.center[a], arc.end[b] - arc.center[b]);
  return {ax[0], ax[1], std::hypot(da, db), std::atan2(db, da), r_end};
}

// The point at angle phi from the start, at `scale` times the radius there (1: on the arc).
Vec3 at_angle(const PlaneArc& arc, const PlaneFrame& f, double phi, double scale) {
  Vec3 p = arc.start;  // the normal axis keeps the start's level
  const double ang = f.alpha0 + phi, r = scale * f.radius_at(phi, arc.sweep);
  p[static_cast<std::size_t>(f.a)] = arc.center[static_cast<std::size_t>(f.a)] + r * std::cos(ang);
  p[static_cast<std::size_t>(f.b)] = arc.center[static_cast<std::size_t>(f.b)] + r * std::sin(ang);
  return p;
}

}  // namespace

Vec3 plane_arc_point(const PlaneArc& a, double phi) { return at_angle(a, frame_of(a), phi, 1.0); }

Vec3 plane_arc_tangent(const PlaneArc& arc, double phi) {
  const PlaneFrame f = frame_of(arc);
  const double ang = f.alpha0 + phi, dir = arc.sweep >= 0.0 ? 1.0 : -1.0;
  Vec3 t{};
  t[static_cast<std::size_t>(f.a)] = -dir * std::sin(ang);
  t[static_cast<std::size_t>(f.b)] = dir * std::cos(ang);
  return t;
}

double plane_arc_length(const PlaneArc& a) {
  const PlaneFrame f = frame_of(a);
  return 0.5 * (f.r + f.r_end) * std::abs(a.sweep);
}

NurbsCurve arc_chain_nurbs(const std::vector<PlaneArc>& arcs, std::vector<double>* arc_start_u) {
  NurbsCurve c;
  c.degree = 2;
  if (arc_start_u) arc_start_u->clear();
  double u = 0.0;
  c.knots.assign(3, 0.0);
  for (const PlaneArc& arc : arcs) {
    if (arc_start_u) arc_start_u->push_back(u);
    const PlaneFrame f = frame_of(arc);
    const int pieces = std::max(1, static_cast<int>(std::ceil(std::abs(arc.sweep) / (0.5 * std::numbers::pi) - 1e-12)));
    const double step = arc.sweep / pieces;
    const double w = std::cos(0.5 * step);
    const double len = plane_arc_length(arc) / pieces;
    if (c.points.empty()) {
      c.points.push_back(arc.start);
      c.weights.push_back(1.0);
    }
    for (int k = 0; k < pieces; ++k) {
      const double phi0 = k * step;
      c.points.push_back(at_angle(arc, f, phi0 + 0.5 * step, 1.0 / w));  // where the end tangents meet
      c.weights.push_back(w);
      c.points.push_back(k + 1 == pieces ? arc.end : at_angle(arc, f, phi0 + step, 1.0));
      c.weights.push_back(1.0);
      u += len;
      c.knots.push_back(u);
      c.knots.push_back(u);
    }
  }
  // clamp the end: the last knot appears degree + 1 = 3 times
  c.knots.push_back(u);
  return c;
}

}  // namespace pcnc
