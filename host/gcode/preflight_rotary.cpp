// preflight_rotary.cpp — the whole program's soft limits on the rotary joints (part of
// Preflight, preflight.hpp): a move with TCP off ends each joint inside its travel (the joints
// run linearly in between); a move under TCP is sampled through the inverse kinematics as the
// rt will run it (tcp_move.hpp) and every joint, linear ones included, must stay inside its
// travel at every sample. Angles are reported in degrees.
#include <cstdio>
#include <string>

#include "config/joint_map.hpp"
#include "gcode/preflight.hpp"
#include "gcode/rotary_move.hpp"
#include "gcode/ruled_move.hpp"
#include "gcode/tcp_move.hpp"

namespace pcnc {
namespace {
constexpr double kJointEps = 1e-9;  // rad
std::string fmt(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4f", v);
  return buf;
}
}  // namespace

void Preflight::check_joint(const Move& m, int joint, double value, const char* where) {
  const auto& j = config_.rotary[static_cast<std::size_t>(joint)];
  if (!check_limits_ || !j || j->continuous) return;
  const bool below = value < j->travel_min_rad - kJointEps;
  const bool above = value > j->travel_max_rad + kJointEps;
  if (!below && !above) return;
  std::uint64_t& count = rot_violations_[static_cast<std::size_t>(2 * joint + (above ? 1 : 0))];
  if (count++ > 0) return;
  sink_.error(m.line, m.column,
              std::string(1, joint_letter(joint)) + " " + fmt(value * kDegPerRad) + " deg" + where + " is " +
                  (above ? "above the travel maximum " + fmt(j->travel_max_rad * kDegPerRad)
                         : "below the travel minimum " + fmt(j->travel_min_rad * kDegPerRad)) +
                  " deg; expected the joint inside its travel");
}

void Preflight::check_linear_joint(const Move& m, int axis, double value) {
  if (!check_limits_) return;
  const AxisConfig& a = config_.axes[static_cast<std::size_t>(axis)];
  const bool below = value < a.travel_min_mm - 1e-9;
  const bool above = value > a.travel_max_mm + 1e-9;
  if (!below && !above) return;
  std::uint64_t& count = violations_[static_cast<std::size_t>(2 * axis + (above ? 1 : 0))];
  if (count++ > 0) return;
  sink_.error(m.line, m.column,
              std::string(1, axis_name(axis)) + " " + fmt(value) + " mm (machine, along the TCP move) is " +
                  (above ? "above the travel maximum " + fmt(a.travel_max_mm) : "below the travel minimum " + fmt(a.travel_min_mm)) +
                  " mm; expected the tool's path and orientation reachable inside the travel");
}

void Preflight::add_fit_pose(const Move& m) {
  if (m.machine_frame) return;  // G53, G28: not the program's own points
  const int t = tilt_index(config_), c = rotary_index(config_);
  FitPose f;
  f.tcp = m.tcp;
  f.tilt = t >= 0 ? m.rot_end[static_cast<std::size_t>(t)] : 0.0;
  f.rotary = c >= 0 ? m.rot_end[static_cast<std::size_t>(c)] : 0.0;
  f.line = m.line;
  f.pose.axis = tool_axis_of(config_, m.rot_end);
  // TCP off with the linear axes still: only the joints turn (the program's tool pose there is
  // the joints' forward kinematics, program.cpp's fit_transform computes it with the tool length)
  f.turn_only = !m.tcp && norm(m.end - m.start) <= 1e-12;
  f.joint_xyz = m.end;
  if (m.tcp && fit_tool_length_) *fit_tool_length_ = m.tool_length;
  // an arc (TCP off) by its extreme points: the chords between them stay inside the travel's box
  for_each_extreme(m, [&](const Vec3& p) {
    f.pose.tip = p;
    fit_poses_->push_back(f);
  });
}

void Preflight::add_rotary(const Move& m) {
  if (!m.tcp) {
    for (int i = 0; i < kRotaryJoints; ++i) check_joint(m, i, m.rot_end[static_cast<std::size_t>(i)], "");
    return;
  }
  const bool angular = angular_move(m);
  const double feed = angular ? (m.feed_mm_s > 0.0 ? m.feed_mm_s : 1e9) : (m.feed_mm_s > 0.0 ? m.feed_mm_s : 1e9);
  const TcpMovePlan plan = plan_tcp_move(m, config_, feed);
  if (!plan.error.empty()) {
    sink_.error(m.line, m.column, plan.error);
    return;
  }
  check_joint_extremes(m, plan.q_min, plan.q_max, " (along the TCP move)");
}

void Preflight::check_joint_extremes(const Move& m, const Joints& q_min, const Joints& q_max, const char* where) {
  for (int i = 0; i < kAxes; ++i) {
    check_linear_joint(m, i, q_min[static_cast<std::size_t>(i)]);
    check_linear_joint(m, i, q_max[static_cast<std::size_t>(i)]);
  }
  const int t = tilt_index(config_), c = rotary_index(config_);
  if (t >= 0) {
    check_joint(m, t, q_min[kTilt], where);
    check_joint(m, t, q_max[kTilt], where);
  }
  if (c >= 0) {
    check_joint(m, c, q_min[kRotary], where);
    check_joint(m, c, q_max[kRotary], where);
  }
}

// A ruled move (G5.4 ... G5.5): the piece walked through the inverse kinematics as the rt will
// run it; every joint inside its travel at every sample, before anything moves.
void Preflight::add_ruled(const Move& m) {
  ++moves_;
  const RuledJointWalk w = walk_ruled_piece(*m.ruled, config_, m.tool_length, ruled_start_joints(m, config_));
  if (!w.error.empty()) {
    sink_.error(m.line, m.column, w.error);
  } else {
    check_joint_extremes(m, w.q_min, w.q_max, " (along the ruled piece)");
  }
  all_.add(m.end);
  if (!m.machine_frame) fit_.add(m.end, m.known);
  if (m.feed_mm_s > 0.0) feed_time_s_ += move_length(m) / m.feed_mm_s;
  last_ = m.end;
}

}  // namespace pcnc
