// block_check_ruled.cpp — the ruled block's part of the block check (block_check.hpp): the
// piece's own data (counts, finite numbers, continuity of the Ferguson chains, the schedule),
// its agreement with the block's fields (start, end, length, speed, accel, end tangents, the
// NURBS blocks' driving-axis rule) and with the machine (TCP kinematics). The joints (start
// continuing, end inside the travel, end joints giving the end tip and axis) are
// check_rotary's, as for a straight TCP block. Pure, allocation-free: the rt runs it on every
// block it takes (one arc-length quadrature, 16 evaluations per segment).
#include <algorithm>
#include <cmath>

#include "ipc/block_check.hpp"
#include "ipc/block_check_util.hpp"
#include "ipc/block_ruled.hpp"

namespace pcnc {
namespace {

bool finite_segment(const HermiteSegment& s) { return all_finite(s.p0) && all_finite(s.p1) && all_finite(s.t0) && all_finite(s.t1); }

constexpr double kRuledRel = 1e-9;       // relative agreement of recomputed lengths and speeds
constexpr double kUnitTol = 1e-6;   // the end axes against the ruling's unit vectors

}  // namespace

BlockVerdict check_ruled(const Block& b, const MachineConfig& cfg, double tol) {
  const RuledGeometry& g = b.ruled;
  if (cfg.kinematics.kind == KinematicsKind::kTrivial) return refuse_block("ruled: a ruled block on a machine without 5-axis kinematics");
  if (b.rotary.tcp != 1 || b.rotary.angular != 0) return refuse_block("ruled: a ruled block runs under TCP (tcp 1, angular 0)");
  if (g.segment_count < 1 || g.segment_count > kMaxRuledSegments) return refuse_block("ruled: segment count outside 1 .. 32", 0, g.segment_count);
  if (g.ruling_form != static_cast<std::int32_t>(RulingForm::kVector) && g.ruling_form != static_cast<std::int32_t>(RulingForm::kAngles)) {
    return refuse_block("ruled: unknown ruling form", 0, g.ruling_form);
  }
  if (g.schedule_count < 1 || g.schedule_count > kMaxRuledSchedule) return refuse_block("ruled: schedule count outside 1 .. 33", 0, g.schedule_count);
  const int n = g.segment_count;
  for (int i = 0; i < n; ++i) {
    if (!finite_segment(g.directrix[i]) || !finite_segment(g.ruling[i])) return refuse_block("ruled: non-finite number in a segment", 0, i);
    // positions join (the tangents per unit u differ with the segments' lengths: the model is G1)
    if (i > 0 && norm(g.directrix[i].p0 - g.directrix[i - 1].p1) > tol) {
      return refuse_block("ruled: the directrix's segments do not join", 0, i);
    }
    if (i > 0 && norm(g.ruling[i].p0 - g.ruling[i - 1].p1) > 1e-9) {
      return refuse_block("ruled: the ruling's segments do not join", 0, i);
    }
    if (g.ruling_form == static_cast<std::int32_t>(RulingForm::kVector) && (norm(g.ruling[i].p0) < 0.5 || norm(g.ruling[i].p1) < 0.5)) {
      return refuse_block("ruled: a tool vector at a set point is not near unit length", 0, i);
    }
  }
  if (!std::isfinite(g.length) || !std::isfinite(g.accel) || !std::isfinite(g.start_speed) || !std::isfinite(g.end_speed)) {
    return refuse_block("ruled: non-finite length, acceleration or speed");
  }
  // the schedule: increasing parameters inside the piece, speeds > 0; the block's speed is the largest
  double top = 0.0;
  for (int i = 0; i < g.schedule_count; ++i) {
    const double u = g.schedule_u[i], v = g.schedule_speed[i];
    if (!std::isfinite(u) || !std::isfinite(v) || u < 0.0 || u > n) return refuse_block("ruled: schedule parameter outside the piece", 0, u);
    if (i > 0 && !(u > g.schedule_u[i - 1])) return refuse_block("ruled: schedule parameters do not increase", 0, u);
    if (!(v > 0.0)) return refuse_block("ruled: schedule speed <= 0", 0, v);
    top = std::max(top, v);
  }
  if (std::abs(b.speed - top) > kRuledRel * top) return refuse_block("ruled: block speed is not the schedule's largest speed", 0, b.speed - top);
  if (!(g.accel > 0.0) || std::abs(b.accel - g.accel) > kRuledRel * g.accel) return refuse_block("ruled: block acceleration is not the piece's", 0, b.accel);
  if (g.start_speed < 0.0 || g.start_speed > top * (1.0 + kRuledRel) || g.end_speed < 0.0 || g.end_speed > top * (1.0 + kRuledRel)) {
    return refuse_block("ruled: start or end speed outside 0 .. the block's speed");
  }
  const double len = hermite_arc_length(HermiteView{g.directrix, n});
  if (!(g.length > 0.0) || std::abs(g.length - len) > kRuledRel * len + 1e-12) return refuse_block("ruled: length is not the directrix's arc length", 0, g.length - len);
  if (std::abs(b.length - g.length) > kRuledRel * g.length) return refuse_block("ruled: block length is not the piece's", 0, b.length - g.length);
  // the block's ends and tangents are the directrix's; the TCP axes the ruling's
  const RuledCurves c = curves_of(g);
  const RuledJet j0 = ruled_jet(c, 0.0), j1 = ruled_jet(c, n);
  if (norm(j0.c.p - b.start) > tol) return refuse_block("ruled: start is not the directrix's start", 0, norm(j0.c.p - b.start));
  if (norm(j1.c.p - b.end) > tol) return refuse_block("ruled: end is not the directrix's end", 0, norm(j1.c.p - b.end));
  if (!(norm(j0.c.d1) > 0.0) || !(norm(j1.c.d1) > 0.0)) return refuse_block("ruled: the directrix stands still at an end");
  if (norm(normalized(j0.c.d1) - b.dir_start) > 1e-6 || norm(normalized(j1.c.d1) - b.dir_end) > 1e-6) {
    return refuse_block("ruled: direction cosines are not the directrix's end tangents");
  }
  if (norm(j0.e.p - b.rotary.axis_start) > kUnitTol || norm(j1.e.p - b.rotary.axis_end) > kUnitTol) {
    return refuse_block("ruled: the TCP tool axes are not the ruling's ends");
  }
  const RuledExtent e = ruled_extent(g);
  const MotionClass mc = e.moving <= 1 ? MotionClass::kSingleAxis : static_cast<MotionClass>(e.moving);
  if (b.motion_class != mc) return refuse_block("motion class disagrees with the axes that move", 0, static_cast<double>(b.motion_class));
  const int k = e.widest;
  if (b.driving_axis != k) return refuse_block("driving axis plan disagrees with the path: driving_axis", k, b.driving_axis);
  if (b.driving_dir != (b.end[k] >= b.start[k] ? 1 : -1)) return refuse_block("driving axis plan disagrees with the path: driving_dir", k, b.driving_dir);
  if (b.driving_speed != 0.0 || b.driving_accel != 0.0 || b.decel_start != 0.0) {
    return refuse_block("driving axis plan disagrees with the path: a ruled block carries only the axis and its flag", k);
  }
  return {};
}

}  // namespace pcnc
