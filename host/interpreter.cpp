// interpreter.cpp — modal G-code interpretation: words to Moves in machine millimetres.
#include "interpreter.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

namespace pcnc {
namespace {

constexpr double kTwoPi = 6.283185307179586476925;
constexpr double kInch = 25.4;

std::string num(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.4f", v);
  // trim trailing zeros for readability: 12.5000 -> 12.5, 3.0000 -> 3
  std::string s(buf);
  if (s.find('.') != std::string::npos) {
    while (!s.empty() && s.back() == '0') s.pop_back();
    if (!s.empty() && s.back() == '.') s.pop_back();
  }
  if (s == "-0") s = "0";
  return s;
}

// nullptr when the G code (x10) is executed or warned about; else why it is rejected.
const char* rejected_g(int c) {
  switch (c) {
    case 100:
      return "setting offsets or tool data from the program (G10) is not supported; expected offsets in the config, "
             "--offset or the control socket";
    case 281:
    case 301: return "storing a home position (G28.1/G30.1) is not supported; expected G28 G91 Z0 for a safe retract";
    case 300: return "a second home position (G30) is not supported; expected G28 G91 Z0 for a safe retract";
    case 520:
    case 920:
    case 921:
    case 922:
    case 923:
      return "coordinate offsets from the program (G52/G92) are not supported; expected G54-G59 (offsets from the "
             "config), --offset or the control socket";
    case 50:
    case 51: return "cubic and quadratic splines (G5/G5.1) are not supported; expected G1/G2/G3 moves";
    case 330:
    case 331:
      return "spindle-synchronized motion (G33) is not supported: the machine has no spindle; expected G0/G1/G2/G3 "
             "moves";
    case 382:
    case 383:
    case 384:
    case 385: return "probing (G38.x) is not supported: the machine has no probe; expected G0/G1/G2/G3 moves";
    case 730:
    case 740:
    case 760:
    case 810:
    case 820:
    case 830:
    case 840:
    case 850:
    case 860:
    case 870:
    case 880:
    case 890:
      return "canned cycles are not supported; expected the CAM post-processor to write drilling as G0/G1 moves";
    case 171:
    case 181:
    case 191: return "the UV/WU/VW planes (G17.1/G18.1/G19.1) are not supported; expected G17, G18 or G19";
    case 901: return "absolute arc centers (G90.1) are not supported; expected G91.1 (I/J/K relative to the arc start)";
    case 930: return "inverse time feed (G93) is not supported; expected G94 (F in units per minute)";
    case 950: return "feed per revolution (G95) is not supported: the machine has no spindle; expected G94";
    case 410:
    case 411:
    case 420:
    case 421:
      return "cutter radius compensation (G41/G42) is not supported; expected a tool path already offset by the CAM "
             "system";
    case 431:
    case 432: return "dynamic tool length offsets (G43.1/G43.2) are not supported; expected G43 H or G49";
    case 980:
    case 990:
      return "canned-cycle return modes (G98/G99) are not supported: there are no canned cycles; expected G0/G1 "
             "retracts";
    case 591:
    case 592:
    case 593: return "work offsets G59.1-G59.3 are not supported; expected G54-G59";
    case 960:
      return "constant surface speed (G96) is not supported: the machine has no spindle; expected G97 or nothing";
    case 70:
    case 80: return "lathe diameter/radius modes (G7/G8) are not supported on this mill; expected a milling program";
    default: return nullptr;
  }
}

const char* rejected_m(int c) {
  if (c == 60) return "pallet change (M60) is not supported; expected M0 to pause the program";
  if (c == 19)
    return "spindle orientation (M19) is not supported: the machine has no spindle; expected no spindle words";
  if (c >= 48 && c <= 53)
    return "override switches (M48-M53) are not supported; expected overrides from the control socket";
  if (c >= 62 && c <= 68)
    return "digital and analog I/O (M62-M68) is not supported; expected a program without I/O words";
  if (c >= 70 && c <= 73)
    return "saving and restoring modal state (M70-M73) is not supported; expected explicit modal words";
  if (c >= 100 && c <= 199)
    return "user M codes (M100-M199) are not supported; expected M codes listed in docs/gcode.md";
  return nullptr;
}

bool is_arc(int motion) { return motion == 20 || motion == 30; }
bool is_straight(int motion) { return motion == 0 || motion == 10; }
char center_letter(int axis) { return static_cast<char>('I' + axis); }

}  // namespace

Interpreter::Interpreter(const MachineConfig& config, const JobFrame& frame, DiagnosticSink& sink)
    : config_(config), frame_(frame), sink_(sink) {
  if (!(frame_.scale > 0.0)) frame_.scale = 1.0;
  max_feed_mm_s_ = config.gcode.max_feed_mm_min > 0.0 ? config.gcode.max_feed_mm_min / 60.0 : 0.0;
  if (max_feed_mm_s_ <= 0.0) {
    for (const AxisConfig& a : config.axes) max_feed_mm_s_ = std::max(max_feed_mm_s_, a.max_velocity_mm_s);
  }
  q_ = to_job(frame_.start);
  work_index_ = std::clamp(frame_.work_offset_index, 0, 5);
  contouring_ = frame_.contouring;
}

Vec3 Interpreter::home_position() const {
  return {config_.axes[0].travel_min_mm, config_.axes[1].travel_min_mm, config_.axes[2].travel_max_mm};
}

Move Interpreter::base_move(MoveKind kind, const ParsedLine& l, int column) const {
  Move m;
  m.kind = kind;
  m.line = l.line;
  m.column = column;
  m.start = m.end = to_machine(q_);
  m.contouring = contouring_;
  m.known = known_;
  return m;
}

Move Interpreter::end_move(int line) const {
  Move m;
  m.kind = MoveKind::kEnd;
  m.line = line;
  m.start = m.end = to_machine(q_);
  m.contouring = contouring_;
  m.known = known_;
  return m;
}

// Rejects unsupported G/M codes and words that nothing on the line uses.
bool Interpreter::check_words(const ParsedLine& l) {
  for (std::uint32_t bits = l.g_groups; bits; bits &= bits - 1) {
    const int g = __builtin_ctz(bits);
    const int c = l.g[static_cast<std::size_t>(g)];
    if (const char* why = rejected_g(c)) return fail(l, l.g_col[static_cast<std::size_t>(g)], g_name(c) + ": " + why);
  }
  for (std::uint32_t bits = l.m_groups; bits; bits &= bits - 1) {
    const int g = __builtin_ctz(bits);
    const int c = l.m[static_cast<std::size_t>(g)];
    if (const char* why = rejected_m(c))
      return fail(l, l.m_col[static_cast<std::size_t>(g)], "M" + std::to_string(c) + ": " + why);
  }
  const int motion_word = l.g[kGMotion];
  const int motion = motion_word >= 0 ? (motion_word == 800 ? -1 : motion_word) : motion_;
  const int nonmodal = l.g[kGNonModal];
  const int plane_word = l.g[kGPlane];
  const int normal = plane_word == 180 ? 1 : plane_word == 190 ? 0 : plane_word == 170 ? 2 : normal_axis_;

  std::uint32_t allowed = bit('N') | bit('F') | bit('S') | bit('T');
  if (nonmodal == 280 || is_straight(motion) || is_arc(motion)) allowed |= kAxisBits;
  if (is_arc(motion) && nonmodal != 280) {
    const auto pa = plane_axes(normal);
    allowed |= bit(center_letter(pa[0])) | bit(center_letter(pa[1])) | bit('R');
    // A center offset along the normal axis is meaningless; FreeCAD writes it as 0 (K0 on G17).
    const char off = center_letter(normal);
    if (l.has(off) && l.get(off) == 0.0) {
      allowed |= bit(off);
      warn(l, l.column(off), "normal-offset", [&] {
        return std::string(std::string(1, off) + "0 on an arc ignored: it is an offset along the arc's normal axis");
      });
    }
  }
  if (nonmodal == 40 || l.g[kGPathControl] == 640) allowed |= bit('P');
  if (l.g[kGPathControl] == 640 || l.m[kMToolChange] == 61) allowed |= bit('Q');
  if (l.g[kGToolLength] == 430) allowed |= bit('H');

  const std::uint32_t extra = l.present & ~allowed;
  if (extra == 0) return true;
  for (int i = 0; i < 26; ++i) {
    if (!((extra >> i) & 1u)) continue;
    const char c = static_cast<char>('A' + i);
    const int col = l.col[static_cast<std::size_t>(i)];
    switch (c) {
      case 'A':
      case 'B':
      case 'C':
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
                          (normal == 2   ? "G17"
                           : normal == 1 ? "G18"
                                         : "G19") +
                          " plane of this arc; expected " + center_letter(std::min(pa[0], pa[1])) + " and " +
                          center_letter(std::max(pa[0], pa[1])));
        }
        return fail(l, col, std::string(1, c) + " word with no G2/G3 that uses it; expected I/J/K only on arcs");
      case 'P':
        if (is_arc(motion))
          return fail(l, col, "P word (number of turns) on an arc is not supported; expected one arc per line");
        return fail(l, col, "P word with no G code that uses it; expected P only with G4 (dwell, seconds) or G64");
      case 'D':
        return fail(l, col,
                    "D word with no G code that uses it (cutter compensation is not supported); expected no D word");
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
  const int motion_word = l.g[kGMotion];
  // NURBS blocks (G5.2 ... G5.3, G6.2) go to one place, where issue 6 plugs in.
  if (motion_word == 52 || motion_word == 53 || motion_word == 62 ||
      (motion_word < 0 && (motion_ == 52 || motion_ == 62))) {
    return nurbs_motion(l, motion_word, out);
  }
  if (!check_words(l)) return false;
  const int first = out.count;

  // Feed, spindle, tool, coolant (RS274 order of execution).
  if (l.has('F')) {
    const double f = l.get('F');
    if (f < 0.0) return fail(l, l.column('F'), "negative F; expected a feed rate >= 0 (units per minute)");
    feed_ = f;
  }
  if (l.has('S'))
    warn(l, l.column('S'), "S",
         [&] { return std::string("S" + num(l.get('S')) + " ignored: the machine has no spindle"); });
  if (l.has('T'))
    warn(l, l.column('T'), "T",
         [&] { return std::string("T" + num(l.get('T')) + " ignored: single-tool machine (no tool changer)"); });
  if (l.m[kMToolChange] >= 0) {
    warn(l, l.m_col[kMToolChange], "M6", [&] {
      return std::string("M" + std::to_string(l.m[kMToolChange]) + " (tool change) ignored: single-tool machine");
    });
  }
  if (l.m[kMSpindle] >= 0) {
    warn(l, l.m_col[kMSpindle], "spindle",
         [&] { return std::string("M" + std::to_string(l.m[kMSpindle]) + " ignored: the machine has no spindle"); });
  }
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
  if (l.g[kGCutterComp] == 400) {
    warn(l, l.g_col[kGCutterComp], "G40",
         [&] { return std::string("G40 ignored: cutter compensation is never active on this machine"); });
  }
  if (l.g[kGToolLength] == 490) {
    warn(l, l.g_col[kGToolLength], "G49",
         [&] { return std::string("G49 ignored: no tool length offset is ever active on this machine"); });
  } else if (l.g[kGToolLength] == 430) {
    warn(l, l.g_col[kGToolLength], "G43", [&] {
      return std::string("G43" + (l.has('H') ? " H" + num(l.get('H')) : std::string()) +
                         " ignored: the machine has no tool length table, the tool length offset stays 0");
    });
  }
  if (l.g[kGCoordSystem] >= 0) work_index_ = (l.g[kGCoordSystem] - 540) / 10;
  if (l.g[kGPathControl] >= 0) {
    const int c = l.g[kGPathControl];
    const bool on = c == 640;
    contouring_ = on;
    warn(l, l.g_col[kGPathControl], on ? "G64" : "G61", [&] {
      return std::string(
          on ? std::string("G64 maps to M21: contouring on") +
                   (l.has('P') || l.has('Q')
                        ? " (its P/Q tolerances are not used: the contouring angle in the config decides)"
                        : "")
             : g_name(c) + " maps to M22: contouring off (stop at every junction)");
    });
  }
  if (l.g[kGDistance] >= 0) incremental_ = l.g[kGDistance] == 910;
  if (l.g[kGSpindleMode] == 970)
    warn(l, l.g_col[kGSpindleMode], "G97", [&] { return std::string("G97 ignored: the machine has no spindle"); });

  if (l.g80_col > 0)
    warn(l, l.g80_col, "G80",
         [&] { return std::string("G80 ignored: no canned cycle is ever active on this machine"); });
  if (motion_word >= 0) {
    if (motion_word == 800) {
      warn(l, l.g_col[kGMotion], "G80",
           [&] { return std::string("G80 ignored: no canned cycle is ever active on this machine"); });
      motion_ = -1;
    } else {
      motion_ = motion_word;
    }
  }
  bool ok = true;
  if (nonmodal == 280) {
    if (motion_word >= 0 && !is_straight(motion_word) && motion_word != 800) {
      return fail(l, l.g_col[kGMotion],
                  "G28 and " + g_name(motion_word) + " both use the axis words; expected them on separate lines");
    }
    ok = home(l, out);
  } else if (nonmodal == 530) {
    if (!is_straight(motion_))
      return fail(l, l.g_col[kGNonModal], "G53 needs G0 or G1 in effect; expected G53 G0 or G53 G1");
    if (!axis_words(l))
      return fail(l, l.g_col[kGNonModal], "G53 without axis words; expected X, Y or Z machine coordinates");
    ok = straight(l, motion_, true, out);
  } else if (is_straight(motion_) && axis_words(l)) {
    ok = straight(l, motion_, false, out);
  } else if (is_arc(motion_) && (axis_words(l) || (l.present & (bit('I') | bit('J') | bit('K') | bit('R'))) != 0)) {
    ok = arc(l, motion_, out);
  } else if (motion_word == 10 && !axis_words(l) && feed_ <= 0.0 && !l.has('F')) {
    // "G1" alone only selects the mode; the feed is checked at the first G1 move.
  }
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
    ended_ = true;
  }
  return true;
}

bool Interpreter::feed_for_move(const ParsedLine& l, int column, double& feed_mm_s) {
  if (!(feed_ > 0.0)) {
    return fail(l, column,
                "feed move with no feed rate in effect (F0 or no F yet); expected an F word > 0 (units per minute)");
  }
  double f = feed_ * (inches_ ? kInch : 1.0) / 60.0;
  if (f > max_feed_mm_s_ * (1.0 + 1e-12)) {
    if (!config_.gcode.clamp_excess_feed) {
      return fail(l, column,
                  "F" + num(feed_) + " (" + num(f) + " mm/s) exceeds the machine maximum feed of " +
                      num(max_feed_mm_s_) +
                      " mm/s; expected F <= " + num(max_feed_mm_s_ * 60.0 / (inches_ ? kInch : 1.0)));
    }
    warn(l, column, "feed-clamp", [&] {
      return std::string("F" + num(feed_) + " (" + num(f) + " mm/s) exceeds the machine maximum feed of " +
                         num(max_feed_mm_s_) + " mm/s; clamped to the maximum");
    });
    f = max_feed_mm_s_;
  }
  feed_mm_s = f;
  return true;
}

bool Interpreter::straight(const ParsedLine& l, int motion, bool g53, MoveList& out) {
  const double u = inches_ ? kInch : 1.0;
  const Vec3 wofs = config_.gcode.work_offsets[static_cast<std::size_t>(work_index_)] - config_.gcode.work_offsets[0];
  Vec3 q = q_;
  Vec3 end = to_machine(q_);
  std::uint8_t known = known_;
  int column = motion == l.g[kGMotion] ? l.g_col[kGMotion] : 0;
  if (g53 && incremental_) return fail(l, l.g_col[kGNonModal], "G53 in incremental mode (G91); expected G90 with G53");
  for (int i = 0; i < kAxes; ++i) {
    const char c = static_cast<char>('X' + i);
    if (!l.has(c)) continue;
    if (column == 0) column = l.column(c);
    const double v = l.get(c) * u;
    if (g53) {
      end[static_cast<std::size_t>(i)] = v;
      q[static_cast<std::size_t>(i)] = (v - frame_.offset[static_cast<std::size_t>(i)]) / frame_.scale;
      known = static_cast<std::uint8_t>(known | (1u << i));
    } else if (incremental_) {
      q[static_cast<std::size_t>(i)] += v;
    } else {
      q[static_cast<std::size_t>(i)] = v + wofs[static_cast<std::size_t>(i)];
      known = static_cast<std::uint8_t>(known | (1u << i));
    }
  }
  if (g53) column = l.g_col[kGNonModal];
  Move m = base_move(motion == 0 ? MoveKind::kRapid : MoveKind::kLine, l, column);
  if (motion == 10 && !feed_for_move(l, column, m.feed_mm_s)) {
    q_ = q;  // keep following the program after the error
    known_ = known;
    return false;
  }
  if (!g53) end = to_machine(q);
  m.end = end;
  m.machine_frame = g53;
  m.known = known;
  q_ = q;
  known_ = known;
  out.push(m);  // even with no displacement: under --fit the same line may move (the stream skips it)
  return true;
}

bool Interpreter::arc(const ParsedLine& l, int motion, MoveList& out) {
  const double u = inches_ ? kInch : 1.0;
  const Vec3 wofs = config_.gcode.work_offsets[static_cast<std::size_t>(work_index_)] - config_.gcode.work_offsets[0];
  const int n = normal_axis_;
  const auto pa = plane_axes(n);
  const auto a0 = static_cast<std::size_t>(pa[0]);
  const auto a1 = static_cast<std::size_t>(pa[1]);
  const char* plane_name = n == 2 ? "G17" : n == 1 ? "G18" : "G19";
  Vec3 e = q_;
  std::uint8_t known = known_;
  int column = motion == l.g[kGMotion] ? l.g_col[kGMotion] : 0;
  for (int i = 0; i < kAxes; ++i) {
    const char c = static_cast<char>('X' + i);
    if (!l.has(c)) continue;
    if (column == 0) column = l.column(c);
    const double v = l.get(c) * u;
    if (incremental_) {
      e[static_cast<std::size_t>(i)] += v;
    } else {
      e[static_cast<std::size_t>(i)] = v + wofs[static_cast<std::size_t>(i)];
      known = static_cast<std::uint8_t>(known | (1u << i));
    }
  }
  // On an error the position still moves to the programmed end point, so that the lines after
  // it are checked from where the program believes it is (no cascade of follow-up errors).
  auto fail_here = [&](int col, std::string message) {
    q_ = e;
    known_ = known;
    return fail(l, col, std::move(message));
  };
  const char l0 = center_letter(pa[0]);
  const char l1 = center_letter(pa[1]);
  if (column == 0) column = l.has(l0) ? l.column(l0) : l.has(l1) ? l.column(l1) : l.column('R');
  const bool has_r = l.has('R');
  const bool has_ijk = l.has(l0) || l.has(l1);
  const std::string gname = motion == 20 ? "G2" : "G3";
  if (has_r && has_ijk)
    return fail_here(l.column('R'),
                     "R and I/J/K words on one arc; expected either the center (I/J/K) or the radius (R)");
  if (!has_r && !has_ijk) {
    return fail_here(column, std::string("I, J, K and R words all missing for arc; expected ") + l0 + "/" + l1 +
                                 " (center offset) or R in the " + plane_name + " plane");
  }
  Move m = base_move(MoveKind::kArc, l, column);
  if (!feed_for_move(l, column, m.feed_mm_s)) {
    q_ = e;
    known_ = known;
    return false;
  }

  const Vec3& s = q_;
  const double su = s[a0], sv = s[a1], eu = e[a0], ev = e[a1];
  const double chord = std::hypot(eu - su, ev - sv);
  // LinuxCNC's rule: the inch threshold is 2.54 times the metric one (0.001 in vs 0.01 mm).
  const double tol_abs = config_.gcode.arc_radius_tolerance_mm * (inches_ ? 2.54 : 1.0);
  const double tol_rel = config_.gcode.arc_radius_tolerance_rel;
  double cu = 0.0, cv = 0.0, r = 0.0;
  bool full = false;
  if (has_ijk) {
    cu = su + (l.has(l0) ? l.get(l0) * u : 0.0);
    cv = sv + (l.has(l1) ? l.get(l1) * u : 0.0);
    const double r1 = std::hypot(su - cu, sv - cv);
    const double r2 = std::hypot(eu - cu, ev - cv);
    if (r1 < 1e-9) return fail_here(column, "arc center equals its start point; expected a nonzero radius");
    const double err = std::fabs(r1 - r2);
    const double rel = err / std::max(r1, r2);
    if (err > 100.0 * tol_abs || (err > tol_abs && rel > tol_rel)) {
      return fail_here(column, "radius to end of arc differs from radius to start: r_start=" + num(r1) +
                                   " mm r_end=" + num(r2) + " mm (difference " + num(err) + " mm, " + num(100.0 * rel) +
                                   "%); expected them to agree within " + num(tol_abs) + " mm or " +
                                   num(100.0 * tol_rel) + "% of the radius (config gcode.arc_radius_tolerance_*)");
    }
    r = r1;
    full = chord < 1e-7;
  } else {
    const double rr = l.get('R') * u;
    if (chord < 1e-9) {
      return fail_here(l.column('R'),
                       "R-form arc whose end point equals its start point; expected a different end point, or I/J/K "
                       "for a full circle");
    }
    const double half = chord / 2.0;
    if (std::fabs(rr) < half && half - std::fabs(rr) > tol_abs) {
      return fail_here(l.column('R'), "R" + num(l.get('R')) + " is too small for the distance " + num(chord) +
                                          " mm between start and end; expected |R| >= " + num(half / u));
    }
    const double h = std::sqrt(std::max(0.0, rr * rr - half * half));
    const double nu = -(ev - sv) / chord, nv = (eu - su) / chord;  // left of the chord
    const double side = (motion == 30 ? 1.0 : -1.0) * (rr > 0.0 ? 1.0 : -1.0);
    cu = 0.5 * (su + eu) + side * h * nu;
    cv = 0.5 * (sv + ev) + side * h * nv;
    r = std::hypot(su - cu, sv - cv);
  }
  const double ts = std::atan2(sv - cv, su - cu);
  const double te = std::atan2(ev - cv, eu - cu);
  double sweep = te - ts;
  if (motion == 30) {
    if (full) {
      sweep = kTwoPi;
    } else {
      while (sweep <= 0.0) sweep += kTwoPi;
    }
  } else {
    if (full) {
      sweep = -kTwoPi;
    } else {
      while (sweep >= 0.0) sweep -= kTwoPi;
    }
  }
  Vec3 c = s;
  c[a0] = cu;
  c[a1] = cv;
  m.end = to_machine(e);
  m.center = to_machine(c);
  m.radius = r * frame_.scale;
  m.sweep = sweep;
  m.normal_axis = n;
  m.known = known;
  q_ = e;
  known_ = known;
  out.push(m);
  return true;
}

bool Interpreter::home(const ParsedLine& l, MoveList& out) {
  const int col = l.g_col[kGNonModal];
  std::uint8_t axes = 0;
  for (int i = 0; i < kAxes; ++i) {
    const char c = static_cast<char>('X' + i);
    if (!l.has(c)) continue;
    if (!incremental_) {
      return fail(l, l.column(c),
                  "G28 with an intermediate point in G90 is not supported; expected the CAM retract form G28 G91 Z0");
    }
    if (l.get(c) != 0.0) {
      return fail(l, l.column(c),
                  "G28 with a nonzero intermediate move is not supported; expected the CAM retract form G28 G91 Z0");
    }
    axes = static_cast<std::uint8_t>(axes | (1u << i));
  }
  if (axes == 0) axes = 7;  // G28 alone: every axis
  const Vec3 home = home_position();
  Move m = base_move(MoveKind::kRapid, l, col);
  std::string what;
  for (int i = 0; i < kAxes; ++i) {
    if (!((axes >> i) & 1u)) continue;
    m.end[static_cast<std::size_t>(i)] = home[static_cast<std::size_t>(i)];
    q_[static_cast<std::size_t>(i)] =
        (home[static_cast<std::size_t>(i)] - frame_.offset[static_cast<std::size_t>(i)]) / frame_.scale;
    what += std::string(what.empty() ? "" : " ") + axis_name(i) + num(home[static_cast<std::size_t>(i)]);
  }
  known_ = static_cast<std::uint8_t>(known_ | axes);
  m.known = known_;
  m.machine_frame = true;
  warn(l, col, "G28" + what, [&] {
    return std::string("G28: rapid to the home position " + what +
                       " (machine coordinates; Z home is the top of its travel)");
  });
  out.push(m);
  return true;
}

bool Interpreter::nurbs_motion(const ParsedLine& l, int motion_word, MoveList& out) {
  // The single plug-in point for NURBS (issue 6, shared/nurbs*): G5.2 ... G5.3 blocks and G6.2.
  // Until it exists, a NURBS block is rejected at its opening line; its control-point lines
  // are taken as part of the rejected block (no second error each).
  (void)out;
  if (motion_word == 53) {
    const bool open = motion_ == 52;
    motion_ = -1;
    if (open) return true;
    return fail(l, l.g_col[kGMotion], "G5.3 without an open G5.2 NURBS block; expected G5.2 first");
  }
  if (motion_word >= 0) {
    motion_ = motion_word;
    return fail(l, l.g_col[kGMotion],
                g_name(motion_word) + ": NURBS not yet supported; expected G0, G1, G2 or G3 moves");
  }
  return true;
}

}  // namespace pcnc
