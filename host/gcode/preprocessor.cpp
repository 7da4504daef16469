// preprocessor.cpp — kinematic plan of one move: speeds and accelerations projected on the axes.
#include "gcode/preprocessor.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "gcode/rotary_move.hpp"
#include "geometry/probe_contact.hpp"

namespace pcnc {
namespace {

constexpr double kNoLimit = std::numeric_limits<double>::infinity();
constexpr double kAxisEps = 1e-9;  // mm: displacements below this do not count as moving

void plan_line(const Move& m, const MachineConfig& cfg, Block& b) {
  const Vec3 d = m.end - m.start;
  const double length = norm(d);
  b.length = length;
  const Vec3 u = length > 0.0 ? (1.0 / length) * d : Vec3{0.0, 0.0, 0.0};
  b.dir_start = b.dir_end = u;

  double speed = m.kind == MoveKind::kRapid ? (cfg.motion.rapid_speed_mm_s > 0.0 ? cfg.motion.rapid_speed_mm_s : kNoLimit)
                                            : m.feed_mm_s;
  double accel = kNoLimit;
  int moving = 0;
  int drive = 0;
  for (int i = 0; i < kAxes; ++i) {
    const auto k = static_cast<std::size_t>(i);
    const double ui = std::fabs(u[k]);
    if (std::fabs(d[k]) > kAxisEps) ++moving;
    if (std::fabs(d[k]) > std::fabs(d[static_cast<std::size_t>(drive)])) drive = i;
    if (ui > 0.0) {
      speed = std::min(speed, cfg.axes[k].max_velocity_mm_s / ui);
      accel = std::min(accel, cfg.axes[k].max_accel_mm_s2 / ui);
    }
  }
  if (!std::isfinite(speed)) speed = 0.0;
  if (!std::isfinite(accel)) accel = 0.0;
  b.motion_class = static_cast<MotionClass>(moving);
  b.speed = speed;
  b.accel = accel;
  const auto dk = static_cast<std::size_t>(drive);
  b.driving_axis = static_cast<std::uint8_t>(drive);
  b.driving_dir = d[dk] < 0.0 ? -1 : 1;
  const double ud = std::fabs(u[dk]);
  b.driving_speed = speed * ud;
  b.driving_accel = accel * ud;
  const double s = decel_start_distance(length, speed, accel);
  b.decel_start = m.start[dk] + u[dk] * s;
}

void plan_arc(const Move& m, const MachineConfig& cfg, Block& b) {
  const int n = m.normal_axis;
  const auto pa = plane_axes(n);
  const auto a0 = static_cast<std::size_t>(pa[0]);
  const auto a1 = static_cast<std::size_t>(pa[1]);
  const auto nk = static_cast<std::size_t>(n);
  const double r = m.radius;
  const double sweep = m.sweep;
  const double helix = m.end[nk] - m.start[nk];
  const double theta0 = std::atan2(m.start[a1] - m.center[a1], m.start[a0] - m.center[a0]);
  const double pitch = helix / std::fabs(sweep);        // mm along the normal per radian
  const double rho = std::sqrt(r * r + pitch * pitch);  // |dp/dtheta|
  const double length = rho * std::fabs(sweep);

  ArcGeometry& g = b.arc;
  g.center = m.center;
  g.radius = r;
  g.start_angle = theta0;
  g.sweep = sweep;
  g.helix = helix;
  g.normal_axis = static_cast<std::uint8_t>(n);
  b.length = length;
  b.motion_class = std::fabs(helix) > kAxisEps ? MotionClass::kSpace : MotionClass::kPlane;

  // Velocity: axis a0 moves with v*(r/rho)*|sin|, a1 with v*(r/rho)*|cos|, the normal with v*|pitch|/rho.
  const double s_max = max_abs_sin(theta0, sweep);
  const double c_max = max_abs_cos(theta0, sweep);
  double v_axes = kNoLimit;  // what the axes allow on this arc, whatever the feed
  if (s_max > 0.0) v_axes = std::min(v_axes, cfg.axes[a0].max_velocity_mm_s * rho / (r * s_max));
  if (c_max > 0.0) v_axes = std::min(v_axes, cfg.axes[a1].max_velocity_mm_s * rho / (r * c_max));
  if (std::fabs(pitch) > 0.0) v_axes = std::min(v_axes, cfg.axes[nk].max_velocity_mm_s * rho / std::fabs(pitch));
  // Centripetal acceleration v^2 * r / rho^2 within a share of what the in-plane axes allow along
  // the sweep, each carrying its own part (shared/geometry/arc_limits.hpp).
  const ArcPlane plane = arc_plane(cfg.axes[a0].max_accel_mm_s2, cfg.axes[a1].max_accel_mm_s2, theta0, sweep);
  if (r > 0.0) v_axes = std::min(v_axes, std::sqrt(kArcCentripetalShare * arc_centripetal_limit(plane) * rho * rho / r));
  const double speed = std::min(m.feed_mm_s, v_axes);
  // Tangential acceleration: what the plane has left at the block's top speed (feed override
  // included), shared/geometry/arc_limits.hpp; the full limit along the normal.
  const double v_top = std::min(v_axes, kArcMaxFeedOverride * speed);
  const double vp_top = v_top * r / rho;
  double accel = r > 0.0 ? arc_plane_tangential_accel(plane, vp_top * vp_top / r) * rho / r : kNoLimit;
  if (std::fabs(pitch) > 0.0) accel = std::min(accel, cfg.axes[nk].max_accel_mm_s2 * rho / std::fabs(pitch));
  if (!std::isfinite(accel)) accel = 0.0;
  b.speed = speed;
  b.accel = accel;

  g.angular_speed = rho > 0.0 ? speed / rho : 0.0;
  g.angular_accel = rho > 0.0 ? accel / rho : 0.0;
  g.decel_start_angle = decel_start_distance(std::fabs(sweep), g.angular_speed, g.angular_accel);

  // Driving axis of an arc: its helical (normal) axis.
  b.driving_axis = static_cast<std::uint8_t>(n);
  b.driving_dir = helix < 0.0 ? -1 : 1;
  const double un = length > 0.0 ? std::fabs(helix) / length : 0.0;
  b.driving_speed = speed * un;
  b.driving_accel = accel * un;
  b.decel_start = m.start[nk] + (std::fabs(sweep) > 0.0 ? helix * g.decel_start_angle / std::fabs(sweep) : 0.0);

  // Unit tangents: direction of travel is sign(sweep) * dp/dtheta.
  const double dirsign = sweep < 0.0 ? -1.0 : 1.0;
  auto tangent = [&](double theta) {
    Vec3 t{0.0, 0.0, 0.0};
    t[a0] = -r * std::sin(theta) * dirsign;
    t[a1] = r * std::cos(theta) * dirsign;
    t[nk] = pitch * (helix != 0.0 ? 1.0 : 0.0) * (std::fabs(sweep) > 0.0 ? 1.0 : 0.0);
    return normalized(t);
  };
  b.dir_start = tangent(theta0);
  b.dir_end = tangent(theta0 + sweep);
}

// A straight move that turns a rotary joint, TCP off: the joints run linearly with the path
// parameter, so each joint's speed and acceleration are the path's times its travel per unit of
// path; an angular move (the linear axes stand still) runs on the joints' Euclidean travel in rad,
// at the feed in rad/s (F in deg/min). A TCP move gets its joint-space plan from tcp_move.hpp
// (in the pipeline, which reports its errors). Either way the block keeps M21 and the path
// tolerance: the rt passes its junctions at the joint-space junction speed (rt/motion/junction.hpp;
// an angular block stops).
void plan_rotary(const Move& m, const MachineConfig& cfg, Block& b) {
  b.rotary.end = m.rot_end;
  if (!moves_rotary(m)) return;
  if (m.tcp) return;
  const bool angular = angular_move(m);
  if (angular) {
    b.rotary.angular = 1;
    b.length = angular_length(m, cfg);
    b.speed = m.kind == MoveKind::kRapid ? kNoLimit : m.feed_mm_s;
    b.accel = kNoLimit;
  }
  for (int i = 0; i < kRotaryJoints; ++i) {
    const auto k = static_cast<std::size_t>(i);
    const double share = std::fabs(m.rot_end[k] - m.rot_start[k]) / b.length;  // rad per path unit
    if (!(share > 0.0) || !cfg.rotary[k]) continue;
    b.speed = std::min(b.speed, cfg.rotary[k]->max_velocity_rad_s / share);
    b.accel = std::min(b.accel, cfg.rotary[k]->max_accel_rad_s2 / share);
  }
  restate_line_plan(m, b);
}

}  // namespace

void restate_line_plan(const Move& m, Block& b) {
  const Vec3 d = m.end - m.start;
  const double chord = norm(d);
  const auto dk = static_cast<std::size_t>(b.driving_axis);
  const double u = chord > 1e-9 ? d[dk] / chord : 0.0;
  b.driving_speed = b.speed * std::fabs(u);
  b.driving_accel = b.accel * std::fabs(u);
  b.decel_start = m.start[dk] + u * decel_start_distance(b.length, b.speed, b.accel);
}

double decel_start_distance(double length, double speed, double accel) {
  if (!(accel > 0.0) || !(speed > 0.0)) return length;
  const double stop = speed * speed / (2.0 * accel);
  if (2.0 * stop >= length) return 0.5 * length;
  return length - stop;
}

Block make_block(const Move& m, const MachineConfig& cfg) {
  Block b{};
  make_block_into(m, cfg, b);
  return b;
}

void make_block_into(const Move& m, const MachineConfig& cfg, Block& b) {
  // Every field but the NURBS arrays, reset to its default.
  b.seq = 0;
  b.kind = BlockKind::kLine;
  b.motion_class = MotionClass::kNone;
  b.optional_stop = 0;
  b.length = b.speed = b.accel = 0.0;
  b.driving_axis = 0;
  b.driving_dir = 1;
  for (auto& p : b.pad0_) p = 0;
  b.probe_rule = 0;
  b.path_tolerance_mm = m.contouring ? static_cast<float>(m.path_tolerance_mm) : 0.0f;
  b.driving_speed = b.driving_accel = b.decel_start = 0.0;
  b.dir_start = b.dir_end = Vec3{0.0, 0.0, 0.0};
  b.dwell_s = 0.0;
  b.arc = ArcGeometry{};
  b.nurbs.point_count = b.nurbs.knot_count = b.nurbs.schedule_count = 0;
  b.nurbs.degree = 0;
  b.rotary = RotaryMotion{};
  b.rotary.start = b.rotary.end = m.rot_start;
  b.line = static_cast<std::uint32_t>(m.line > 0 ? m.line : 0);
  b.start = m.start;
  b.end = m.end;
  b.contouring = m.contouring ? 1 : 0;
  switch (m.kind) {
    case MoveKind::kRapid:
      b.kind = BlockKind::kRapid;
      plan_line(m, cfg, b);
      plan_rotary(m, cfg, b);
      break;
    case MoveKind::kLine:
      b.kind = BlockKind::kLine;
      plan_line(m, cfg, b);
      if (m.probe_rule != 0) {
        // a probing move: the feed capped so that the stop after contact fits in the probe's
        // overtravel (docs/probe.md); the rt's block check holds it to that
        b.probe_rule = m.probe_rule;
        const double v_max = probe_speed_limit(b.accel, cfg.cycle_period_s(), cfg.probe.model.overtravel_mm);
        if (b.speed > v_max) {
          Move capped = m;
          capped.feed_mm_s = v_max;
          plan_line(capped, cfg, b);
        }
      }
      plan_rotary(m, cfg, b);
      break;
    case MoveKind::kArc:
      b.kind = BlockKind::kArc;
      plan_arc(m, cfg, b);
      break;
    case MoveKind::kDwell:
      b.kind = BlockKind::kDwell;
      b.dwell_s = m.dwell_s;
      break;
    case MoveKind::kPause:
      b.kind = BlockKind::kPause;
      b.optional_stop = m.optional_stop ? 1 : 0;
      break;
    case MoveKind::kEnd: b.kind = BlockKind::kEnd; break;
    case MoveKind::kNurbs:
      // A NURBS move becomes several blocks: plan_nurbs_move (host/nurbs_move.hpp). Here it
      // stays an empty NURBS block, which the rt refuses: never a silent wrong move.
      b.kind = BlockKind::kNurbs;
      break;
    case MoveKind::kRuled:
      // likewise: a ruled piece's blocks are plan_ruled_move's (host/ruled_move.hpp)
      b.kind = BlockKind::kRuled;
      break;
  }
}

}  // namespace pcnc
