// rotary_move.cpp — rotary and TCP moves as the stages see them (see rotary_move.hpp).
#include "gcode/rotary_move.hpp"

#include <cmath>

#include "config/joint_map.hpp"
#include "geometry/axis_slerp.hpp"

namespace pcnc {

namespace {
constexpr double kStill = 1e-9;  // mm: the tip or the axes do not move
}

bool moves_rotary(const Move& m) {
  return (m.kind == MoveKind::kLine || m.kind == MoveKind::kRapid) && (m.tcp || m.rot_start != m.rot_end);
}

bool angular_move(const Move& m) {
  if (m.kind != MoveKind::kLine && m.kind != MoveKind::kRapid) return false;
  return norm(m.end - m.start) <= kStill && m.rot_start != m.rot_end;
}

double angular_length(const Move& m, const MachineConfig& cfg) {
  if (m.tcp) return make_axis_slerp(tool_axis_of(cfg, m.rot_start), tool_axis_of(cfg, m.rot_end)).angle;
  double sq = 0.0;
  for (int i = 0; i < kRotaryJoints; ++i) {
    const double d = m.rot_end[static_cast<std::size_t>(i)] - m.rot_start[static_cast<std::size_t>(i)];
    sq += d * d;
  }
  return std::sqrt(sq);
}

Vec3 tool_axis_of(const MachineConfig& cfg, const Rot3& rot) {
  return forward(cfg.kinematics, to_joints(cfg, Vec3{0.0, 0.0, 0.0}, rot)).axis;
}

}  // namespace pcnc
