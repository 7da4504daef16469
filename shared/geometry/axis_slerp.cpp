// axis_slerp.cpp — the great-circle arc between two tool axes (axis_slerp.hpp): the angle from
// atan2(|a × b|, a·b), which is accurate near 0 and π, and the unit direction of b across a.
#include "geometry/axis_slerp.hpp"

#include <cmath>
#include <numbers>

namespace pcnc {

AxisSlerp make_axis_slerp(const Vec3& a, const Vec3& b) {
  AxisSlerp s;
  s.from = normalized(a);
  const Vec3 to = normalized(b);
  const double c = dot(s.from, to);
  const Vec3 perp = to - c * s.from;  // b's part across a
  const double pn = norm(perp);
  s.angle = std::atan2(norm(cross(s.from, to)), c);
  if (pn > 1e-12) {
    s.across = (1.0 / pn) * perp;
    return s;
  }
  // equal (angle 0: any across works, it is never used) or opposite (angle π): a fixed perpendicular
  int least = 0;
  for (int i = 1; i < 3; ++i)
    if (std::abs(s.from[i]) < std::abs(s.from[least])) least = i;
  Vec3 e{0.0, 0.0, 0.0};
  e[least] = 1.0;
  s.across = normalized(e - dot(e, s.from) * s.from);
  s.angle = c < 0.0 ? std::numbers::pi : 0.0;
  return s;
}

Vec3 slerp_axis(const AxisSlerp& s, double t) {
  const double phi = t * s.angle;
  return std::cos(phi) * s.from + std::sin(phi) * s.across;
}

Vec3 slerp_axis_d1(const AxisSlerp& s, double t) {
  const double phi = t * s.angle;
  return s.angle * (std::cos(phi) * s.across - std::sin(phi) * s.from);
}

Vec3 slerp_axis_d2(const AxisSlerp& s, double t) { return (-s.angle * s.angle) * slerp_axis(s, t); }

}  // namespace pcnc
