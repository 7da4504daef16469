// hermite_curve.hpp — Ferguson (cubic Hermite) curves, the seed paper's eq. (12):
// p(u) = [u^3 u^2 u 1] M [p0 p1 T0 T1]^T, 0 <= u <= 1, with the analytic first, second and
// third derivatives. The ruled-surface model (ruled_surface.hpp) uses one for the directrix
// (tool positions) and one in (theta, phi, 0) for the ruling's spherical curve (its eq. 17:
// a planar curve is the space curve with z = 0).
//
// A HermiteSpline joins segments end to end; its parameter runs over [0, count], segment i
// over [i, i+1] (the seed's set points S_i at the integers). Pure: no I/O, no allocation in
// evaluation.
#pragma once

#include <vector>

#include "geometry/curve_jet.hpp"
#include "geometry/vec3.hpp"

namespace pcnc {

/// One Ferguson segment: end points p0, p1 and end tangents t0 = p'(0), t1 = p'(1).
struct HermiteSegment {
  Vec3 p0{};
  Vec3 p1{};
  Vec3 t0{};
  Vec3 t1{};
};

/// p(u) and its first three derivatives for u in [0, 1] (extrapolated outside, as the
/// polynomial is).
CurveJet hermite_jet(const HermiteSegment& s, double u);

/// The polynomial coefficients of a segment: p(u) = a0 + a1 u + a2 u^2 + a3 u^3 (the product
/// M S_p of eq. 12, constant term first).
struct HermiteCoefficients {
  Vec3 a0{}, a1{}, a2{}, a3{};
};
HermiteCoefficients hermite_coefficients(const HermiteSegment& s);

/// Read-only view of consecutive segments: what evaluation works on (a spline's vector or,
/// later, a block's fixed array).
struct HermiteView {
  const HermiteSegment* segments = nullptr;
  int count = 0;
  double u_max() const { return count; }
};

/// The jet of the piecewise curve at u in [0, count] (clamped); at an interior integer the
/// segment that starts there is used (right-hand derivatives). An empty view gives zeros.
CurveJet hermite_jet(const HermiteView& c, double u);

/// Segments through `points` with the given tangents at them (per unit of the segment
/// parameter): segment i runs from points[i] to points[i+1]. Sizes must match (>= 2 points).
std::vector<HermiteSegment> hermite_through(const std::vector<Vec3>& points, const std::vector<Vec3>& tangents);

/// Catmull–Rom tangents for the set points: (p[i+1] - p[i-1]) / 2 inside, one-sided at the
/// ends (the usual choice when a program lists points and no tangents). C1 joins.
std::vector<Vec3> catmull_rom_tangents(const std::vector<Vec3>& points);

}  // namespace pcnc
