// interpreter.cpp — modal G-code interpretation, the modal state and the word dispatch: which
// words a line may carry (check_words: the rest rejected, naming the word), then the line
// executed in RS274 order (execute). The moves themselves: interpreter_motion.cpp (lines,
// G28, units and offsets, feed), interpreter_arc.cpp (G2/G3), interpreter_nurbs.cpp (the
// NURBS groups).
#include "gcode/interpreter.hpp"

#include <algorithm>
#include <string>

#include "gcode/interpreter_text.hpp"
#include "gcode/words.hpp"

namespace pcnc {

using namespace interp;

Interpreter::Interpreter(const MachineConfig& config, const JobFrame& frame, DiagnosticSink& sink,
                         ParameterStore& params)
    : config_(config), frame_(frame), sink_(sink), params_(params) {
  if (!(frame_.scale > 0.0)) frame_.scale = 1.0;
  max_feed_mm_s_ = config.gcode.max_feed_mm_min > 0.0 ? config.gcode.max_feed_mm_min / 60.0 : 0.0;
  if (max_feed_mm_s_ <= 0.0) {
    for (const AxisConfig& a : config.axes) max_feed_mm_s_ = std::max(max_feed_mm_s_, a.max_velocity_mm_s);
  }
  q_ = to_job(frame_.start);
  for (int i = 0; i < kRotaryJoints; ++i) {
    const auto k = static_cast<std::size_t>(i);
    if (config.rotary[k]) rot_[k] = frame_.rot_start ? (*frame_.rot_start)[k] : config.rotary[k]->home_rad;
  }
  contouring_ = frame_.contouring;
  path_tolerance_ = config_.motion.path_tolerance_mm;
  // The offsets' parameters (mm), as the state file left them.
  const WorkState w = frame_.work ? *frame_.work : default_work_state(config);
  for (int k = 0; k < 9; ++k) {
    for (int i = 0; i < 3; ++i) params_.at(5221 + 20 * k + i) = w.g5x[static_cast<std::size_t>(k)][static_cast<std::size_t>(i)];
  }
  for (int i = 0; i < 3; ++i) {
    const auto k = static_cast<std::size_t>(i);
    params_.at(5161 + i) = w.g28[k];
    params_.at(5181 + i) = w.g30[k];
    params_.at(5211 + i) = w.g92[k];
  }
  params_.at(5210) = w.g92_applied ? 1.0 : 0.0;
  if (w.g92_applied) g92_ = w.g92;
  base_ = w.g5x[0];
  // The tool in the spindle and its length offset, as the last program or MDI left them.
  tool_ = w.tool;
  tool_offset_on_ = w.tool_offset_applied;
  tlo_ = w.tool_offset_applied ? w.tool_offset : Vec3{};
  if (frame_.tools) {
    tools_ = *frame_.tools;
    have_tools_ = true;
  }
  params_.set_system(this);
  select_system(std::clamp(frame_.work_offset_index, 0, 8));
}

Move Interpreter::base_move(MoveKind kind, const ParsedLine& l, int column) const {
  Move m;
  m.kind = kind;
  m.line = l.line;
  m.column = column;
  m.start = m.end = to_machine(q_);
  m.rot_start = m.rot_end = rot_;
  m.tcp = tcp_;
  m.tool_length = tcp_ ? tcp_length_ : 0.0;
  m.contouring = contouring_;
  m.path_tolerance_mm = path_tolerance_;
  m.known = known_;
  m.comp = comp_;
  return m;
}

// G64 [P]: P sets the path tolerance in the program's units (LinuxCNC), not scaled by --fit;
// G64 alone takes the config's. An operator's --tolerance holds: P is then ignored, with a warning.
bool Interpreter::path_tolerance(const ParsedLine& l) {
  if (!l.has('P')) {
    path_tolerance_ = config_.motion.path_tolerance_mm;
    return true;
  }
  const double p = l.get('P');
  if (!(p >= 0.0)) return fail(l, l.column('P'), "negative G64 P; expected the path tolerance >= 0");
  const double mm = inches_ ? p * 25.4 : p;
  if (mm > 1.0) return fail(l, l.column('P'), "G64 P above 1 mm; expected a path tolerance of 0 .. 1 mm");
  if (config_.motion.path_tolerance_fixed) {
    warn(l, l.column('P'), "G64 P", [&] {
      return "G64 P" + num(p) + " ignored: --tolerance " + num(config_.motion.path_tolerance_mm) + " mm holds";
    });
    return true;
  }
  path_tolerance_ = mm;
  return true;
}

Move Interpreter::end_move(int line) const {
  Move m;
  m.kind = MoveKind::kEnd;
  m.line = line;
  m.start = m.end = to_machine(q_);
  m.contouring = contouring_;
  m.path_tolerance_mm = path_tolerance_;
  m.known = known_;
  m.comp = comp_;
  return m;
}

// Rejects unsupported G/M codes and words that nothing on the line uses.
bool Interpreter::check_words(const ParsedLine& l) {
  for (std::uint32_t bits = l.g_groups; bits; bits &= bits - 1) {
    const int g = __builtin_ctz(bits);
    const int c = l.g[static_cast<std::size_t>(g)];
    if (const char* why = g_rejected(c)) return fail(l, l.g_col[static_cast<std::size_t>(g)], g_name(c) + ": " + why);
  }
  for (std::uint32_t bits = l.m_groups; bits; bits &= bits - 1) {
    const int g = __builtin_ctz(bits);
    const int c = l.m[static_cast<std::size_t>(g)];
    if (const char* why = m_rejected(c))
      return fail(l, l.m_col[static_cast<std::size_t>(g)], "M" + std::to_string(c) + ": " + why);
  }
  const int motion_word = l.g[kGMotion];
  const int motion = motion_word >= 0 ? (motion_word == 800 ? -1 : motion_word) : motion_;
  const int nonmodal = l.g[kGNonModal];
  const int plane_word = l.g[kGPlane];
  const int normal = plane_word == 180 ? 1 : plane_word == 190 ? 0 : plane_word == 170 ? 2 : normal_axis_;

  std::uint32_t allowed = bit('N') | bit('F') | bit('S') | bit('T');
  if (nonmodal == 280 || nonmodal == 300 || is_straight(motion) || is_arc(motion) || is_probe(motion)) allowed |= kAxisBits;
  // polar coordinates (@ ^) name the end point of a move or a hole (LinuxCNC), nothing else
  if (!takes_axis_words(l) && nonmodal != 530 && (is_straight(motion) || is_arc(motion) || is_probe(motion) || is_cycle(motion)))
    allowed |= kPolarBits;
  // the machine's rotary joints move with G0/G1 only (not G53, G28/G30, arcs, probes or cycles)
  if (is_straight(motion) && nonmodal != 280 && nonmodal != 300 && nonmodal != 530 && nonmodal != 100 &&
      nonmodal != 520 && nonmodal < 920 && l.g[kGToolLength] != 431 && l.g[kGToolLength] != 432) {
    allowed |= rotary_bits();
  }
  // The common line (a move in the mode in effect) needs no more: the rest only widens `allowed`.
  if ((l.present & ~allowed) == 0) return true;
  if (nonmodal == 100) allowed |= kAxisBits | bit('L') | bit('P') | bit('R');
  if (nonmodal == 520 || nonmodal == 920) allowed |= kAxisBits;
  if (l.g[kGToolLength] == 431 || l.g[kGToolLength] == 432) allowed |= kAxisBits;
  const bool other_axes = nonmodal == 280 || nonmodal == 300 || nonmodal == 100 || nonmodal == 520 || nonmodal == 920;
  if (is_cycle(motion) && !other_axes) allowed |= kAxisBits | bit('R') | bit('L') | bit('P') | bit('Q');
  if (l.m[kMSubprogram] == 98) allowed |= bit('P') | bit('L');
  if (is_arc(motion) && nonmodal != 280 && nonmodal != 300) {
    const auto pa = plane_axes(normal);
    allowed |= bit(center_letter(pa[0])) | bit(center_letter(pa[1])) | bit('R') | bit('P');  // P: turns
    // A center offset along the normal axis is meaningless; FreeCAD writes it as 0 (K0 on G17).
    const char off = center_letter(normal);
    if (l.has(off) && l.get(off) == 0.0) {
      allowed |= bit(off);
      warn(l, l.column(off), "normal-offset", [&] {
        return std::string(std::string(1, off) + "0 on an arc ignored: it is an offset along the arc's normal axis");
      });
    }
  }
  // G5: X Y, I J (first control point), P Q (second); G5.1: X Y, I J. A Z word is refused
  // by spline() with its own message.
  if (motion == 50) allowed |= kAxisBits | bit('I') | bit('J') | bit('P') | bit('Q');
  if (motion == 51) allowed |= kAxisBits | bit('I') | bit('J');
  // NURBS opening lines: their words are checked by nurbs_open.
  if (motion == 52) allowed |= kAxisBits | bit('P') | bit('L');
  if (motion == 62) allowed |= kAxisBits | bit('P') | bit('K') | bit('R');
  if (nonmodal == 40 || l.g[kGPathControl] == 640) allowed |= bit('P');
  if (l.m[kMToolChange] == 61) allowed |= bit('Q');
  if (l.g[kGCutterComp] >= 410) allowed |= bit('D');  // G41/G42: tool number; G41.1/G42.1: diameter
  if (l.g[kGPathControl] == 640) allowed |= bit('P') | bit('Q');
  if (l.g[kGToolLength] == 430 || l.g[kGToolLength] == 432 || l.g[kGToolLength] == 434) allowed |= bit('H');

  const std::uint32_t extra = l.present & ~allowed;
  if (extra == 0) return true;
  for (int i = 0; i < kWordSlots; ++i) {
    if (!((extra >> i) & 1u)) continue;
    const char c = i == word_slot('@') ? '@' : i == word_slot('^') ? '^' : static_cast<char>('A' + i);
    const int col = l.col[static_cast<std::size_t>(i)];
    switch (c) {
      case '@':
      case '^':
        return fail(l, col,
                    std::string(1, c) + " (polar " + (c == '@' ? "radius" : "angle") +
                        ") with no move that uses it; expected polar coordinates only for the end point of G0, G1, G2, "
                        "G3, G38.x or a canned cycle's hole (not with G10, G28, G30, G52, G53, G92 or G43.1)");
      case 'A':
      case 'B':
      case 'C':
        if ((rotary_bits() & bit(c)) != 0) {
          return fail(l, col, std::string(1, c) + " word here: the rotary joints move with G0 or G1 only; expected it on a G0/G1 line");
        }
        return fail(l, col, std::string("the machine has no ") + c + " axis; expected X, Y or Z");
      case 'U':
      case 'V':
      case 'W': return fail(l, col, std::string("the machine has no ") + c + " axis; expected X, Y or Z");
      case 'X':
      case 'Y':
      case 'Z':
        return fail(l, col,
                    std::string(1, c) +
                        " word with no motion mode in effect; expected G0, G1, G2 or G3 on this line or before it");
      case 'I':
      case 'J':
      case 'K':
        if (is_arc(motion)) {
          const auto pa = plane_axes(normal);
          return fail(l, col,
                      std::string(1, c) + " word is not an offset in the " +
                          plane_name(normal) +
                          " plane of this arc; expected " + center_letter(std::min(pa[0], pa[1])) + " and " +
                          center_letter(std::max(pa[0], pa[1])));
        }
        return fail(l, col, std::string(1, c) + " word with no G2/G3 that uses it; expected I/J/K only on arcs (I/J also on G5/G5.1 splines, K as the knot of G6.2)");
      case 'P':
        return fail(l, col, "P word with no G code that uses it; expected P only with G4 (dwell, seconds), G2/G3 (turns), G64, G5 (spline), G5.2 (weight) or G6.2 (order)");
      case 'D':
        return fail(l, col, "D word with no G code that uses it; expected D only with G41/G42 (tool) or G41.1/G42.1 (diameter)");
      case 'E':
        return fail(
            l, col,
            "E word is not part of this G-code dialect; expected a word letter of RS274 (G, M, X, Y, Z, F, ...)");
      default:
        return fail(l, col,
                    std::string(1, c) + " word with no G code that uses it; expected no " + c + " word on this line");
    }
  }
  return true;
}

bool Interpreter::execute(const ParsedLine& l, MoveList& out) {
  if (l.empty) return true;
  last_line_ = l.line;
  // Inside an open NURBS group every line is a control point, a knot or its end.
  if (nurbs_.open) return nurbs_line(l, out);
  const int motion_word = l.g[kGMotion];
  if (motion_word == 53)
    return fail(l, l.g_col[kGMotion], "G5.3 without an open G5.2 NURBS curve; expected G5.2 first");
  if (!check_words(l) || !comp_forbids(l)) return false;
  const int first = out.count;

  // Feed mode, feed, spindle, tool, coolant (RS274 order of execution: G93/G94 before F).
  if (l.g[kGFeedMode] >= 0) feed_mode(l);
  if (l.has('F')) {
    const double f = l.get('F');
    if (f < 0.0) return fail(l, l.column('F'), "negative F; expected a feed rate >= 0 (units per minute)");
    if (!inverse_time_) {
      feed_ = f;  // G93: each move reads its own line's F (an F without one is ignored, as in LinuxCNC)
      feed_cleared_line_ = 0;
    }
  }
  if (l.has('S'))
    warn(l, l.column('S'), "S",
         [&] { return std::string("S" + num(l.get('S')) + " ignored: the machine has no spindle"); });
  if (l.m[kMSpindle] >= 0) {
    warn(l, l.m_col[kMSpindle], "spindle",
         [&] { return std::string("M" + std::to_string(l.m[kMSpindle]) + " ignored: the machine has no spindle"); });
  }
  // M70-M73 (LinuxCNC's order: after F, S and the spindle; before the plane, units and offsets)
  if (!modal_state_words(l)) return false;
  if (l.m[kMCoolant] >= 0) {
    warn(l, l.m_col[kMCoolant], "coolant",
         [&] { return std::string("M" + std::to_string(l.m[kMCoolant]) + " ignored: the machine has no coolant"); });
  }
  if (l.m[kMContouring] == 21) contouring_ = true;
  if (l.m[kMContouring] == 22) contouring_ = false;

  const int nonmodal = l.g[kGNonModal];
  if (nonmodal == 40) {  // dwell: P in seconds
    if (!l.has('P')) return fail(l, l.g_col[kGNonModal], "G4 without P; expected P with the dwell time in seconds");
    const double p = l.get('P');
    if (p < 0.0) return fail(l, l.column('P'), "negative dwell time; expected P >= 0 (seconds)");
    Move m = base_move(MoveKind::kDwell, l, l.g_col[kGNonModal]);
    m.dwell_s = p;
    out.push(m);
  }
  if (l.g[kGPlane] >= 0) normal_axis_ = l.g[kGPlane] == 170 ? 2 : l.g[kGPlane] == 180 ? 1 : 0;
  if (l.g[kGUnits] >= 0) inches_ = l.g[kGUnits] == 200;
  if (!comp_words(l)) return false;
  // T, M6, M61 and the tool length offset (after the units: G43.1's words are in them).
  if (!tool_words(l)) {
    out.count = first;
    return false;
  }
  if (!tcp_words(l)) {
    out.count = first;
    return false;
  }
  if (l.m[kMToolChange] == 6 && config_.gcode.pause_on_tool_change) {
    out.push(base_move(MoveKind::kPause, l, l.m_col[kMToolChange]));  // the operator changes the tool; resume goes on
  }
  if (l.g[kGCoordSystem] >= 0) {
    const int c = l.g[kGCoordSystem];
    select_system(c <= 590 ? (c - 540) / 10 : 6 + (c - 591));
  }
  if (l.g[kGPathControl] >= 0) {
    const int c = l.g[kGPathControl];
    const bool on = c == 640;
    contouring_ = on;
    if (on && !path_tolerance(l)) return false;
    warn(l, l.g_col[kGPathControl], on ? "G64" : "G61", [&] {
      return std::string(
          on ? std::string("G64 maps to M21: contouring on, path tolerance ") + num(path_tolerance_) + " mm" +
                   (l.has('Q') ? " (its Q tolerance is not used: P is the one path tolerance)" : "")
             : g_name(c) + " maps to M22: contouring off (stop at every junction)");
    });
  }
  if (l.g[kGDistance] >= 0) incremental_ = l.g[kGDistance] == 910;
  if (l.g[kGArcDistance] >= 0) arc_absolute_ = l.g[kGArcDistance] == 901;
  if (l.g[kGCannedReturn] >= 0) retract_r_ = l.g[kGCannedReturn] == 990;
  if (l.g[kGSpindleMode] == 970)
    warn(l, l.g_col[kGSpindleMode], "G97", [&] { return std::string("G97 ignored: the machine has no spindle"); });

  if (l.g80_col > 0)
    warn(l, l.g80_col, "G80", [&] { return std::string("G80 next to a motion code: the motion code applies"); });
  const int previous_motion = motion_;
  if (motion_word >= 0) motion_ = motion_word == 800 ? -1 : motion_word;
  if (motion_word >= 0 && !is_cycle(motion_word)) cycle_.end_series();  // G0-G3, G80: the series ends
  bool ok = true;
  bool spline_line = false;  // this line's move is a G5/G5.1 spline
  if (takes_axis_words(l) && motion_word >= 0 && motion_word != 800 && axis_words(l)) {
    return fail(l, l.g_col[kGMotion],
                g_name(nonmodal) + " and " + g_name(motion_word) +
                    " both use the axis words; expected them on separate lines");
  }
  if ((l.present & kPolarBits) != 0 && !polar_words_fit(l, motion_, normal_axis_)) return false;
  if (tcp_) {
    const bool other = nonmodal == 280 || nonmodal == 300 || nonmodal == 530 || motion_word == 52 || motion_word == 62 ||
                       motion_word == 50 || motion_word == 51 ||
                       ((is_arc(motion_) || is_probe(motion_) || is_cycle(motion_)) && (axis_words(l) || motion_word >= 0));
    if (other) {
      const int col = motion_word >= 0 ? l.g_col[kGMotion] : l.g_col[kGNonModal];
      return fail(l, col, "under tool-centre-point control (M428/G43.4) only G0 and G1 moves run; expected M429 before it");
    }
  }
  if (nonmodal == 280 || nonmodal == 300 || nonmodal == 281 || nonmodal == 301) {
    ok = home(l, out);
  } else if (nonmodal == 100) {
    ok = set_offsets(l);
  } else if (nonmodal == 520 || (nonmodal >= 920 && nonmodal <= 923)) {
    ok = axis_offset(l);
  } else if (l.g[kGToolLength] == 431 || l.g[kGToolLength] == 432) {
    // G43.1's and G43.2's axis words are the tool length (or what is added to it), not a move
  } else if (nonmodal == 530) {
    if (!is_straight(motion_))
      return fail(l, l.g_col[kGNonModal], "G53 needs G0 or G1 in effect; expected G53 G0 or G53 G1");
    if (!axis_words(l))
      return fail(l, l.g_col[kGNonModal], "G53 without axis words; expected X, Y or Z machine coordinates");
    ok = straight(l, motion_, true, out);
  } else if (motion_word == 52 || motion_word == 62) {
    ok = nurbs_open(l, motion_word, out);
  } else if (is_straight(motion_) && (axis_words(l) || (l.present & rotary_bits()) != 0)) {
    ok = straight(l, motion_, false, out);
  } else if (is_arc(motion_) && (axis_words(l) || (l.present & (bit('I') | bit('J') | bit('K') | bit('R'))) != 0)) {
    ok = arc(l, motion_, out);
  } else if ((motion_ == 50 || motion_ == 51) && (axis_words(l) || (l.present & (bit('I') | bit('J') | bit('P') | bit('Q'))) != 0)) {
    ok = spline(l, motion_, out);
    spline_line = true;
  } else if (is_probe(motion_) && axis_words(l)) {
    ok = probe(l, motion_, out);
  } else if (is_probe(motion_) && motion_word >= 0) {
    ok = fail(l, l.g_col[kGMotion], g_name(motion_word) + " without axis words; expected X, Y or Z: the point to probe toward");
  } else if (is_cycle(motion_) && axis_words(l)) {
    ok = cycle(l, motion_, previous_motion != motion_, out);
  }
  if (!spline_line && out.count > first) spline_series_ = false;  // any other move ends a G5 series
  if (!ok) {
    out.count = first;
    return false;
  }

  const int stop = l.m[kMStop];
  if (stop == 0 || stop == 1) {
    Move m = base_move(MoveKind::kPause, l, l.m_col[kMStop]);
    m.optional_stop = stop == 1;
    out.push(m);
  } else if (stop == 2 || stop == 30) {
    out.push(base_move(MoveKind::kEnd, l, l.m_col[kMStop]));
    select_system(0);  // M2/M30: back to G54, as LinuxCNC does
    inverse_time_ = false;  // ... and to G94
    comp_.side = 0;    // ... and to G40
    ended_ = true;
  }
  return true;
}

}  // namespace pcnc
