// arc2.hpp — one element of an arc spline in a working plane: a circular arc or, where the
// curvature vanishes, a straight segment. Exact evaluation, nearest-point distance, the
// exact offset (radius -/+ d about the same centre) and sub-arcs. Pure, plane coordinates
// (vec2.hpp): a positive sweep is counter-clockwise, G3, in every plane.
#pragma once

#include "geometry/vec2.hpp"

namespace pcnc {

/// A circular arc (line == false) or a straight segment (line == true) from start to end.
/// For an arc: centre, radius > 0 (0 only for an offset that collapsed to a point) and the
/// signed sweep in radians (> 0 counter-clockwise = G3, < 0 clockwise = G2, |sweep| <= 2 pi;
/// a full circle has start == end and |sweep| = 2 pi). A segment has sweep 0, radius 0.
struct Arc2 {
  Vec2 start{};
  Vec2 end{};
  Vec2 centre{};
  double radius = 0.0;
  double sweep = 0.0;
  bool line = true;

  bool ccw() const { return sweep > 0.0; }
};

/// The straight segment a -> b.
Arc2 make_segment(Vec2 a, Vec2 b);

/// The arc that leaves p along the unit direction t and ends at q (sweep 2x the angle from t
/// to the chord; up to a full turn less than 2 pi). A segment when q lies on the line of t
/// ahead of p within about 1e-10 mm of sagitta, or when q == p.
Arc2 make_arc_from_tangent(Vec2 p, Vec2 t, Vec2 q);

/// The arc about `centre` from `start` through the signed angle `sweep` (end computed).
Arc2 make_arc_about(Vec2 centre, Vec2 start, double sweep);

double arc_length(const Arc2& a);

/// The point at fraction f in [0, 1] of the length (f = 0 gives start, f = 1 end, exactly).
Vec2 arc_point(const Arc2& a, double f);

/// Unit tangent (direction of travel) at fraction f.
Vec2 arc_tangent(const Arc2& a, double f);
inline Vec2 start_tangent(const Arc2& a) { return arc_tangent(a, 0.0); }
inline Vec2 end_tangent(const Arc2& a) { return arc_tangent(a, 1.0); }

/// Signed curvature (1/mm, > 0 turning left); 0 for a segment.
double arc_curvature(const Arc2& a);

/// The fraction of the arc's length at which the point of its circle (or line) at the
/// direction of p lies, unclamped: < 0 or > 1 when outside the arc. For a segment the
/// projection of p on its line.
double arc_fraction_of(const Arc2& a, Vec2 p);

/// Exact distance from p to the arc (or segment), and the fraction of its nearest point.
double arc_distance(const Arc2& a, Vec2 p, double* fraction = nullptr);

/// The same path travelled the other way.
Arc2 reversed(const Arc2& a);

/// The part between fractions f0 < f1 (exact: same centre and radius).
Arc2 sub_arc(const Arc2& a, double f0, double f1);

/// The offset of an arc or segment by d to the LEFT of the direction of travel (d < 0: to
/// the right). G41 puts the tool centre at d = +r, G42 at d = -r. An arc keeps its centre
/// and sweep, its radius becomes R - d (counter-clockwise) or R + d (clockwise).
/// `collapsed` when that radius is <= 0: the offset passes through the centre (radius 0,
/// a point) or turns inside out (radius |R -/+ d|, travelled against the original
/// direction): a piece a tool of that radius cannot follow; `arc` is still the exact
/// offset locus (what the loop removal needs).
struct ArcOffset {
  Arc2 arc;
  bool collapsed = false;
};
ArcOffset offset_arc(const Arc2& a, double d);

}  // namespace pcnc
