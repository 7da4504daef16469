// curve_jet.hpp — a point of a parametric curve with its first three derivatives (the "jet"
// to third order), the value every ruled-surface function is built from: the directrix c(u)
// and the ruling e(u) are each handed around as a CurveJet at one parameter u. Also the
// scalar version for a function of u (the spin angle, an angle of a spherical curve).
#pragma once

#include "geometry/vec3.hpp"

namespace pcnc {

/// x(u), dx/du, d2x/du2, d3x/du3 at one parameter u.
struct CurveJet {
  Vec3 p{};
  Vec3 d1{};
  Vec3 d2{};
  Vec3 d3{};
};

/// f(u), f', f'', f''' of a scalar function at one parameter u.
struct ScalarJet {
  double f = 0.0;
  double d1 = 0.0;
  double d2 = 0.0;
  double d3 = 0.0;
};

/// The scalar triple product a . (b x c) = det[a b c].
inline constexpr double det3(const Vec3& a, const Vec3& b, const Vec3& c) { return dot(a, cross(b, c)); }

}  // namespace pcnc
