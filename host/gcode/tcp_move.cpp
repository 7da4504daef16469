// tcp_move.cpp — the joint-space plan of a TCP move (see tcp_move.hpp).
#include "gcode/tcp_move.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "config/joint_map.hpp"
#include "gcode/preprocessor.hpp"
#include "gcode/rotary_move.hpp"
#include "geometry/tcp_path.hpp"

namespace pcnc {
namespace {

constexpr double kTcpStill = 1e-9;     // mm: the tip stands still
constexpr double kSameRad = 1e-6;   // rad: joints agree

std::string deg(double rad) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", rad * kDegPerRad);
  return buf;
}

}  // namespace

JointLimits joint_limits(const MachineConfig& cfg) {
  JointLimits l;
  for (int i = 0; i < kAxes; ++i) {
    l.velocity[static_cast<std::size_t>(i)] = cfg.axes[static_cast<std::size_t>(i)].max_velocity_mm_s;
    l.acceleration[static_cast<std::size_t>(i)] = cfg.axes[static_cast<std::size_t>(i)].max_accel_mm_s2;
  }
  const RotaryAxisConfig* t = cfg.tilt_joint();
  const RotaryAxisConfig* c = cfg.rotary_joint();
  l.velocity[kTilt] = t ? t->max_velocity_rad_s : 1.0;
  l.acceleration[kTilt] = t ? t->max_accel_rad_s2 : 1.0;
  l.velocity[kRotary] = c ? c->max_velocity_rad_s : 1.0;
  l.acceleration[kRotary] = c ? c->max_accel_rad_s2 : 1.0;
  return l;
}

TcpMovePlan plan_tcp_move(const Move& m, const MachineConfig& cfg, double feed) {
  TcpMovePlan p;
  const Kinematics kin = kinematics_with_tool(cfg, m.tool_length);
  const RotaryTravel travel = cfg.rotary_travel();
  p.axis_start = tool_axis_of(cfg, m.rot_start);
  p.axis_end = tool_axis_of(cfg, m.rot_end);
  const TcpMove move{{m.start, p.axis_start}, {m.end, p.axis_end}};
  const double tip = norm(m.end - m.start);
  const double turn = angular_length(m, cfg);
  if (tip > kTcpStill) {
    p.length = tip;
  } else if (turn > 1e-12) {
    p.angular = true;
    p.length = turn;
  } else if (std::abs(m.rot_end[0] - m.rot_start[0]) <= kSameRad && std::abs(m.rot_end[1] - m.rot_start[1]) <= kSameRad &&
             std::abs(m.rot_end[2] - m.rot_start[2]) <= kSameRad) {
    // a null move (to where the tool stands, as `G0 Z0` right after M428 at Z0): accepted and
    // nothing runs, as LinuxCNC does; the pipeline drops it (is_null_move). The joints stand where
    // they are: the preflight checks them there.
    const Joints q = inverse(kin, move.start, to_joints(cfg, Vec3{}, m.rot_start), travel);
    p.q_min = p.q_max = q;
    Rot3 rot = m.rot_start;
    from_joints(cfg, q, p.joint_end, rot);
    p.rot_end = rot;
    p.speed = feed;
    return p;
  } else {
    p.error = "under TCP this move neither moves the tool tip nor turns the tool axis but turns a joint (C on the "
              "pole of its axis); expected the joint turned with TCP off (M429) first";
    return p;
  }
  // the joints where the move starts: the programmed angles, the linear axes where they put the tip
  const Joints seed = to_joints(cfg, Vec3{}, m.rot_start);
  const Joints q0 = inverse(kin, move.start, seed, travel);
  const Joints qs = tcp_start_joints(kin, move, q0, travel);
  if (std::abs(qs[kTilt] - seed[kTilt]) > kSameRad || std::abs(qs[kRotary] - seed[kRotary]) > kSameRad) {
    p.error = "under TCP the tool leaves the pole of the C axis towards C " + deg(qs[kRotary]) + " deg but C stands at " +
              deg(seed[kRotary]) + " deg; expected C turned there first (with TCP off, M429)";
    return p;
  }
  const double step = p.angular ? kTcpSampleStep * kRadPerDeg : kTcpSampleStep;
  const int n = std::clamp(static_cast<int>(std::ceil(p.length / step)) + 1, kTcpMinSamples, kTcpMaxSamples);
  const std::vector<JointSample> samples = sample_tcp_move(kin, move, p.length, q0, n, travel);
  p.samples = static_cast<int>(samples.size());
  const Joints& qe = samples.back().q;
  const Joints want = to_joints(cfg, Vec3{}, m.rot_end);
  if (std::abs(qe[kTilt] - want[kTilt]) > kSameRad || std::abs(qe[kRotary] - want[kRotary]) > kSameRad) {
    const char tl = tilt_index(cfg) == 1 ? 'B' : 'A';
    p.error = std::string("under TCP the tool axis turns the short way, on the great circle, and reaches this orientation at ") +
              tl + deg(qe[kTilt]) + " C" + deg(qe[kRotary]) + ", not at the programmed " + tl + deg(want[kTilt]) + " C" +
              deg(want[kRotary]) + "; expected the angles the move reaches (or the move split)";
    return p;
  }
  p.q_min = p.q_max = samples.front().q;
  for (const JointSample& s : samples) {
    for (int j = 0; j < kJoints; ++j) {
      p.q_min[static_cast<std::size_t>(j)] = std::min(p.q_min[static_cast<std::size_t>(j)], s.q[static_cast<std::size_t>(j)]);
      p.q_max[static_cast<std::size_t>(j)] = std::max(p.q_max[static_cast<std::size_t>(j)], s.q[static_cast<std::size_t>(j)]);
    }
  }
  Rot3 rot = m.rot_end;
  from_joints(cfg, qe, p.joint_end, rot);
  p.rot_end = rot;
  JointLimits lim = joint_limits(cfg);
  for (int j = 0; j < kJoints; ++j) {
    lim.velocity[static_cast<std::size_t>(j)] *= kTcpLimitShare;
    lim.acceleration[static_cast<std::size_t>(j)] *= kTcpLimitShare;
  }
  const PathCaps caps = tcp_path_caps(samples, lim, feed, 1e12);
  p.speed = caps.speed;
  p.accel = caps.accel;
  p.speed_joint = caps.speed_joint;
  p.accel_joint = caps.accel_joint;
  if (!(p.speed > 0.0) || !(p.accel > 0.0) || !std::isfinite(p.speed) || !std::isfinite(p.accel)) {
    p.error = "under TCP no path speed keeps every joint within its limits on this move";
  }
  return p;
}

void apply_tcp_plan(const Move& m, const TcpMovePlan& plan, Block& b) {
  b.rotary.tcp = 1;
  b.rotary.angular = plan.angular ? 1 : 0;
  b.rotary.axis_start = plan.axis_start;
  b.rotary.axis_end = plan.axis_end;
  b.rotary.joint_end = plan.joint_end;
  b.rotary.end = plan.rot_end;
  b.rotary.tool_length = m.tool_length;
  b.length = plan.length;
  if (plan.angular) {
    b.speed = plan.speed;
    b.accel = plan.accel;
  } else {
    b.speed = std::min(b.speed, plan.speed);
    b.accel = std::min(b.accel, plan.accel);
  }
  restate_line_plan(m, b);
}

}  // namespace pcnc
