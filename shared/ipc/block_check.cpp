// block_check.cpp — block validation and the soft-limit test (see block_check.hpp).
#include "ipc/block_check.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "ipc/block_check_util.hpp"
#include "ipc/block_nurbs.hpp"
#include "geometry/plane.hpp"
#include "geometry/probe_contact.hpp"
#include "geometry/tangential_budget.hpp"

namespace pcnc {
namespace {

bool unit(const Vec3& v) { return std::abs(norm(v) - 1.0) < 1e-3; }

// ---- The seed's driving-axis plan and the arc's angular plan, cross-checked against the
// path-length plan (length, speed, accel, geometry) that the executor runs. The rt moves by
// path length; these fields restate the same plan per axis or per radian (docs/gcode.md,
// "Preprocessing"), so a host that computes either wrong is refused here. Each expected
// value is recomputed with the host's rules (host/gcode/preprocessor.cpp); speeds and
// accelerations must agree to 1e-9 relative, positions to motion.block_tolerance_mm.

constexpr double kRel = 1e-9;        // relative tolerance of speeds and accelerations
constexpr double kMovingMm = 1e-9;   // an axis moves when its travel exceeds this (host: kAxisEps)

// |got − want| within kRel of `scale` (false for NaN).
bool agrees(double got, double want, double scale) { return std::abs(got - want) <= kRel * std::abs(scale); }

// Where on a path of `length` a stop from `speed` at `accel` must begin so as to end at rest
// exactly at its end: the braking distance before the end, or the midpoint when the block is
// too short to reach `speed` and stop again (triangular profile).
double stop_begins_at(double length, double speed, double accel) {
  const double braking = speed * speed / (2.0 * accel);
  return 2.0 * braking >= length ? 0.5 * length : length - braking;
}

// Lines and rapids: the driving axis is the one with the largest travel (the first on a tie),
// its flag the sign of that travel; its speed and acceleration are the path's times its
// direction cosine; decel_start is its coordinate where the path's stop must begin.
BlockVerdict check_line_plan(const Block& b, double tol) {
  const Vec3 d = b.end - b.start;
  const double length = norm(d);
  int moving = 0, k = 0;
  for (int i = 0; i < kAxes; ++i) {
    if (std::abs(d[i]) > kMovingMm) ++moving;
    if (std::abs(d[i]) > std::abs(d[k])) k = i;
  }
  if (b.motion_class != static_cast<MotionClass>(moving)) {
    return refuse_block("motion class disagrees with the axes that move", 0, static_cast<double>(b.motion_class));
  }
  if (b.driving_axis != k) return refuse_block("driving axis plan disagrees with the path: driving_axis", k, b.driving_axis);
  if (b.driving_dir != (d[k] < 0.0 ? -1 : 1)) {
    return refuse_block("driving axis plan disagrees with the path: driving_dir", k, b.driving_dir);
  }
  const double u = length > 0.0 ? d[k] / length : 0.0;  // signed direction cosine of the driving axis
  if (!agrees(b.driving_speed, b.speed * std::abs(u), b.speed)) {
    return refuse_block("driving axis plan disagrees with the path: driving_speed", k, b.driving_speed);
  }
  if (!agrees(b.driving_accel, b.accel * std::abs(u), b.accel)) {
    return refuse_block("driving axis plan disagrees with the path: driving_accel", k, b.driving_accel);
  }
  const double decel = b.start[k] + u * stop_begins_at(length, b.speed, b.accel);
  if (!(std::abs(b.decel_start - decel) <= tol)) {
    return refuse_block("driving axis plan disagrees with the path: decel_start", k, b.decel_start);
  }
  return {};
}

// Arcs and helices: with pitch p = helix/|sweep| and rho = sqrt(r² + p²) (the path length per
// radian), angular speed and acceleration are the path's divided by rho, decel_start_angle
// the same stop rule in radians from the start. The driving axis is the normal (helical)
// axis, its speed and acceleration the path's times |helix|/length, decel_start its
// coordinate at decel_start_angle. The tangents at the ends are the direction cosines.
BlockVerdict check_arc_plan(const Block& b, double tol) {
  const ArcGeometry& g = b.arc;
  const int n = g.normal_axis;
  const double turn = std::abs(g.sweep);
  const double pitch = g.helix / turn;
  const double rho = std::sqrt(g.radius * g.radius + pitch * pitch);
  const double length = rho * turn;
  const MotionClass mc = std::abs(g.helix) > kMovingMm ? MotionClass::kSpace : MotionClass::kPlane;
  if (b.motion_class != mc) return refuse_block("motion class disagrees with the axes that move", 0, static_cast<double>(b.motion_class));

  const double w = b.speed / rho, alpha = b.accel / rho;
  if (!agrees(g.angular_speed, w, w)) return refuse_block("arc plan disagrees with the path: angular_speed", n, g.angular_speed);
  if (!agrees(g.angular_accel, alpha, alpha)) {
    return refuse_block("arc plan disagrees with the path: angular_accel", n, g.angular_accel);
  }
  const double decel_angle = stop_begins_at(turn, w, alpha);
  if (!(std::abs(g.decel_start_angle - decel_angle) * rho <= tol)) {
    return refuse_block("arc plan disagrees with the path: decel_start_angle", n, g.decel_start_angle);
  }

  if (b.driving_axis != n) return refuse_block("driving axis plan disagrees with the path: driving_axis", n, b.driving_axis);
  if (b.driving_dir != (g.helix < 0.0 ? -1 : 1)) {
    return refuse_block("driving axis plan disagrees with the path: driving_dir", n, b.driving_dir);
  }
  const double share = std::abs(g.helix) / length;
  if (!agrees(b.driving_speed, b.speed * share, b.speed)) {
    return refuse_block("driving axis plan disagrees with the path: driving_speed", n, b.driving_speed);
  }
  if (!agrees(b.driving_accel, b.accel * share, b.accel)) {
    return refuse_block("driving axis plan disagrees with the path: driving_accel", n, b.driving_accel);
  }
  const double decel = b.start[n] + g.helix * decel_angle / turn;
  if (!(std::abs(b.decel_start - decel) <= tol)) {
    return refuse_block("driving axis plan disagrees with the path: decel_start", n, b.decel_start);
  }

  // Direction cosines: the unit tangents in the direction of travel, sign(sweep)·dp/dθ.
  if (!unit(b.dir_start) || !unit(b.dir_end)) return refuse_block("arc: direction cosines are not unit vectors");
  const auto pa = plane_axes(g.normal_axis);
  const double sign = g.sweep < 0.0 ? -1.0 : 1.0;
  auto tangent = [&](double theta) {
    Vec3 t{0.0, 0.0, 0.0};
    t[pa[0]] = -g.radius * std::sin(theta) * sign;
    t[pa[1]] = g.radius * std::cos(theta) * sign;
    t[n] = pitch;
    return normalized(t);
  };
  if (b.length > 10.0 * tol &&
      (dot(tangent(g.start_angle), b.dir_start) < 0.9999 || dot(tangent(g.start_angle + g.sweep), b.dir_end) < 0.9999)) {
    return refuse_block("arc: direction cosines disagree with the tangents");
  }
  return {};
}

// NURBS: the block's own feed schedule is its plan, so the driving-axis plan holds only the
// axis (the widest extent of the control polygon, the first on a tie) and its flag; its
// speed, acceleration and deceleration start are 0. The motion class counts the axes the
// control polygon spans.
BlockVerdict check_nurbs_plan(const Block& b) {
  const NurbsGeometry& g = b.nurbs;
  Vec3 lo = g.points[0], hi = g.points[0];
  for (int j = 1; j < g.point_count; ++j) {
    for (int i = 0; i < kAxes; ++i) {
      lo[i] = std::min(lo[i], g.points[j][i]);
      hi[i] = std::max(hi[i], g.points[j][i]);
    }
  }
  int moving = 0, k = 0;
  for (int i = 0; i < kAxes; ++i) {
    if (hi[i] - lo[i] > 1e-12) ++moving;
    if (hi[i] - lo[i] > hi[k] - lo[k]) k = i;
  }
  const MotionClass mc = moving <= 1 ? MotionClass::kSingleAxis : static_cast<MotionClass>(moving);
  if (b.motion_class != mc) return refuse_block("motion class disagrees with the axes that move", 0, static_cast<double>(b.motion_class));
  if (b.driving_axis != k) return refuse_block("driving axis plan disagrees with the path: driving_axis", k, b.driving_axis);
  if (b.driving_dir != (b.end[k] >= b.start[k] ? 1 : -1)) {
    return refuse_block("driving axis plan disagrees with the path: driving_dir", k, b.driving_dir);
  }
  if (b.driving_speed != 0.0) return refuse_block("driving axis plan disagrees with the path: driving_speed", k, b.driving_speed);
  if (b.driving_accel != 0.0) return refuse_block("driving axis plan disagrees with the path: driving_accel", k, b.driving_accel);
  if (b.decel_start != 0.0) return refuse_block("driving axis plan disagrees with the path: decel_start", k, b.decel_start);
  return {};
}

// Arc-only checks; the shared part (start, end, travel, speed...) is done by the caller.
BlockVerdict check_arc(const Block& b, const MachineConfig& cfg, double tol) {
  const ArcGeometry& g = b.arc;
  if (!all_finite(g.center) || !std::isfinite(g.radius) || !std::isfinite(g.start_angle) || !std::isfinite(g.sweep) ||
      !std::isfinite(g.helix) || !std::isfinite(g.angular_speed) || !std::isfinite(g.angular_accel) ||
      !std::isfinite(g.decel_start_angle)) {
    return refuse_block("arc: non-finite number");
  }
  if (g.normal_axis > 2) return refuse_block("arc: normal axis is not 0, 1 or 2", 0, g.normal_axis);
  if (!(g.radius > 0.0)) return refuse_block("arc: radius <= 0", 0, g.radius);
  if (!(std::abs(g.sweep) > 0.0) || std::abs(g.sweep) > 2.0 * std::numbers::pi * 1000.0) {
    return refuse_block("arc: sweep is zero or absurd", 0, g.sweep);
  }
  const int a1 = plane_axes(g.normal_axis)[0], a2 = plane_axes(g.normal_axis)[1];
  const int an = g.normal_axis;
  const double rtol = cfg.gcode.arc_radius_tolerance_mm + cfg.gcode.arc_radius_tolerance_rel * g.radius + tol;
  const double r0 = std::hypot(b.start[a1] - g.center[a1], b.start[a2] - g.center[a2]);
  const double r1 = std::hypot(b.end[a1] - g.center[a1], b.end[a2] - g.center[a2]);
  if (std::abs(r0 - g.radius) > rtol) return refuse_block("arc: start point is not on the radius", a1, r0 - g.radius);
  if (std::abs(r1 - g.radius) > rtol) return refuse_block("arc: end point is not on the radius", a1, r1 - g.radius);
  if (std::abs(g.center[an] - b.start[an]) > tol) return refuse_block("arc: centre is not at the start level", an);
  if (std::abs(b.end[an] - b.start[an] - g.helix) > tol) {
    return refuse_block("arc: helix does not match end minus start on the normal axis", an, g.helix);
  }
  // Angles: the stated start angle and start + sweep must match the points (as arc length).
  const double th0 = std::atan2(b.start[a2] - g.center[a2], b.start[a1] - g.center[a1]);
  const double th1 = std::atan2(b.end[a2] - g.center[a2], b.end[a1] - g.center[a1]);
  auto wrap = [](double a) { return std::remainder(a, 2.0 * std::numbers::pi); };
  if (std::abs(wrap(th0 - g.start_angle)) * g.radius > rtol) return refuse_block("arc: start angle does not match start point");
  if (std::abs(wrap(th1 - (g.start_angle + g.sweep))) * g.radius > rtol) {
    return refuse_block("arc: start angle + sweep does not match end point");
  }
  const double len = std::hypot(g.radius * g.sweep, g.helix);
  if (std::abs(len - b.length) > tol + 1e-6 * len + rtol * std::abs(g.sweep)) {
    return refuse_block("arc: length inconsistent with radius, sweep and helix", 0, b.length - len);
  }
  // The arc's bulge must stay inside the travel: check each in-plane extreme the sweep reaches.
  const double rmax = std::max(r0, r1);
  const double lo = std::min(g.start_angle, g.start_angle + g.sweep);
  const double hi = std::max(g.start_angle, g.start_angle + g.sweep);
  const double half_pi = std::numbers::pi / 2.0;
  for (double k = std::ceil(lo / half_pi); k * half_pi <= hi && k - std::ceil(lo / half_pi) < 5; k += 1.0) {
    Vec3 p = b.start;
    p[a1] = g.center[a1] + rmax * std::cos(k * half_pi);
    p[a2] = g.center[a2] + rmax * std::sin(k * half_pi);
    const int ax = outside_travel(p, cfg, tol);
    if (ax >= 0) return refuse_block("arc: bulges outside the travel", ax, p[ax]);
  }
  return check_arc_plan(b, tol);
}

// NURBS-only checks (allocation-free): array sizes, knots, weights, the curve's ends, the
// feed schedule, and the control polygon inside the travel (a NURBS curve with positive
// weights lies in the convex hull of its control points, so the curve is then inside too).
BlockVerdict check_nurbs(const Block& b, const MachineConfig& cfg, double tol) {
  const NurbsGeometry& g = b.nurbs;
  const int p = g.degree, n = g.point_count;
  if (p < 1 || p > kMaxNurbsDegree) return refuse_block("nurbs: degree out of range", 0, p);
  if (n < p + 1 || n > kMaxNurbsPoints) return refuse_block("nurbs: control point count out of range", 0, n);
  if (g.knot_count != n + p + 1) return refuse_block("nurbs: knot count is not points + degree + 1", 0, g.knot_count);
  for (int i = 0; i < g.knot_count; ++i) {
    if (!std::isfinite(g.knots[i])) return refuse_block("nurbs: non-finite knot");
    if (i > 0 && g.knots[i] < g.knots[i - 1]) return refuse_block("nurbs: knots decrease", 0, g.knots[i]);
  }
  if (!(g.knots[p] < g.knots[n])) return refuse_block("nurbs: empty parameter domain");
  for (int i = 0; i < n; ++i) {
    if (!all_finite(g.points[i])) return refuse_block("nurbs: non-finite control point");
    if (!(std::isfinite(g.weights[i]) && g.weights[i] > 0.0)) return refuse_block("nurbs: weight not positive", 0, g.weights[i]);
    if (int ax = outside_travel(g.points[i], cfg, tol); ax >= 0) {
      return refuse_block("nurbs: control polygon leaves the travel", ax, g.points[i][ax]);
    }
  }
  const int m = g.schedule_count;
  if (m < 1 || m > kMaxFeedSchedule) return refuse_block("nurbs: feed schedule size out of range", 0, m);
  for (int i = 0; i < m; ++i) {
    if (!std::isfinite(g.schedule_u[i]) || !std::isfinite(g.schedule_speed[i]) || g.schedule_speed[i] < 0.0) {
      return refuse_block("nurbs: bad feed schedule entry", 0, g.schedule_speed[i]);
    }
    if (i > 0 && !(g.schedule_u[i] > g.schedule_u[i - 1])) return refuse_block("nurbs: feed schedule not increasing in u");
    if (!std::isfinite(g.schedule_accel[i]) || !(g.schedule_accel[i] > 0.0)) {
      return refuse_block("nurbs: feed schedule acceleration not positive", 0, g.schedule_accel[i]);
    }
    if (b.accel > g.schedule_accel[i] * (1.0 + kRel)) return refuse_block("nurbs: block acceleration above its schedule's", 0, b.accel);
  }
  const NurbsView view = view_of(g);
  const double slack = 1e-12 * (view.u_max() - view.u_min());
  if (g.schedule_u[0] < view.u_min() - slack || g.schedule_u[m - 1] > view.u_max() + slack) {
    return refuse_block("nurbs: feed schedule outside the curve's parameter range");
  }
  // The points' arc lengths: from 0 to the block's length, and between two points at least
  // the chord (since they end at the length, each is then at most the chord plus what the
  // whole block's length exceeds the sum of the chords by).
  if (std::abs(g.schedule_s[0]) > tol || std::abs(g.schedule_s[m - 1] - b.length) > tol) {
    return refuse_block("nurbs: feed schedule arc lengths do not run from 0 to the block length", 0, g.schedule_s[m - 1]);
  }
  // Every schedule point within the axes' limits: speed along the tangent, and tangential
  // plus normal acceleration (|t_i|·a + |k_i|·v² <= A_i, geometry/tangential_budget.hpp).
  Vec3 last{};
  for (int j = 0; j < m; ++j) {
    const CurveFrame f = nurbs_frame(view, g.schedule_u[j]);
    if (!std::isfinite(g.schedule_s[j]) ||
        (j > 0 && !(g.schedule_s[j] - g.schedule_s[j - 1] >= norm(f.p - last) * (1.0 - 1e-9) - 1e-12))) {
      return refuse_block("nurbs: feed schedule arc length shorter than the chord", 0, g.schedule_s[j]);
    }
    last = f.p;
    if (!f.ok) continue;
    const double v = g.schedule_speed[j], a = g.schedule_accel[j];
    for (int i = 0; i < kAxes; ++i) {
      if (std::abs(f.t[i]) * v > cfg.axes[i].max_velocity_mm_s * (1.0 + 1e-9) + 1e-9) {
        return refuse_block("nurbs: feed schedule above an axis's velocity limit", i, v);
      }
    }
    for (int i = 0; i < kAxes; ++i) {
      const AxisConfig& ax = cfg.axes[i];
      if (std::abs(f.t[i]) * a + std::abs(f.k[i]) * v * v > ax.max_accel_mm_s2 * (1.0 + 1e-9) + 1e-9) {
        return refuse_block("nurbs: feed schedule above an axis's acceleration limit", i, a);
      }
    }
  }
  const Vec3 c0 = nurbs_point(view, view.u_min()), c1 = nurbs_point(view, view.u_max());
  for (int i = 0; i < kAxes; ++i) {
    if (std::abs(c0[i] - b.start[i]) > tol) return refuse_block("nurbs: curve does not begin at the block start", i, c0[i]);
    if (std::abs(c1[i] - b.end[i]) > tol) return refuse_block("nurbs: curve does not end at the block end", i, c1[i]);
  }
  if (b.length + tol < norm(b.end - b.start)) return refuse_block("nurbs: length shorter than the chord", 0, b.length);
  if (!unit(b.dir_start) || !unit(b.dir_end)) return refuse_block("nurbs: direction cosines are not unit vectors");
  return check_nurbs_plan(b);
}

}  // namespace

int outside_travel(const Vec3& p, const MachineConfig& cfg, double tol) {
  for (int i = 0; i < kAxes; ++i) {
    if (!(p[i] >= cfg.axes[i].travel_min_mm - tol && p[i] <= cfg.axes[i].travel_max_mm + tol)) return i;
  }
  return -1;
}

BlockVerdict check_block(const Block& b, const Vec3& expected_start, std::uint64_t expected_seq,
                         const MachineConfig& cfg) {
  if (b.seq != expected_seq) {
    return {FaultCode::kSequence, b.seq < expected_seq ? "block repeated (sequence number went back)"
                                                       : "block missing (gap in sequence numbers)",
            0, static_cast<double>(b.seq)};
  }
  if (b.optional_stop > 1 || (b.optional_stop != 0 && b.kind != BlockKind::kPause)) {
    return refuse_block("optional_stop is set on a block that is not a pause, or is not 0 or 1", 0, b.optional_stop);
  }
  const double tol = cfg.motion.block_tolerance_mm;
  switch (b.kind) {
    case BlockKind::kDwell:
      if (!std::isfinite(b.dwell_s) || b.dwell_s < 0.0 || b.dwell_s > 1e6) return refuse_block("dwell: time not in [0, 1e6] s", 0, b.dwell_s);
      return {};
    case BlockKind::kPause:
    case BlockKind::kEnd:
      return {};
    case BlockKind::kNurbs:
    case BlockKind::kRuled:
    case BlockKind::kRapid:
    case BlockKind::kLine:
    case BlockKind::kArc:
      break;
    default:
      return refuse_block("unknown block kind", 0, static_cast<double>(static_cast<int>(b.kind)));
  }
  if (!all_finite(b.start) || !all_finite(b.end) || !std::isfinite(b.length) || !std::isfinite(b.speed) ||
      !std::isfinite(b.accel) || !all_finite(b.dir_start) || !all_finite(b.dir_end)) {
    return refuse_block("non-finite number in a motion block");
  }
  if (!(b.path_tolerance_mm >= 0.0f && b.path_tolerance_mm <= 1.0f)) {
    return refuse_block("path tolerance outside 0 .. 1 mm", 0, static_cast<double>(b.path_tolerance_mm));
  }
  for (int i = 0; i < kAxes; ++i) {
    if (std::abs(b.start[i] - expected_start[i]) > tol) {
      return refuse_block("start does not continue from the previous end", i, b.start[i] - expected_start[i]);
    }
  }
  // under TCP start and end are the tool tip in workpiece coordinates: check_rotary checks the joints
  const bool tcp = b.rotary.tcp != 0 && (b.kind == BlockKind::kLine || b.kind == BlockKind::kRapid || b.kind == BlockKind::kRuled);
  const bool angular = b.rotary.angular != 0 && (b.kind == BlockKind::kLine || b.kind == BlockKind::kRapid);
  if (int ax = tcp ? -1 : outside_travel(b.start, cfg, tol); ax >= 0) return refuse_block("start point outside the travel", ax, b.start[ax]);
  if (int ax = tcp ? -1 : outside_travel(b.end, cfg, tol); ax >= 0) return refuse_block("end point outside the travel", ax, b.end[ax]);
  if (!(b.length >= 0.0)) return refuse_block("negative length", 0, b.length);
  if (!(b.speed > 0.0)) return refuse_block("speed <= 0 on a motion block", 0, b.speed);
  if (!(b.accel > 0.0)) return refuse_block("acceleration <= 0 on a motion block", 0, b.accel);
  if (b.probe_rule != kProbeNone) {
    if (b.kind != BlockKind::kLine || b.probe_rule > kProbeAway) return refuse_block("probe rule on a block that is not a line, or unknown", 0, b.probe_rule);
    if (!cfg.probe.present) return refuse_block("probing move on a machine without a probe ([probe] in the config)");
    const double v_max = probe_speed_limit(b.accel, cfg.cycle_period_s(), cfg.probe.model.overtravel_mm);
    if (b.speed > v_max * (1.0 + 1e-9)) return refuse_block("probing speed would not stop within the probe's overtravel", 0, b.speed);
  }
  if (b.kind == BlockKind::kArc) return check_arc(b, cfg, tol);
  if (b.kind == BlockKind::kNurbs) return check_nurbs(b, cfg, tol);
  if (b.kind == BlockKind::kRuled) return check_ruled(b, cfg, tol);
  const double chord = norm(b.end - b.start);
  if (angular) return check_line_plan(b, tol);  // its length is an angle (check_rotary)
  if (std::abs(chord - b.length) > tol) return refuse_block("length inconsistent with start and end", 0, b.length - chord);
  if (b.length > 0.0) {
    if (!unit(b.dir_start) || !unit(b.dir_end)) return refuse_block("direction cosines are not unit vectors");
    const Vec3 u = normalized(b.end - b.start);
    if (chord > 10.0 * tol && (dot(u, b.dir_start) < 0.9999 || dot(u, b.dir_end) < 0.9999)) {
      return refuse_block("direction cosines disagree with start and end");
    }
  }
  return check_line_plan(b, tol);
}

}  // namespace pcnc
