// nurbs_schedule.hpp — the feed schedule of a NURBS move (host preprocessing).
//
// The curve is sampled densely in its parameter. At each sample the speed limit is the
// smallest of: the programmed feed; the chord-error speed (2/T) sqrt(2 rho delta - delta^2)
// at which one sample period's chord deviates delta from a circle of the local curvature
// radius rho; the centripetal limit sqrt(a_n,i / |kappa_i|) per axis (kappa the curvature
// vector, a_n,i the share of axis i's acceleration the normal part may take); each axis's
// velocity limit projected on the tangent. The tangential acceleration varies along the curve:
// at every sample it is what the axes leave after the normal part at that sample's speed and
// curvature (per axis |t_i·a_t + k_i·v²| ≤ A_i, geometry/tangential_budget.hpp), so a bend's
// apex may give nearly all of an axis to the centripetal part and the straights all of it to
// the ramps. Forward and backward passes make each step between samples keep within what both
// samples allow, from the start speed to the end speed. The schedule is cut into the blocks'
// NurbsGeometry::schedule_u/schedule_speed/schedule_accel arrays (at most kMaxFeedSchedule
// points each, never above the dense schedule), and plan_nurbs_blocks() turns a whole curve
// into ready-to-queue blocks.
#pragma once

#include <string>
#include <vector>

#include "ipc/block.hpp"
#include "config/config.hpp"
#include "geometry/nurbs.hpp"
#include "ipc/block_nurbs.hpp"
#include "geometry/vec3.hpp"

namespace pcnc {

/// The default share of an axis's acceleration a bend's centripetal part may take.
constexpr double kNormalAccelShare = 0.7;
/// The share of what the axes leave after the normal part that a sample's tangential
/// acceleration takes (FeedSample::accel): the margin for the tangent and curvature turning
/// between samples and the rt's parameter steps (see nurbs_schedule.cpp).
constexpr double kTangentialAccelMargin = 0.95;
/// The share of one cycle's acceleration (per axis) the velocity step at a kink of the curve
/// may take (geometry/nurbs.hpp kTangentKinkTurn): the schedule caps the speed there to keep it.
constexpr double kKinkStepShare = 0.1;

struct NurbsLimits {
  double feed_mm_s = 0.0;             // programmed path feed
  double period_s = 0.0005;           // interpolation period T
  double chord_tolerance_mm = 0.001;  // delta
  Vec3 axis_velocity_mm_s{};          // per axis velocity limit
  Vec3 axis_accel_mm_s2{};            // per axis acceleration limit
  // Share of each axis's acceleration the centripetal part may take at most (the speed limit
  // of a bend); the tangential acceleration gets what is left at each sample's actual speed.
  // Below 1 so that even a bend's apex keeps some acceleration for braking.
  double normal_accel_share = kNormalAccelShare;
  int samples_per_span = 32;          // dense sampling of each knot span
};

/// Limits from the machine configuration (cycle period, delta, axis limits) and a feed.
NurbsLimits nurbs_limits(const MachineConfig& config, double feed_mm_s);

/// Which limit set a sample's speed (before the acceleration passes).
enum class FeedLimit : std::uint8_t { kFeed, kChord, kCentripetal, kAxisVelocity, kCorner };
const char* to_string(FeedLimit limit);

struct FeedSample {
  double u = 0.0;      // curve parameter
  double s = 0.0;      // arc length from the curve start, mm
  double limit = 0.0;  // speed limit at u before the acceleration passes, mm/s
  double speed = 0.0;  // scheduled speed after the passes, mm/s
  // tangential acceleration allowed here at any speed up to `speed` (a margin below what the
  // axes leave after the normal part), mm/s²
  double accel = 0.0;
  FeedLimit binding = FeedLimit::kFeed;
  bool has_frame = false;  // t and k are set (the curve has a tangent here)
  Vec3 t{}, k{};           // unit tangent, curvature vector (1/mm)
  // At an interior knot the curvature may jump (a quadratic is only C1 there): the frame just
  // before it too. The sample's limits hold on both sides (a block ending here is evaluated
  // from the left, the next one from the right).
  bool has_left = false;
  Vec3 t_left{}, k_left{};
};

struct FeedSchedule {
  std::vector<FeedSample> samples;  // increasing u, first at u_min, last at u_max
  double accel_mm_s2 = 0.0;         // the smallest sample accel (what braking anywhere may use)
  double length_mm = 0.0;           // arc length of the curve
  NurbsLimits limits{};             // what it was planned with
};

/// Plans the dense schedule of a valid curve. v_start and v_end are the speeds at its ends
/// (0 unless the caller joins it to neighbours without stopping); they are capped by the
/// local limits.
FeedSchedule plan_nurbs_feed(const NurbsCurve& curve, const NurbsLimits& limits, double v_start = 0.0,
                             double v_end = 0.0);

/// The dense schedule's speed at u (linear between samples).
double schedule_speed_at(const FeedSchedule& schedule, double u);

/// Writes the part [u0, u1] of the schedule into g.schedule_u/schedule_speed/schedule_accel:
/// every sample when they fit, else kMaxFeedSchedule of them picked where the polyline through
/// them deviates most, their speeds lowered so that the linear interpolation never exceeds the
/// dense schedule, each point's acceleration the smallest of the dense samples from its left
/// to its right neighbour, and re-passed. u0 and u1 must be sample parameters (knots).
void fill_block_schedule(const FeedSchedule& schedule, double u0, double u1, NurbsGeometry& g);

/// A whole NURBS move as ring blocks: validated, split into pieces of at most
/// kMaxNurbsPoints control points (and at corners), each with geometry, schedule, start/end
/// points, length, speed (programmed feed capped by the schedule's maximum), accel,
/// direction cosines and motion class; the block's accel is the smallest of its schedule's
/// accelerations (the rt brakes with it). The block schedules hold the geometric limits
/// (feed, chord error, centripetal, axis velocity, 0 at corners) with the acceleration passes
/// between them but no start or end ramp: the rt's NurbsFollower ramps from the speed it
/// enters with and to the end speed the executor asks for. seq, line and contouring are left for the caller;
/// the caller should let the rt pass the joins between pieces of one curve without
/// stopping (they are tangent continuous) except at corners, which `corner_after` marks.
/// The fields of a NURBS block that follow from its curve (b.nurbs): start and end points,
/// arc length, direction cosines at both ends, and the control polygon's motion class and
/// driving axis with its flag (what the block check recomputes). Schedule, speed and accel
/// are the caller's.
void set_nurbs_block_geometry(Block& b);

struct NurbsBlocks {
  std::string error;                // non-empty: the curve was rejected, no blocks
  std::vector<Block> blocks;
  std::vector<bool> corner_after;   // per block: its end is a corner of the curve
  FeedSchedule schedule;            // the dense schedule of the whole curve (for reports)
};
NurbsBlocks plan_nurbs_blocks(const NurbsCurve& curve, const NurbsLimits& limits);

}  // namespace pcnc
