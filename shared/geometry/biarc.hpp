// biarc.hpp — biarc fitting and arc-spline offsets: the geometry of cutter compensation on
// free-form contours (seed paper: cutter-compensation-biarc.txt; docs/biarc-fit.md).
//
// A line segment's offset direction comes from its two rounded end points, so CAM polylines
// of short segments s offset with an error d = 2 r eps / s. An arc offsets exactly about its
// centre. So a free-form contour is approximated by biarcs (two tangent arcs) within a
// tolerance, and the arcs are offset exactly.
//
// API (all pure; plane coordinates of vec2.hpp; lengths in mm):
//   make_biarc(p0, t0, p1, t1)           one biarc between two points with unit tangents
//   fit_biarcs(curve, normal_axis, opt)  a planar NURBS -> tangent-continuous arcs within
//                                        opt.tolerance_mm, measured on the curve (Newton)
//   fit_biarcs_polyline(points, opt)     a smooth run of short G1 moves -> arcs through (within
//                                        the tolerance of) every programmed point
//   curve_deviation(curve, ...)          the measured deviation between a curve and arcs
//   offset_chain(arcs, d)                exact offset of a chain, corners rounded
//   remove_loops(arcs, R, side)          the seed's twice-offset loop removal for a tool radius
// Arc2 (arc2.hpp) is one arc or segment: start, end, centre, radius, signed sweep (> 0 = G3);
// offset_arc (arc2.hpp) offsets one exactly and says when it collapses. arc_moves
// (host/gcode/biarc_moves.hpp) turns arcs into the pipeline's Moves.
#pragma once

#include <cstddef>
#include <optional>
#include <vector>

#include "geometry/arc2.hpp"
#include "geometry/nurbs.hpp"
#include "geometry/vec2.hpp"

namespace pcnc {

/// Two arcs (either may be a straight segment) meeting tangentially at first.end ==
/// second.start; first.start, second.end and the end tangents are the given ones exactly.
struct Biarc {
  Arc2 first;
  Arc2 second;
};

/// The biarc from p0 (unit tangent t0) to p1 (unit tangent t1) whose tangent lengths
/// alpha = |Q1 - p0| and beta = |p1 - Q2| have the ratio beta / alpha = `ratio` (1: equal, the
/// classical choice and LinuxCNC's). Empty when none exists with positive lengths (p0 == p1,
/// or the tangents point back against the chord so that no finite pair joins them).
std::optional<Biarc> make_biarc(Vec2 p0, Vec2 t0, Vec2 p1, Vec2 t1, double ratio = 1.0);

/// Appends a biarc's arcs to a chain: zero-length arcs dropped, two collinear segments
/// (a biarc between aligned tangents) as one.
void append_biarc(std::vector<Arc2>& chain, const std::vector<Arc2>& arcs);

/// Exact distance from p to the nearest of `arcs` (infinity when empty); q its nearest point.
double nearest_on_arcs(const std::vector<Arc2>& arcs, Vec2 p, Vec2* q = nullptr);

struct BiarcOptions {
  double tolerance_mm = 0.001;  // maximum deviation between the curve and its arcs
  int max_depth = 30;           // bisections of one piece before it is accepted as is
  double min_chord_mm = 1e-4;   // a piece this short is accepted as is (an unreachable tolerance
                                // must not bisect the whole curve 2^max_depth times)
};

/// Arcs that replace a curve. Consecutive arcs share end points exactly; they are tangent
/// continuous except where the curve itself has a corner.
struct BiarcFit {
  std::vector<Arc2> arcs;
  std::size_t biarcs = 0;         // number of biarcs (an arc pair; a degenerate one may be 1 arc)
  double max_deviation_mm = 0.0;  // the largest deviation measured (two-sided, see curve_deviation)
  bool within_tolerance = true;   // false when a piece reached max_depth or min_chord_mm above the tolerance
};

/// Fits biarcs to the NURBS curve seen in the plane normal to `normal_axis` (2 = G17 XY,
/// 1 = G18 ZX, 0 = G19 YZ); the curve's coordinate along the normal is ignored (callers
/// check it is constant). The curve is split at its corner knots; each piece is bisected in
/// its parameter (the seed's algorithm) until the biarc between the piece's end points and
/// end tangents is within the tolerance. Never throws on a valid curve; a closed curve
/// (a full circle) and a straight one are handled.
BiarcFit fit_biarcs(const NurbsCurve& curve, int normal_axis, const BiarcOptions& options = {});

/// The deviation between the curve on [u0, u1] and `arcs`, both ways: the largest distance
/// from a curve point to the arcs (sampled, then each local maximum refined by safeguarded
/// Newton iteration on d/du |C(u) - Q(u)|^2 / 2 = 0, Q the exact nearest arc point) and the
/// largest distance from an arc point to the curve (Newton projection on the curve).
double curve_deviation(const NurbsCurve& curve, int normal_axis, double u0, double u1, const std::vector<Arc2>& arcs);

/// A run of short G1 moves as the underlying smooth curve. Tangents at the points come from
/// a local least-squares quadratic over the neighbouring points (robust to the 0.5 um rounding
/// of CAM output); biarcs join points with those tangents, spans halved until every
/// programmed point between is within the tolerance of the arcs (exact distance) and every
/// arc stays within tolerance + sagitta of the programmed segments (the chords' own distance
/// from the smooth curve, estimated from the tangents). First and last points kept exactly.
struct PolylineFit : BiarcFit {
  double max_point_deviation_mm = 0.0;    // programmed points to the arcs (<= tolerance)
  double max_segment_deviation_mm = 0.0;  // arcs to the programmed segments (measured)
  double max_sagitta_mm = 0.0;            // the allowance above: largest chord sagitta
};
PolylineFit fit_biarcs_polyline(const std::vector<Vec2>& points, const BiarcOptions& options = {});

/// The offset of a chain by d to the left of travel (d < 0: right). Each piece is offset
/// exactly (offset_arc); where consecutive offsets do not meet (a corner of the chain) an arc
/// of radius |d| about the corner joins them: it rounds a convex corner and runs backwards
/// at a concave one (a loop that remove_loops cuts). Collapsed pieces are kept as loci.
std::vector<Arc2> offset_chain(const std::vector<Arc2>& chain, double d);

/// The seed's twice-offset step: the contour a tool of radius R on `side` (+1 left = G41,
/// -1 right = G42) can follow without its offset tangling. The chain is offset by R to that
/// side, the offset's self-intersections found (exact arc/arc, arc/line, line/line), the loops
/// between them cut, and the result offset back (a kept part of a piece's offset is the same
/// fraction range of the piece); the corners left by the cuts become arcs of radius R about
/// the crossings (the tool's own rounding). Chains without loops come back unchanged. A closed
/// chain (its end at its start) is walked round, so loops across its closing point are cut
/// too, and comes back closed, starting at its start point; when that point is cut off (in a
/// loop, or a concave corner rounded) the chain comes back unchanged with `unresolved` set.
struct LoopRemoval {
  std::vector<Arc2> arcs;
  int loops_removed = 0;
  int unresolved = 0;          // > 0: parts the tool still cannot follow (backwards offset pieces no crossing
                               // cut off), or the chain came back unchanged because its start was cut off
                               // or what the walk kept was not a valid offset
  double max_change_mm = 0.0;  // largest distance of the new contour from the old one
};
LoopRemoval remove_loops(const std::vector<Arc2>& chain, double tool_radius, int side);

}  // namespace pcnc
