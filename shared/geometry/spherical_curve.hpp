// spherical_curve.hpp — the ruling of a ruled surface as a curve on the unit sphere, with its
// first three derivatives. Two forms:
//  - spherical coordinates, the seed paper's eq. (10): e = (cos(theta) sin(phi),
//    sin(theta) sin(phi), cos(phi)), with theta(u), phi(u) a planar Ferguson or NURBS curve
//    (eqs. 16-17; stored as (theta, phi, 0) in a CurveJet);
//  - a vector curve r(u) (a NURBS or Hermite curve of tool vectors) normalised: e = r/|r|,
//    which has no pole (theta is undefined where phi = 0, a vertical tool).
// Also the conversion of a unit vector back to (theta, phi) and unwrapping of theta along a
// list so that set points interpolate without a 2 pi jump. Pure functions.
#pragma once

#include <vector>

#include "geometry/curve_jet.hpp"
#include "geometry/vec3.hpp"

namespace pcnc {

/// e(u) and its derivatives from the angles: angles.p = (theta, phi, 0) and its derivatives
/// (radians, per unit u). The z components of angles are ignored.
CurveJet sphere_point_jet(const CurveJet& angles);

/// e = r/|r| and its derivatives from a vector curve r(u) (|r| > 0).
CurveJet unit_vector_jet(const CurveJet& r);

/// (theta, phi, 0) of a unit vector: theta = atan2(y, x) in (-pi, pi], phi = acos(z) in
/// [0, pi]. At the poles theta is 0.
Vec3 sphere_angles(const Vec3& e);

/// The angles of each unit vector, theta unwrapped along the list (consecutive values
/// differ by at most pi), so that Ferguson curves through them take the short way round.
std::vector<Vec3> sphere_angles_unwrapped(const std::vector<Vec3>& unit_vectors);

}  // namespace pcnc
