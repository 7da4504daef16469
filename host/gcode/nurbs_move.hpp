// nurbs_move.hpp — a NURBS move (G5.2 ... G5.3 or G6.2) in the front-end pipeline
// (gcode/pipeline.hpp): its extreme points for the soft limits and --fit (the preflight
// stage), and its ring blocks (the preprocessor stage).
//
// The curve arrives from the interpreter validated and in machine coordinates. The rt
// accepts a NURBS block only when its control polygon lies inside the travel (the curve lies
// in the polygon's convex hull), so a curve that is inside the travel while its control
// polygon is not is first refined by knot insertion (same curve, same parametrisation) until
// the polygon comes inside too. Then shared/nurbs_schedule plans the feed schedule and cuts
// the curve into ring-sized pieces; the joins inside one curve flow (contouring flag set)
// except at corners of the curve, where the program's M21/M22 decides as at any junction.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "ipc/block.hpp"
#include "config/config.hpp"
#include "gcode/move.hpp"
#include "geometry/nurbs.hpp"

namespace pcnc {

/// Most control points one G5.2/G6.2 curve may have: the host holds one whole curve (and its
/// dense feed schedule, 32 samples per span) in memory, so this bounds the front end's memory.
constexpr int kMaxNurbsCurvePoints = 10000;

/// Density of the feed schedule's sampling (NurbsLimits::samples_per_span): 128 samples per
/// knot span, fewer for long curves so that one curve's dense schedule stays under
/// kMaxScheduleSamples samples (never fewer than the schedule's own default of 32). The
/// schedule takes the speed limit at its samples only, so a sharp curvature peak between two
/// samples is seen late: at 32 per span the trident's 4 um cusp ran 19 % over a 0.01 um chord
/// tolerance (tests/test_nurbs_end_to_end.cpp, FastCubic...), at 128 within it.
constexpr std::size_t kMaxScheduleSamples = 256 * 1024;
constexpr std::size_t kMinSamplesPerSpan = 32;
constexpr std::size_t kMaxSamplesPerSpan = 128;
int schedule_samples_per_span(const NurbsCurve& curve);

/// Points of the curve where a coordinate peaks (C'_axis changes sign inside a knot span,
/// found on a dense sampling of every span and refined by bisection), plus the sample points
/// themselves and both ends: the curve's extents to within the bisection's precision.
void nurbs_extreme_points(const NurbsCurve& curve, std::vector<Vec3>& out);

/// Refines `curve` by knot insertion until every control point lies inside the travel with
/// margin `tol` (mm). Returns "" on success, else why not (the curve itself leaves the
/// travel, or it cannot be done within the point budget).
std::string refine_into_travel(NurbsCurve& curve, const MachineConfig& config, double tol);

/// The control-polygon margin the host aims for: half the rt's block tolerance.
double nurbs_travel_margin(const MachineConfig& config);

/// The ring blocks of a NURBS move: line and contouring flag set (joins inside the curve
/// flow, except at its corners; the last piece carries the program's M21/M22), seq left 0.
/// `error` is non-empty when the curve could not be planned.
struct NurbsMoveBlocks {
  std::string error;
  std::vector<Block> blocks;
};
NurbsMoveBlocks plan_nurbs_move(const Move& move, const MachineConfig& config);

}  // namespace pcnc
