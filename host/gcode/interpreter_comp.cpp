// interpreter_comp.cpp — the modal side of cutter radius compensation: G40, G41/G42 (D: the
// tool whose diameter is used; none: the tool in the spindle), G41.1/G42.1 (D: the diameter in
// program units; a negative one swaps the side, as in LinuxCNC), and what LinuxCNC refuses while
// compensation is on. The state rides on every Move (MoveComp); the geometry is the stage's
// (cutter_comp.hpp).
#include <cmath>
#include <string>

#include "gcode/interpreter.hpp"
#include "gcode/interpreter_text.hpp"
#include "gcode/words.hpp"

namespace pcnc {

using namespace interp;

// LinuxCNC's refusals while compensation is on, checked before the line runs (the plane is
// checked against the state before this line's G40, as LinuxCNC sets the plane first).
bool Interpreter::comp_forbids(const ParsedLine& l) {
  if (comp_.side == 0) return true;
  const auto refuse = [&](int column, const std::string& what) {
    return fail(l, column, "cannot " + what + " with cutter radius compensation on; expected G40 first");
  };
  if (l.g[kGPlane] >= 0) {
    const int n = l.g[kGPlane] == 170 ? 2 : l.g[kGPlane] == 180 ? 1 : 0;
    if (n != normal_axis_) return refuse(l.g_col[kGPlane], "change the plane (" + g_name(l.g[kGPlane]) + ")");
  }
  if (l.m[kMToolChange] == 6) return refuse(l.m_col[kMToolChange], "change tools (M6)");
  if (l.g[kGToolLength] >= 0) return refuse(l.g_col[kGToolLength], "change the tool length offset (" + g_name(l.g[kGToolLength]) + ")");
  if (l.g[kGCoordSystem] >= 0) return refuse(l.g_col[kGCoordSystem], "change coordinate systems (" + g_name(l.g[kGCoordSystem]) + ")");
  if (l.g[kGPathControl] >= 0) return refuse(l.g_col[kGPathControl], "change the path control mode (" + g_name(l.g[kGPathControl]) + ")");
  const int nonmodal = l.g[kGNonModal];
  if (nonmodal == 280 || nonmodal == 300 || nonmodal == 281 || nonmodal == 301)
    return refuse(l.g_col[kGNonModal], "use " + g_name(nonmodal));
  if (nonmodal == 520 || (nonmodal >= 920 && nonmodal <= 923))
    return refuse(l.g_col[kGNonModal], "change axis offsets (" + g_name(nonmodal) + ")");
  if (nonmodal == 530) return refuse(l.g_col[kGNonModal], "use G53");
  const int motion = l.g[kGMotion];  // NURBS (G5.2/G6.2) are fitted with biarcs (cutter_comp_fit.cpp)
  const int effective = motion >= 0 ? motion : motion_;
  if (is_cycle(effective) && (motion >= 0 || axis_words(l)))
    return refuse(motion >= 0 ? l.g_col[kGMotion] : 0, "use canned cycles");
  return true;
}

// G40/G41/G42 (.1) on this line, after the plane and units (RS274 order).
bool Interpreter::comp_words(const ParsedLine& l) {
  const int g = l.g[kGCutterComp];
  if (g < 0) return true;
  const int column = l.g_col[kGCutterComp];
  if (g == 400) {
    comp_.side = 0;
    return true;
  }
  if (comp_.side != 0)
    return fail(l, column, g_name(g) + ": cutter radius compensation is already on; expected G40 before turning it on again");
  std::uint8_t side = (g == 410 || g == 411) ? 1 : 2;
  double radius = 0.0;
  if (g == 411 || g == 421) {
    if (!l.has('D')) return fail(l, column, g_name(g) + " with no D word; expected D with the tool diameter");
    radius = l.get('D') * (inches_ ? kInch : 1.0) / 2.0;
  } else {
    int tool = tool_;
    if (l.has('D')) {
      const double dv = l.get('D');
      const long d = std::lround(dv);
      if (std::fabs(dv - static_cast<double>(d)) >= 1e-4)
        return fail(l, l.column('D'), g_name(g) + " D" + num(dv) + ": expected D to be a whole number (a tool number)");
      if (d < 0) return fail(l, l.column('D'), g_name(g) + " D" + num(dv) + ": expected a tool number >= 0");
      if (d != 0) tool = static_cast<int>(d);
    }
    const ToolEntry* t = have_tools_ ? tools_.find(tool) : nullptr;
    if (have_tools_ && tool != 0 && t == nullptr)
      return fail(l, l.has('D') ? l.column('D') : column,
                  g_name(g) + ": tool " + std::to_string(tool) + " is not in the tool table; expected a tool it lists");
    if (t == nullptr) {
      warn(l, column, "comp-no-tool", [&] {
        return g_name(g) + ": no tool table entry for tool " + std::to_string(tool) +
               ": its diameter is 0, the path is not offset";
      });
    }
    radius = t != nullptr ? t->diameter / 2.0 : 0.0;
  }
  if (radius < 0.0) {  // a negative diameter swaps the side (LinuxCNC)
    radius = -radius;
    side = side == 1 ? 2 : 1;
  }
  comp_.side = side;
  comp_.radius_mm = radius;
  comp_.normal_axis = static_cast<std::uint8_t>(normal_axis_);
  comp_.inch = inches_;
  ++comp_.serial;
  return true;
}

}  // namespace pcnc
