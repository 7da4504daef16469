// arc_intersect.hpp — exact intersections of two arcs or segments in a plane (circle/circle,
// line/circle, line/line in closed form), with the fractions along each where they cross.
// Used by the loop removal of arc-spline offsets (biarc_loops.cpp).
#pragma once

#include <vector>

#include "geometry/arc2.hpp"

namespace pcnc {

struct ArcCrossing {
  double fa = 0.0;  // fraction along a, in [0, 1]
  double fb = 0.0;  // fraction along b
  Vec2 point{};
};

/// The points common to a and b (0, 1 or 2; overlapping collinear or concentric pieces give
/// none). A tangent contact counts once. Fractions within about 1e-9 of an end are accepted.
std::vector<ArcCrossing> intersect(const Arc2& a, const Arc2& b);

}  // namespace pcnc
