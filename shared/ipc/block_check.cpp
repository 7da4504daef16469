// block_check.cpp — block validation and the soft-limit test (see block_check.hpp).
#include "ipc/block_check.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "ipc/block_nurbs.hpp"
#include "geometry/plane.hpp"

namespace pcnc {
namespace {

bool finite(const Vec3& v) { return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]); }

BlockVerdict bad(const char* reason, int axis = 0, double value = 0.0) {
  return {FaultCode::kBadBlock, reason, static_cast<std::uint8_t>(axis), value};
}

bool unit(const Vec3& v) { return std::abs(norm(v) - 1.0) < 1e-3; }

// Arc-only checks; the shared part (start, end, travel, speed...) is done by the caller.
BlockVerdict check_arc(const Block& b, const MachineConfig& cfg, double tol) {
  const ArcGeometry& g = b.arc;
  if (!finite(g.center) || !std::isfinite(g.radius) || !std::isfinite(g.start_angle) || !std::isfinite(g.sweep) ||
      !std::isfinite(g.helix) || !std::isfinite(g.angular_speed) || !std::isfinite(g.angular_accel) ||
      !std::isfinite(g.decel_start_angle)) {
    return bad("arc: non-finite number");
  }
  if (g.normal_axis > 2) return bad("arc: normal axis is not 0, 1 or 2", 0, g.normal_axis);
  if (!(g.radius > 0.0)) return bad("arc: radius <= 0", 0, g.radius);
  if (!(std::abs(g.sweep) > 0.0) || std::abs(g.sweep) > 2.0 * std::numbers::pi * 1000.0) {
    return bad("arc: sweep is zero or absurd", 0, g.sweep);
  }
  const int a1 = plane_axes(g.normal_axis)[0], a2 = plane_axes(g.normal_axis)[1];
  const int an = g.normal_axis;
  const double rtol = cfg.gcode.arc_radius_tolerance_mm + cfg.gcode.arc_radius_tolerance_rel * g.radius + tol;
  const double r0 = std::hypot(b.start[a1] - g.center[a1], b.start[a2] - g.center[a2]);
  const double r1 = std::hypot(b.end[a1] - g.center[a1], b.end[a2] - g.center[a2]);
  if (std::abs(r0 - g.radius) > rtol) return bad("arc: start point is not on the radius", a1, r0 - g.radius);
  if (std::abs(r1 - g.radius) > rtol) return bad("arc: end point is not on the radius", a1, r1 - g.radius);
  if (std::abs(g.center[an] - b.start[an]) > tol) return bad("arc: centre is not at the start level", an);
  if (std::abs(b.end[an] - b.start[an] - g.helix) > tol) {
    return bad("arc: helix does not match end minus start on the normal axis", an, g.helix);
  }
  // Angles: the stated start angle and start + sweep must match the points (as arc length).
  const double th0 = std::atan2(b.start[a2] - g.center[a2], b.start[a1] - g.center[a1]);
  const double th1 = std::atan2(b.end[a2] - g.center[a2], b.end[a1] - g.center[a1]);
  auto wrap = [](double a) { return std::remainder(a, 2.0 * std::numbers::pi); };
  if (std::abs(wrap(th0 - g.start_angle)) * g.radius > rtol) return bad("arc: start angle does not match start point");
  if (std::abs(wrap(th1 - (g.start_angle + g.sweep))) * g.radius > rtol) {
    return bad("arc: start angle + sweep does not match end point");
  }
  const double len = std::hypot(g.radius * g.sweep, g.helix);
  if (std::abs(len - b.length) > tol + 1e-6 * len + rtol * std::abs(g.sweep)) {
    return bad("arc: length inconsistent with radius, sweep and helix", 0, b.length - len);
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
    if (ax >= 0) return bad("arc: bulges outside the travel", ax, p[ax]);
  }
  return {};
}

// NURBS-only checks (allocation-free): array sizes, knots, weights, the curve's ends, the
// feed schedule, and the control polygon inside the travel (a NURBS curve with positive
// weights lies in the convex hull of its control points, so the curve is then inside too).
BlockVerdict check_nurbs(const Block& b, const MachineConfig& cfg, double tol) {
  const NurbsGeometry& g = b.nurbs;
  const int p = g.degree, n = g.point_count;
  if (p < 1 || p > kMaxNurbsDegree) return bad("nurbs: degree out of range", 0, p);
  if (n < p + 1 || n > kMaxNurbsPoints) return bad("nurbs: control point count out of range", 0, n);
  if (g.knot_count != n + p + 1) return bad("nurbs: knot count is not points + degree + 1", 0, g.knot_count);
  for (int i = 0; i < g.knot_count; ++i) {
    if (!std::isfinite(g.knots[i])) return bad("nurbs: non-finite knot");
    if (i > 0 && g.knots[i] < g.knots[i - 1]) return bad("nurbs: knots decrease", 0, g.knots[i]);
  }
  if (!(g.knots[p] < g.knots[n])) return bad("nurbs: empty parameter domain");
  for (int i = 0; i < n; ++i) {
    if (!finite(g.points[i])) return bad("nurbs: non-finite control point");
    if (!(std::isfinite(g.weights[i]) && g.weights[i] > 0.0)) return bad("nurbs: weight not positive", 0, g.weights[i]);
    if (int ax = outside_travel(g.points[i], cfg, tol); ax >= 0) {
      return bad("nurbs: control polygon leaves the travel", ax, g.points[i][ax]);
    }
  }
  const int m = g.schedule_count;
  if (m < 1 || m > kMaxFeedSchedule) return bad("nurbs: feed schedule size out of range", 0, m);
  for (int i = 0; i < m; ++i) {
    if (!std::isfinite(g.schedule_u[i]) || !std::isfinite(g.schedule_speed[i]) || g.schedule_speed[i] < 0.0) {
      return bad("nurbs: bad feed schedule entry", 0, g.schedule_speed[i]);
    }
    if (i > 0 && !(g.schedule_u[i] > g.schedule_u[i - 1])) return bad("nurbs: feed schedule not increasing in u");
  }
  const NurbsView view = view_of(g);
  const Vec3 c0 = nurbs_point(view, view.u_min()), c1 = nurbs_point(view, view.u_max());
  for (int i = 0; i < kAxes; ++i) {
    if (std::abs(c0[i] - b.start[i]) > tol) return bad("nurbs: curve does not begin at the block start", i, c0[i]);
    if (std::abs(c1[i] - b.end[i]) > tol) return bad("nurbs: curve does not end at the block end", i, c1[i]);
  }
  if (b.length + tol < norm(b.end - b.start)) return bad("nurbs: length shorter than the chord", 0, b.length);
  if (!unit(b.dir_start) || !unit(b.dir_end)) return bad("nurbs: direction cosines are not unit vectors");
  return {};
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
  const double tol = cfg.motion.block_tolerance_mm;
  switch (b.kind) {
    case BlockKind::kDwell:
      if (!std::isfinite(b.dwell_s) || b.dwell_s < 0.0 || b.dwell_s > 1e6) return bad("dwell: time not in [0, 1e6] s", 0, b.dwell_s);
      return {};
    case BlockKind::kPause:
    case BlockKind::kEnd:
      return {};
    case BlockKind::kNurbs:
    case BlockKind::kRapid:
    case BlockKind::kLine:
    case BlockKind::kArc:
      break;
    default:
      return bad("unknown block kind", 0, static_cast<double>(static_cast<int>(b.kind)));
  }
  if (!finite(b.start) || !finite(b.end) || !std::isfinite(b.length) || !std::isfinite(b.speed) ||
      !std::isfinite(b.accel) || !finite(b.dir_start) || !finite(b.dir_end)) {
    return bad("non-finite number in a motion block");
  }
  for (int i = 0; i < kAxes; ++i) {
    if (std::abs(b.start[i] - expected_start[i]) > tol) {
      return bad("start does not continue from the previous end", i, b.start[i] - expected_start[i]);
    }
  }
  if (int ax = outside_travel(b.start, cfg, tol); ax >= 0) return bad("start point outside the travel", ax, b.start[ax]);
  if (int ax = outside_travel(b.end, cfg, tol); ax >= 0) return bad("end point outside the travel", ax, b.end[ax]);
  if (!(b.length >= 0.0)) return bad("negative length", 0, b.length);
  if (!(b.speed > 0.0)) return bad("speed <= 0 on a motion block", 0, b.speed);
  if (!(b.accel > 0.0)) return bad("acceleration <= 0 on a motion block", 0, b.accel);
  if (b.kind == BlockKind::kArc) return check_arc(b, cfg, tol);
  if (b.kind == BlockKind::kNurbs) return check_nurbs(b, cfg, tol);
  const double chord = norm(b.end - b.start);
  if (std::abs(chord - b.length) > tol) return bad("length inconsistent with start and end", 0, b.length - chord);
  if (b.length > 0.0) {
    if (!unit(b.dir_start) || !unit(b.dir_end)) return bad("direction cosines are not unit vectors");
    const Vec3 u = normalized(b.end - b.start);
    if (chord > 10.0 * tol && (dot(u, b.dir_start) < 0.9999 || dot(u, b.dir_end) < 0.9999)) {
      return bad("direction cosines disagree with start and end");
    }
  }
  return {};
}

}  // namespace pcnc
