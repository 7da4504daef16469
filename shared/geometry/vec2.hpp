// vec2.hpp — a point or direction in a working plane (plane coordinates, mm): what biarcs,
// arcs and their offsets are computed in. Plane coordinates are (p[a0], p[a1]) with
// {a0, a1} = plane_axes(normal) (plane.hpp), so a positive angle is G3 in every plane.
#pragma once

#include <cmath>

#include "geometry/plane.hpp"
#include "geometry/vec3.hpp"

namespace pcnc {

struct Vec2 {
  double x = 0.0;
  double y = 0.0;
};

inline constexpr Vec2 operator+(Vec2 a, Vec2 b) { return {a.x + b.x, a.y + b.y}; }
inline constexpr Vec2 operator-(Vec2 a, Vec2 b) { return {a.x - b.x, a.y - b.y}; }
inline constexpr Vec2 operator-(Vec2 a) { return {-a.x, -a.y}; }
inline constexpr Vec2 operator*(double s, Vec2 a) { return {s * a.x, s * a.y}; }
inline constexpr Vec2 operator*(Vec2 a, double s) { return {s * a.x, s * a.y}; }
inline constexpr double dot(Vec2 a, Vec2 b) { return a.x * b.x + a.y * b.y; }
/// z of the 3-D cross product: > 0 when b is counter-clockwise from a.
inline constexpr double cross(Vec2 a, Vec2 b) { return a.x * b.y - a.y * b.x; }
/// a turned by +90 degrees (the left normal of a direction of travel).
inline constexpr Vec2 perp(Vec2 a) { return {-a.y, a.x}; }
inline double norm(Vec2 a) { return std::hypot(a.x, a.y); }
inline double distance(Vec2 a, Vec2 b) { return norm(a - b); }
/// Unit vector along a; the zero vector stays zero.
inline Vec2 normalized(Vec2 a) {
  const double n = norm(a);
  return n > 0.0 ? (1.0 / n) * a : Vec2{};
}
/// The unit vector at angle t (radians) from the plane's first axis.
inline Vec2 unit_at(double t) { return {std::cos(t), std::sin(t)}; }

/// A 3-D point's coordinates in the plane normal to `normal_axis` (2 = G17, 1 = G18, 0 = G19).
inline Vec2 to_plane(const Vec3& p, int normal_axis) {
  const auto ax = plane_axes(normal_axis);
  return {p[static_cast<std::size_t>(ax[0])], p[static_cast<std::size_t>(ax[1])]};
}
/// The 3-D point with plane coordinates q and `level` along the normal axis.
inline Vec3 from_plane(Vec2 q, int normal_axis, double level) {
  const auto ax = plane_axes(normal_axis);
  Vec3 p{};
  p[static_cast<std::size_t>(normal_axis)] = level;
  p[static_cast<std::size_t>(ax[0])] = q.x;
  p[static_cast<std::size_t>(ax[1])] = q.y;
  return p;
}

}  // namespace pcnc
