// intersect.hpp — exact intersections and distances of plane pieces (segments and arcs, see
// offset.hpp): line/line, line/circle and circle/circle intersection points, whether a point
// lies within an arc's sweep, and the minimum distance between two pieces (found at their
// end points, at the critical points along the normal, or 0 where they cross). The cutter
// compensation's gouge check measures with it how far a tool path comes into the contour.
#pragma once

#include "geometry/offset.hpp"

namespace pcnc {

/// Up to two intersection points.
struct Hits {
  int count = 0;
  Vec2 p[2]{};
};

/// The lines through a0->a1 and b0->b1 (not segments); none when parallel.
Hits intersect_lines(Vec2 a0, Vec2 a1, Vec2 b0, Vec2 b1);
/// The line through a0->a1 and the circle about c of radius r.
Hits intersect_line_circle(Vec2 a0, Vec2 a1, Vec2 c, double r);
/// Two circles; none when concentric, apart or nested.
Hits intersect_circles(Vec2 c0, double r0, Vec2 c1, double r1);

/// True when the direction from an arc's center to q lies within the arc's sweep.
bool within_sweep(const Piece& arc, Vec2 q);

/// Nearest point of a piece to q, and the distance.
Vec2 closest_point(const Piece& p, Vec2 q);
double distance(const Piece& p, Vec2 q);

/// The minimum distance between two pieces (0 when they touch or cross); `at` (optional) is
/// the point of `a` where it is reached.
double distance(const Piece& a, const Piece& b, Vec2* at = nullptr);

}  // namespace pcnc
