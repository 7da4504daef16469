// interpreter_offsets.cpp — the coordinate systems and tools of the interpreter: G54-G59.3
// selection, G10 L1/L2/L10/L11/L20, G52, G92/G92.1/G92.2/G92.3, G28/G30 and their .1 forms,
// T/M6/M61 and G43/G43.1/G49; and the parameters that show them (#5161-#5428, #<_x>, ...).
//
// As in LinuxCNC the offsets are kept in the numbered parameters, always in mm (the machine's
// units): G54 at #5221-#5223, G55 at #5241, ... G59.3 at #5381 (20 apart); G92 at #5211-#5213
// with #5210 = 1 while it applies; G28 at #5161-#5163 and G30 at #5181-#5183 (machine
// coordinates); #5220 the active system (1-9). Writing one of them directly (#5221=3) takes
// effect when that system is next selected, as in LinuxCNC.
#include <cmath>
#include <string>

#include "gcode/interpreter.hpp"
#include "gcode/interpreter_text.hpp"
#include "gcode/words.hpp"

namespace pcnc {

using namespace interp;

namespace {
constexpr int kG28 = 5161;
constexpr int kG30 = 5181;
constexpr int kG92Flag = 5210;
constexpr int kG92 = 5211;
constexpr int kActive = 5220;
constexpr int kG54 = 5221;
int system_base(int index) { return kG54 + 20 * index; }
}  // namespace

Vec3 Interpreter::param_vec(int base) const { return {params_.at(base), params_.at(base + 1), params_.at(base + 2)}; }

void Interpreter::set_param_vec(int base, const Vec3& v) {
  for (int i = 0; i < 3; ++i) params_.at(base + i) = v[static_cast<std::size_t>(i)];
}

// Under TCP the tool length is applied along the tool axis by the kinematics, never to Z as well.
void Interpreter::update_origin() { origin_ = g5x_ + g92_ + (tcp_ ? Vec3{} : tlo_) - base_; }

void Interpreter::select_system(int index) {
  work_index_ = index;
  params_.at(kActive) = index + 1;
  g5x_ = param_vec(system_base(index));
  update_origin();
}

Vec3 Interpreter::program_point() const { return q_ - origin_; }

WorkState Interpreter::work_state() const {
  WorkState w;
  for (int k = 0; k < 9; ++k) w.g5x[static_cast<std::size_t>(k)] = param_vec(system_base(k));
  w.active = work_index_;
  w.g92 = param_vec(kG92);
  w.g92_applied = params_.at(kG92Flag) != 0.0;
  w.g28 = param_vec(kG28);
  w.g30 = param_vec(kG30);
  w.tool = tool_;
  w.tool_offset_applied = tool_offset_on_;
  w.tool_offset = tlo_;
  return w;
}

bool Interpreter::write_parameter(int number, double value, std::string& why) {
  return params_.write(number, value, why);
}

bool Interpreter::numbered(int number, double& value) const {
  const double u = inches_ ? kInch : 1.0;
  const ToolEntry* t = have_tools_ ? tools_.find(tool_) : nullptr;
  if (number >= 5021 && number <= 5029) {  // the machine position, program units (LinuxCNC)
    const int i = number - 5021;
    value = i < 3 ? (frame_.scale * q_[static_cast<std::size_t>(i)] + frame_.offset[static_cast<std::size_t>(i)]) / u : 0.0;
  } else if (number == 5400) {
    value = tool_;
  } else if (number >= 5401 && number <= 5409) {
    const int i = number - 5401;
    value = (t != nullptr && i < 3) ? t->offset[static_cast<std::size_t>(i)] / u : 0.0;
  } else if (number == 5410) {
    value = t != nullptr ? t->diameter / u : 0.0;
  } else if (number >= 5420 && number <= 5428) {
    const int i = number - 5420;
    value = i < 3 ? program_point()[static_cast<std::size_t>(i)] / u : 0.0;
  } else {
    return false;
  }
  return true;
}

bool Interpreter::named(std::string_view name, double& value) const {
  const double u = inches_ ? kInch : 1.0;
  const Vec3 p = program_point();
  struct Entry {
    const char* name;
    double v;
  };
  const Entry table[] = {
      {"_x", p[0] / u},
      {"_y", p[1] / u},
      {"_z", p[2] / u},
      {"_a", 0},
      {"_b", 0},
      {"_c", 0},
      {"_u", 0},
      {"_v", 0},
      {"_w", 0},
      {"_abs_x", (frame_.scale * q_[0] + frame_.offset[0]) / u},
      {"_abs_y", (frame_.scale * q_[1] + frame_.offset[1]) / u},
      {"_abs_z", (frame_.scale * q_[2] + frame_.offset[2]) / u},
      {"_line", static_cast<double>(last_line_)},
      {"_motion_mode", motion_ < 0 ? 800.0 : static_cast<double>(motion_)},
      {"_plane", normal_axis_ == 2 ? 170.0 : normal_axis_ == 1 ? 180.0 : 190.0},
      {"_ccomp", 400},
      {"_metric", inches_ ? 0.0 : 1.0},
      {"_imperial", inches_ ? 1.0 : 0.0},
      {"_absolute", incremental_ ? 0.0 : 1.0},
      {"_incremental", incremental_ ? 1.0 : 0.0},
      {"_inverse_time", inverse_time_ ? 1.0 : 0.0},
      {"_units_per_minute", inverse_time_ ? 0.0 : 1.0},
      {"_units_per_rev", 0},
      {"_coord_system", work_index_ < 6 ? 540.0 + 10.0 * work_index_ : 591.0 + (work_index_ - 6)},
      {"_tool_offset", tool_offset_on_ ? 1.0 : 0.0},
      {"_retract_r_plane", retract_r_ ? 1.0 : 0.0},
      {"_retract_old_z", retract_r_ ? 0.0 : 1.0},
      {"_spindle_rpm_mode", 1},
      {"_spindle_css_mode", 0},
      {"_ijk_absolute_mode", 0},
      {"_lathe_diameter_mode", 0},
      {"_lathe_radius_mode", 0},
      {"_spindle_on", 0},
      {"_spindle_cw", 0},
      {"_mist", 0},
      {"_flood", 0},
      {"_speed_override", 0},
      {"_feed_override", 0},
      {"_adaptive_feed", 0},
      {"_feed_hold", 0},
      {"_feed", feed_},
      {"_rpm", 0},
      {"_current_tool", static_cast<double>(tool_)},
      {"_current_pocket", 0},
      {"_selected_tool", static_cast<double>(selected_tool_)},
      {"_selected_pocket", selected_tool_ >= 0 ? 0.0 : -1.0},
      {"_vmajor", 2},
      {"_vminor", 9},
      {"_task", 1},
      {"_call_level", static_cast<double>(params_.call_depth())},
      {"_remap_level", 0},
  };
  for (const Entry& e : table) {
    if (name == e.name) {
      value = e.v;
      return true;
    }
  }
  return false;
}

// G10: L2/L20 work offsets (P0 = the active system), L1/L10/L11 tool table entries.
bool Interpreter::set_offsets(const ParsedLine& l) {
  const int col = l.g_col[kGNonModal];
  if (!l.has('L')) return fail(l, col, "G10 without L; expected L1, L2, L10, L11 or L20");
  const double lv = l.get('L');
  const int L = static_cast<int>(std::lround(lv));
  if (lv != L || (L != 1 && L != 2 && L != 10 && L != 11 && L != 20))
    return fail(l, l.column('L'), "G10 L" + num(lv) + " is not supported; expected L1, L2, L10, L11 or L20");
  if (!l.has('P')) return fail(l, col, "G10 L" + std::to_string(L) + " without P; expected P with the " +
                                           (L == 2 || L == 20 ? "coordinate system (0-9)" : "tool number"));
  const double pv = l.get('P');
  const double u = inches_ ? kInch : 1.0;
  if (L == 2 || L == 20) {
    const int P = static_cast<int>(std::lround(pv));
    if (pv != P || P < 0 || P > 9)
      return fail(l, l.column('P'), "G10 L" + std::to_string(L) + " P" + num(pv) + ": expected P0 (the active system) to P9");
    if (l.has('R') && l.get('R') != 0.0)
      return fail(l, l.column('R'), "coordinate system rotation (G10 L2 R) is not supported; expected R0 or no R");
    const int index = P == 0 ? work_index_ : P - 1;
    const int base = system_base(index);
    // The current point in machine terms, without the tool length (what the offsets place).
    const Vec3 here = program_point() + g5x_ + g92_;
    for (int i = 0; i < kAxes; ++i) {
      const char c = static_cast<char>('X' + i);
      if (!l.has(c)) continue;
      const double v = l.get(c) * u;
      params_.at(base + i) = L == 2 ? v : here[static_cast<std::size_t>(i)] - g92_[static_cast<std::size_t>(i)] - v;
    }
    if (index == work_index_) select_system(index);
    return true;
  }
  // Tool table: L1 sets the entry from the words; L10/L11 so that the current point reads the
  // given coordinates with this tool's offset (L11: as if G59.3 were active).
  const int T = static_cast<int>(std::lround(pv));
  if (pv != T || T < 0) return fail(l, l.column('P'), "G10 L" + std::to_string(L) + " P" + num(pv) + ": expected P with a tool number >= 0");
  ToolEntry e;
  if (const ToolEntry* old = tools_.find(T)) e = *old;
  e.number = T;
  if (e.pocket == 0) e.pocket = T;
  const Vec3 offsets_other = L == 11 ? param_vec(system_base(8)) + g92_ : g5x_ + g92_;
  const Vec3 machine_no_tool = program_point() + g5x_ + g92_ + tlo_;  // where the spindle is, in offset terms
  for (int i = 0; i < kAxes; ++i) {
    const char c = static_cast<char>('X' + i);
    if (!l.has(c)) continue;
    const auto k = static_cast<std::size_t>(i);
    const double v = l.get(c) * u;
    e.offset[k] = L == 1 ? v : machine_no_tool[k] - offsets_other[k] - v;
  }
  if (l.has('R')) e.diameter = 2.0 * l.get('R') * u;
  tools_.set(e);
  have_tools_ = true;
  return true;
}

// G52, G92, G92.1, G92.2, G92.3: the axis offset (LinuxCNC shares it between G52 and G92).
bool Interpreter::axis_offset(const ParsedLine& l) {
  const int code = l.g[kGNonModal];
  const double u = inches_ ? kInch : 1.0;
  if (code == 920 || code == 520) {
    if (!axis_words(l))
      return fail(l, l.g_col[kGNonModal], g_name(code) + " without axis words; expected X, Y or Z");
    const Vec3 p = program_point();
    for (int i = 0; i < kAxes; ++i) {
      const char c = static_cast<char>('X' + i);
      if (!l.has(c)) continue;
      const auto k = static_cast<std::size_t>(i);
      const double v = l.get(c) * u;
      g92_[k] = code == 920 ? p[k] + g92_[k] - v : v;
      params_.at(kG92 + i) = g92_[k];
    }
    params_.at(kG92Flag) = 1.0;
  } else if (code == 921 || code == 922) {
    g92_ = Vec3{};
    if (code == 921) set_param_vec(kG92, Vec3{});
    params_.at(kG92Flag) = 0.0;
  } else if (code == 923) {
    g92_ = param_vec(kG92);
    params_.at(kG92Flag) = 1.0;
  }
  update_origin();
  return true;
}

bool Interpreter::tool_words(const ParsedLine& l) {
  if (!l.has('T') && l.m[kMToolChange] < 0 && l.g[kGToolLength] < 0) return true;  // most lines
  if (l.has('T')) {
    const double tv = l.get('T');
    const int t = static_cast<int>(std::lround(tv));
    if (tv != t || t < 0) return fail(l, l.column('T'), "T" + num(tv) + ": expected a tool number, a whole number >= 0");
    if (have_tools_ && t != 0 && tools_.find(t) == nullptr)
      return fail(l, l.column('T'), "T" + std::to_string(t) + " is not in the tool table; expected a tool it lists");
    selected_tool_ = t;
    if (!have_tools_)
      warn(l, l.column('T'), "T", [&] {
        return std::string("T" + std::to_string(t) + ": no tool table (--tool-table or gcode.tool_table), the tool has length and diameter 0");
      });
  }
  const int m = l.m[kMToolChange];
  if (m == 6) {
    if (selected_tool_ >= 0) tool_ = selected_tool_;
    if (!config_.gcode.pause_on_tool_change) warn(l, l.m_col[kMToolChange], "M6", [&] {
      return std::string("M6: tool change to T" + std::to_string(tool_) +
                         " without a pause (no tool changer; set gcode.pause_on_tool_change to pause)");
    });
  } else if (m == 61) {
    if (!l.has('Q')) return fail(l, l.m_col[kMToolChange], "M61 without Q; expected M61 Q<tool number>");
    const double qv = l.get('Q');
    const int q = static_cast<int>(std::lround(qv));
    if (qv != q || q < 0) return fail(l, l.column('Q'), "M61 Q" + num(qv) + ": expected a tool number >= 0");
    tool_ = q;
  }
  const int g = l.g[kGToolLength];
  // G43 / G43.2 H: tool h's offset from the table (0 without one, warned); false on an error
  auto table_offset = [&](const char* gname, int h, Vec3& offset) {
    if (l.has('H')) {
      const double hv = l.get('H');
      h = static_cast<int>(std::lround(hv));
      if (hv != h || h < 0) return fail(l, l.column('H'), std::string(gname) + " H" + num(hv) + ": expected a tool number >= 0");
    }
    const ToolEntry* t = have_tools_ ? tools_.find(h) : nullptr;
    if (have_tools_ && h != 0 && t == nullptr)
      return fail(l, l.column('H'), std::string(gname) + " H" + std::to_string(h) + ": tool " + std::to_string(h) +
                                        " is not in the tool table; expected a tool it lists");
    if (!have_tools_) {
      warn(l, l.g_col[kGToolLength], gname, [&] {
        return std::string(gname) + ": no tool table, the tool length offset is 0";
      });
    }
    offset = t != nullptr ? t->offset : Vec3{};
    return true;
  };
  if (g == 430) {
    Vec3 offset{};
    if (!table_offset("G43", tool_, offset)) return false;
    tlo_ = offset;
    tool_offset_on_ = true;
  } else if (g == 432) {
    // LinuxCNC: H or axis words (not both, not neither), added to the offset in effect
    const bool axes = l.has('X') || l.has('Y') || l.has('Z');
    if (l.has('H') && axes) return fail(l, l.column('H'), "G43.2 with both H and axis words; expected H (add a tool's offset) or axis words (add them)");
    if (!l.has('H') && !axes)
      return fail(l, l.g_col[kGToolLength], "G43.2 without H or axis words; expected H<tool> or X/Y/Z values to add to the tool length offset");
    Vec3 add{};
    if (l.has('H')) {
      if (!table_offset("G43.2", 0, add)) return false;
    } else {
      const double u = inches_ ? kInch : 1.0;
      for (int i = 0; i < kAxes; ++i) {
        const char c = static_cast<char>('X' + i);
        if (l.has(c)) add[static_cast<std::size_t>(i)] = l.get(c) * u;
      }
    }
    tlo_ = tlo_ + add;
    tool_offset_on_ = true;
  } else if (g == 431) {
    const double u = inches_ ? kInch : 1.0;
    Vec3 v{};
    for (int i = 0; i < kAxes; ++i) {
      const char c = static_cast<char>('X' + i);
      if (l.has(c)) v[static_cast<std::size_t>(i)] = l.get(c) * u;
    }
    tlo_ = v;
    tool_offset_on_ = true;
  } else if (g == 490) {
    tlo_ = Vec3{};
    tool_offset_on_ = false;
  }
  update_origin();
  return true;
}

// G28/G30 (optionally through an intermediate point), G28.1/G30.1 (store the position).
bool Interpreter::home(const ParsedLine& l, MoveList& out) {
  const int code = l.g[kGNonModal];
  const int col = l.g_col[kGNonModal];
  const int store = (code == 280 || code == 281) ? kG28 : kG30;
  const Vec3 machine_now = frame_.scale * q_ + frame_.offset;
  if (code == 281 || code == 301) {
    set_param_vec(store, machine_now);
    return true;
  }
  const Vec3 target = param_vec(store);
  std::uint8_t axes = 0;
  for (int i = 0; i < kAxes; ++i) {
    if (l.has(static_cast<char>('X' + i))) axes = static_cast<std::uint8_t>(axes | (1u << i));
  }
  if (axes != 0) {  // the intermediate point, in the program's coordinates and distance mode
    std::uint8_t known = known_;
    int first_col = 0;
    const Vec3 q = axis_target(l, q_, known, first_col);
    Move m = base_move(MoveKind::kRapid, l, col);
    m.end = to_machine(q);
    m.known = known;
    q_ = q;
    known_ = known;
    out.push(m);
  } else {
    axes = 7;  // G28 alone: every axis
  }
  Move m = base_move(MoveKind::kRapid, l, col);
  for (int i = 0; i < kAxes; ++i) {
    if (!((axes >> i) & 1u)) continue;
    const auto k = static_cast<std::size_t>(i);
    m.end[k] = target[k];
    q_[k] = (target[k] - frame_.offset[k]) / frame_.scale;
  }
  known_ = static_cast<std::uint8_t>(known_ | axes);
  m.known = known_;
  m.machine_frame = true;
  out.push(m);
  return true;
}

}  // namespace pcnc
