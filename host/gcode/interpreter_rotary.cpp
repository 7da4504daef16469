// interpreter_rotary.cpp — the rotary joints' words and tool-centre-point control in the
// interpreter: A/B/C on G0/G1 lines of a machine that declares them (degrees, G90/G91, never
// scaled by G20 or --fit, no work offsets), and M428/G43.4 on, M429/G49 off (docs/kinematics.md,
// "The pipeline"). Under TCP the current point q_ is the tool tip in workpiece coordinates and the
// tool length of the tool in the spindle (or G43.4's H) is applied along the tool axis by the
// kinematics; switching re-expresses the current point through the forward or inverse kinematics,
// so the machine does not move.
#include <cmath>
#include <string>

#include "config/joint_map.hpp"
#include "gcode/interpreter.hpp"
#include "gcode/interpreter_text.hpp"
#include "gcode/rotary_move.hpp"

namespace pcnc {

using namespace interp;

std::uint32_t Interpreter::rotary_bits() const {
  std::uint32_t bits = 0;
  for (int i = 0; i < kRotaryJoints; ++i) {
    if (config_.rotary[static_cast<std::size_t>(i)]) bits |= bit(joint_letter(i));
  }
  return bits;
}

Rot3 Interpreter::rotary_target(const ParsedLine& l) const {
  Rot3 r = rot_;
  for (int i = 0; i < kRotaryJoints; ++i) {
    const char c = joint_letter(i);
    if (!config_.rotary[static_cast<std::size_t>(i)] || !l.has(c)) continue;
    const double v = l.get(c) * kRadPerDeg;  // degrees in G20 and G21 alike
    r[static_cast<std::size_t>(i)] = incremental_ ? r[static_cast<std::size_t>(i)] + v : v;
  }
  return r;
}

double Interpreter::tcp_tool_length(int tool) const {
  if (!have_tools_ || tool == 0) return 0.0;
  const ToolEntry* t = tools_.find(tool);
  return t != nullptr ? t->offset[2] : 0.0;
}

bool Interpreter::tcp_words(const ParsedLine& l) {
  const int m = l.m[kMTcp];
  const int g = l.g[kGToolLength];
  const bool on = m == 428 || g == 434;
  const bool off = m == 429 || (g == 490 && tcp_);
  if (!on && !off) return true;
  const int col = m >= 0 ? l.m_col[kMTcp] : l.g_col[kGToolLength];
  const std::string name = m >= 0 ? "M" + std::to_string(m) : g_name(g);
  if (on && off) return fail(l, col, name + ": TCP on and off on one line; expected one of M428/G43.4 and M429/G49");
  if (config_.kinematics.kind == KinematicsKind::kTrivial || config_.rotary_mask() == 0) {
    if (m == 429) return true;  // off on a machine that never had it: nothing to do
    return fail(l, col,
                name + ": tool-centre-point control needs rotary joints and a [kinematics] section; this machine has none");
  }
  if (on && comp_.side != 0) {
    return fail(l, col, name + ": tool-centre-point control under cutter radius compensation (G41/G42); expected G40 first");
  }
  if (on) {
    int tool = tool_;
    if (g == 434 && l.has('H')) {
      const double hv = l.get('H');
      tool = static_cast<int>(std::lround(hv));
      if (hv != tool || tool < 0) return fail(l, l.column('H'), "G43.4 H" + num(hv) + ": expected a tool number >= 0");
      if (have_tools_ && tool != 0 && tools_.find(tool) == nullptr) {
        return fail(l, l.column('H'), "G43.4 H" + std::to_string(tool) + ": tool " + std::to_string(tool) +
                                          " is not in the tool table; expected a tool it lists");
      }
    }
    const double length = tcp_tool_length(tool);
    // the machine's joints now: the linear axes at the spindle's gauge point, then the tool tip
    const Vec3 gauge = tcp_ ? Vec3{} : to_machine(q_);
    if (tcp_) {  // already on (a new length): back to the joints first
      const Joints q = inverse(kinematics_with_tool(config_, tcp_length_),
                               ToolPose{to_machine(q_), tool_axis_of(config_, rot_)}, to_joints(config_, Vec3{}, rot_));
      const Vec3 xyz{q[0], q[1], q[2]};
      const ToolPose tip = forward(kinematics_with_tool(config_, length), to_joints(config_, xyz, rot_));
      tcp_length_ = length;
      q_ = to_job(tip.tip);
      return true;
    }
    const ToolPose tip = forward(kinematics_with_tool(config_, length), to_joints(config_, gauge, rot_));
    tcp_ = true;
    tcp_length_ = length;
    update_origin();
    q_ = to_job(tip.tip);
    return true;
  }
  // off: the linear axes where the inverse kinematics puts them for the tip and the joints now
  const Joints q = inverse(kinematics_with_tool(config_, tcp_length_), ToolPose{to_machine(q_), tool_axis_of(config_, rot_)},
                           to_joints(config_, Vec3{}, rot_));
  tcp_ = false;
  tcp_length_ = 0.0;
  update_origin();
  q_ = to_job(Vec3{q[0], q[1], q[2]});
  return true;
}

}  // namespace pcnc
