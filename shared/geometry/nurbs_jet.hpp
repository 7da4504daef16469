// nurbs_jet.hpp — a NURBS curve's point with its first, second and third derivatives
// (analytic: derivatives of the B-spline basis and the quotient rule on the homogeneous
// curve). nurbs_eval (nurbs.hpp) stops at the second; the ruled-surface theory needs the
// third of the directrix and of the ruling (ruled_surface.hpp). Allocation-free.
#pragma once

#include "geometry/curve_jet.hpp"
#include "geometry/nurbs.hpp"

namespace pcnc {

/// C(u), C', C'', C''' with respect to u; u is clamped to the domain; at an interior knot
/// the span starting there is used (right-hand derivatives). Derivatives above the degree
/// are zero for a polynomial curve.
CurveJet nurbs_jet(const NurbsView& c, double u);

}  // namespace pcnc
