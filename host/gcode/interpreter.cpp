// interpreter.cpp — modal G-code interpretation: words to Moves in machine millimetres.
#include "gcode/interpreter.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "geometry/nurbs.hpp"
#include "gcode/nurbs_move.hpp"

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
  // NURBS opening lines: their words are checked by nurbs_open.
  if (motion == 52) allowed |= kAxisBits | bit('P') | bit('L');
  if (motion == 62) allowed |= kAxisBits | bit('P') | bit('K') | bit('R');
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
                          plane_name(normal) +
                          " plane of this arc; expected " + center_letter(std::min(pa[0], pa[1])) + " and " +
                          center_letter(std::max(pa[0], pa[1])));
        }
        return fail(l, col, std::string(1, c) + " word with no G2/G3 that uses it; expected I/J/K only on arcs (and K as the knot of G6.2)");
      case 'P':
        if (is_arc(motion))
          return fail(l, col, "P word (number of turns) on an arc is not supported; expected one arc per line");
        return fail(l, col, "P word with no G code that uses it; expected P only with G4 (dwell, seconds), G64, G5.2 (weight) or G6.2 (order)");
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
  // Inside an open NURBS group every line is a control point, a knot or its end.
  if (nurbs_.open) return nurbs_line(l, out);
  const int motion_word = l.g[kGMotion];
  if (motion_word == 53)
    return fail(l, l.g_col[kGMotion], "G5.3 without an open G5.2 NURBS curve; expected G5.2 first");
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
  } else if (motion_word == 52 || motion_word == 62) {
    ok = nurbs_open(l, motion_word, out);
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
  const char* plane = plane_name(n);
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
                                 " (center offset) or R in the " + plane + " plane");
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

// ---- NURBS: G5.2 ... G5.3 (LinuxCNC) and G6.2 ... closing knots (Fanuc) -------------------
//
// The opening line is an ordinary line (modal words, F) whose motion word opens a group;
// every following line belongs to the group until it is complete: G5.3 for G5.2, the
// order-th knot-only K line for G6.2. Inside a group only control points (G5.2: the two
// plane axes and P; G6.2: K, X Y Z and R) are allowed; any G or M word abandons the curve
// with an error. The curve is handed on as one Move in machine coordinates.

bool Interpreter::nurbs_open(const ParsedLine& l, int motion, MoveList& out) {
  (void)out;
  const int col = l.g_col[kGMotion];
  const bool fanuc = motion == 62;
  const std::string gname = fanuc ? "G6.2" : "G5.2";
  motion_ = -1;  // a failed opening leaves no NURBS mode behind
  if (l.g[kGNonModal] >= 0) {
    return fail(l, l.g_col[kGNonModal],
                g_name(l.g[kGNonModal]) + " on a line that opens a " + gname +
                    " NURBS curve; expected it on a line of its own");
  }
  if (l.m[kMStop] >= 0) {
    return fail(l, l.m_col[kMStop],
                "M" + std::to_string(l.m[kMStop]) + " on a line that opens a " + gname +
                    " NURBS curve; expected it after the curve");
  }
  NurbsGroup g;
  g.fanuc = fanuc;
  g.line = l.line;
  g.column = col;
  g.normal_axis = normal_axis_;
  g.order = fanuc ? 4 : 3;  // Fanuc's default rank 4 (cubic); LinuxCNC's default L3
  const char order_letter = fanuc ? 'P' : 'L';
  if (l.has(order_letter)) {
    const double v = l.get(order_letter);
    if (v != std::floor(v) || v < kMinNurbsOrder || v > kMaxNurbsOrder) {
      return fail(l, l.column(order_letter),
                  std::string(1, order_letter) + num(v) + ": the NURBS order must be a whole number from " +
                      std::to_string(kMinNurbsOrder) + " to " + std::to_string(kMaxNurbsOrder) + "; expected " +
                      order_letter + "2 (lines) to " + order_letter + "6 (degree 5), e.g. " + order_letter +
                      "3 quadratic, " + order_letter + "4 cubic");
    }
    g.order = static_cast<int>(v);
  }
  if (!feed_for_move(l, col, g.feed_mm_s)) return false;
  g.known = known_;
  g.points.push_back(q_);  // the current position is the first control point
  const char weight_letter = fanuc ? 'R' : 'P';
  double w0 = 1.0;
  if (l.has(weight_letter)) {
    w0 = l.get(weight_letter);
    if (!(w0 > 0.0)) {
      return fail(l, l.column(weight_letter),
                  std::string("NURBS weight ") + weight_letter + num(w0) + " is not positive; expected " +
                      weight_letter + " > 0");
    }
  }
  if (!fanuc) {
    if (axis_words(l)) {
      // G5.2 X Y P L: the current point (weight 1) and this line's point (weight P).
      g.weights.push_back(1.0);
      nurbs_ = std::move(g);
      nurbs_.open = true;
      if (!nurbs_point_line(l)) {
        nurbs_ = NurbsGroup{};
        return false;
      }
    } else {
      g.weights.push_back(w0);
      nurbs_ = std::move(g);
      nurbs_.open = true;
    }
  } else {
    // G6.2 [P] [K] [X Y Z] [R] [F]: the first control point must be the current position.
    if (axis_words(l)) {
      const double u = inches_ ? kInch : 1.0;
      const Vec3 wofs =
          config_.gcode.work_offsets[static_cast<std::size_t>(work_index_)] - config_.gcode.work_offsets[0];
      Vec3 q = q_;
      int first_col = 0;
      for (int i = 0; i < kAxes; ++i) {
        const char c = static_cast<char>('X' + i);
        if (!l.has(c)) continue;
        if (first_col == 0) first_col = l.column(c);
        const auto k = static_cast<std::size_t>(i);
        q[k] = incremental_ ? q_[k] + l.get(c) * u : l.get(c) * u + wofs[k];
        if (!incremental_) g.known = static_cast<std::uint8_t>(g.known | (1u << i));
      }
      if (norm(q - q_) * frame_.scale > config_.motion.block_tolerance_mm) {
        return fail(l, first_col,
                    "the first control point of a G6.2 curve is " + num(norm(q - q_)) +
                        " mm away from the current position; expected the curve to start where the tool is (or no "
                        "coordinates on the G6.2 line)");
      }
    }
    g.weights.push_back(w0);
    g.knots.push_back(l.has('K') ? l.get('K') : std::numeric_limits<double>::quiet_NaN());
    nurbs_ = std::move(g);
    nurbs_.open = true;
  }
  motion_ = motion;
  return true;
}

bool Interpreter::nurbs_line(const ParsedLine& l, MoveList& out) {
  NurbsGroup& g = nurbs_;
  const std::string gname = g.fanuc ? "G6.2" : "G5.2";
  const std::string where = " inside the " + gname + " NURBS curve opened on line " + std::to_string(g.line);
  const std::string still_open =
      g.fanuc ? "; expected its " + std::to_string(g.order) + " closing knot-only K lines first (" +
                    std::to_string(g.closing) + " given)"
              : std::string("; expected G5.3 to close the curve first");
  // A G or M word ends the group with an error (nothing is half executed).
  for (std::uint32_t bits = l.g_groups; bits; bits &= bits - 1) {
    const int grp = __builtin_ctz(bits);
    const int c = l.g[static_cast<std::size_t>(grp)];
    if (!g.fanuc && c == 53) continue;
    const bool report = !g.failed;
    nurbs_abandon();
    if (!report) return false;
    return fail(l, l.g_col[static_cast<std::size_t>(grp)], g_name(c) + where + still_open);
  }
  for (std::uint32_t bits = l.m_groups; bits; bits &= bits - 1) {
    const int grp = __builtin_ctz(bits);
    const int c = l.m[static_cast<std::size_t>(grp)];
    const bool report = !g.failed;
    nurbs_abandon();
    if (!report) return false;
    return fail(l, l.m_col[static_cast<std::size_t>(grp)], "M" + std::to_string(c) + where + still_open);
  }
  const std::uint32_t allowed =
      bit('N') | kAxisBits | (g.fanuc ? (bit('K') | bit('R')) : bit('P'));
  const std::uint32_t extra = l.present & ~allowed;
  if (extra != 0) {
    const int i = __builtin_ctz(extra);
    const char c = static_cast<char>('A' + i);
    const bool report = !g.failed;
    g.failed = true;
    if (!report) return false;
    return fail(l, l.col[static_cast<std::size_t>(i)],
                std::string(1, c) + " word" + where +
                    (g.fanuc ? "; expected only K X Y Z R lines (control points) and K lines (closing knots)"
                             : "; expected only control points X Y P (in the plane) and G5.3"));
  }
  if (!g.fanuc) {
    if (l.g[kGMotion] == 53) {
      if (axis_words(l) || l.has('P')) {
        const bool report = !g.failed;
        g.failed = true;
        if (report) {
          fail(l, axis_words(l) ? l.column(l.has('X') ? 'X' : l.has('Y') ? 'Y' : 'Z') : l.column('P'),
               "G5.3 with a control point; expected G5.3 alone on its line");
        }
      }
      return nurbs_close(l, out);
    }
    if (!axis_words(l) && !l.has('P')) return true;  // an N word alone
    return nurbs_point_line(l);
  }
  if (!nurbs_knot(l)) return false;
  if (g.closing == g.order) return nurbs_close(l, out);
  return true;
}

// An error inside a NURBS group: reported once; the group is dropped at its end.
bool Interpreter::nurbs_fail(const ParsedLine& l, int column, std::string message) {
  const bool report = !nurbs_.failed;
  nurbs_.failed = true;
  if (report) fail(l, column, std::move(message));
  return false;
}

// A control point: G5.2: both plane axes and P (the third axis stays); G6.2: K, any of X Y Z
// (an axis not given keeps its value from the previous point) and R (default 1).
bool Interpreter::nurbs_point_line(const ParsedLine& l) {
  NurbsGroup& g = nurbs_;
  auto group_fail = [&](int col, std::string message) { return nurbs_fail(l, col, std::move(message)); };
  const int first_col = l.column(l.has('X') ? 'X' : l.has('Y') ? 'Y' : l.has('Z') ? 'Z' : g.fanuc ? 'R' : 'P');
  if (static_cast<int>(g.points.size()) >= kMaxNurbsCurvePoints) {
    return group_fail(first_col, "more than " + std::to_string(kMaxNurbsCurvePoints) +
                                     " control points in one NURBS curve; expected the curve split into several");
  }
  const double u = inches_ ? kInch : 1.0;
  const Vec3 wofs = config_.gcode.work_offsets[static_cast<std::size_t>(work_index_)] - config_.gcode.work_offsets[0];
  const Vec3 prev = g.points.back();
  Vec3 q = prev;
  if (!g.fanuc) {
    const auto pa = plane_axes(g.normal_axis);
    const char a0 = axis_name(pa[0]), a1 = axis_name(pa[1]), an = axis_name(g.normal_axis);
    const char* plane = plane_name(g.normal_axis);
    if (l.has(an)) {
      return group_fail(l.column(an), std::string(1, an) + " word in a " + plane +
                                          " NURBS curve; expected only " + a0 + " and " + a1 +
                                          " (the curve lies in the plane)");
    }
    if (!l.has(a0) || !l.has(a1)) {
      return group_fail(first_col, std::string("NURBS control point without ") + (l.has(a0) ? a1 : a0) +
                                       "; expected both " + a0 + " and " + a1 + " on every control point of a " +
                                       plane + " curve");
    }
    if (!l.has('P')) {
      return group_fail(first_col, "NURBS control point without its weight P; expected P > 0 on every control point");
    }
  }
  const char weight_letter = g.fanuc ? 'R' : 'P';
  const double w = l.has(weight_letter) ? l.get(weight_letter) : 1.0;
  if (!(w > 0.0)) {
    return group_fail(l.column(weight_letter), std::string("NURBS weight ") + weight_letter + num(w) +
                                                   " is not positive; expected " + weight_letter + " > 0");
  }
  for (int i = 0; i < kAxes; ++i) {
    const char c = static_cast<char>('X' + i);
    if (!l.has(c)) continue;
    const auto k = static_cast<std::size_t>(i);
    q[k] = incremental_ ? prev[k] + l.get(c) * u : l.get(c) * u + wofs[k];
    if (!incremental_) g.known = static_cast<std::uint8_t>(g.known | (1u << i));
  }
  g.points.push_back(q);
  g.weights.push_back(w);
  return true;
}

// G6.2 lines after the first: K with a control point, or K alone (the closing knots).
bool Interpreter::nurbs_knot(const ParsedLine& l) {
  NurbsGroup& g = nurbs_;
  auto group_fail = [&](int col, std::string message) { return nurbs_fail(l, col, std::move(message)); };
  const bool point = axis_words(l) || l.has('R');
  if (!l.has('K')) {
    if (!point) return true;  // an N word alone
    return group_fail(l.column(l.has('X') ? 'X' : l.has('Y') ? 'Y' : l.has('Z') ? 'Z' : 'R'),
                      "G6.2 control point without its knot K; expected K on every line of the curve");
  }
  const double k = l.get('K');
  if (g.knots.size() == 1 && std::isnan(g.knots[0])) g.knots[0] = k;  // K omitted on the G6.2 line
  if (k < g.knots.back()) {
    return group_fail(l.column('K'), "knot K" + num(k) + " is smaller than the knot before it (K" +
                                         num(g.knots.back()) + "); expected non-decreasing knots");
  }
  if (point) {
    if (g.closing > 0) {
      return group_fail(l.column(l.has('X') ? 'X' : l.has('Y') ? 'Y' : l.has('Z') ? 'Z' : 'R'),
                        "G6.2 control point after the closing knot-only lines; expected " +
                            std::to_string(g.order - g.closing) + " more K lines to finish the curve");
    }
    if (!nurbs_point_line(l)) return false;
  } else {
    ++g.closing;
  }
  g.knots.push_back(k);
  return true;
}

void Interpreter::nurbs_abandon() {
  if (!nurbs_.points.empty()) q_ = nurbs_.points.back();  // where the program meant to be
  known_ = nurbs_.known;
  nurbs_ = NurbsGroup{};
  motion_ = -1;
}

bool Interpreter::nurbs_close(const ParsedLine& l, MoveList& out) {
  (void)l;
  NurbsGroup g = std::move(nurbs_);
  nurbs_abandon();  // the group is over either way: position at its last control point
  q_ = g.points.back();
  known_ = g.known;
  if (g.failed) return false;  // its error was reported on the line where it happened
  const std::string gname = g.fanuc ? "G6.2" : "G5.2";
  const std::string what = gname + " NURBS curve (lines " + std::to_string(g.line) + "-" + std::to_string(l.line) + ")";
  auto curve_fail = [&](std::string message) {
    sink_.error(g.line, g.column, what + ": " + message);
    return false;
  };
  const int count = static_cast<int>(g.points.size());
  if (count < g.order) {
    return curve_fail("order " + std::to_string(g.order) + " needs at least " + std::to_string(g.order) +
                      " control points, got " + std::to_string(count) +
                      (g.fanuc ? "" : " (the current position and " + std::to_string(count - 1) + " lines)") +
                      "; expected more control points or a lower order");
  }
  NurbsCurve c;
  c.degree = g.order - 1;
  c.points.reserve(g.points.size());
  for (const Vec3& q : g.points) c.points.push_back(to_machine(q));
  c.weights = std::move(g.weights);
  if (g.fanuc) {
    c.knots = std::move(g.knots);
    // Fanuc's rule: exactly `order` equal knots at each end (the curve starts at its first
    // control point and ends at its last).
    const std::size_t n = c.knots.size();
    const auto o = static_cast<std::size_t>(g.order);
    const bool start_ok = c.knots[0] == c.knots[o - 1] && c.knots[o] > c.knots[0];
    const bool end_ok = c.knots[n - 1] == c.knots[n - o] && c.knots[n - o - 1] < c.knots[n - 1];
    if (!start_ok || !end_ok) {
      return curve_fail("its first " + std::to_string(g.order) + " and its last " + std::to_string(g.order) +
                        " knots must be equal (and no more than that many); expected clamped knots such as K0 x" +
                        std::to_string(g.order) + " ... K1 x" + std::to_string(g.order));
    }
  } else {
    c.knots = config_.gcode.nurbs_knots == static_cast<int>(KnotRule::kChordLength)
                  ? chord_length_knots(c.points, c.degree)
                  : open_uniform_knots(count, c.degree);
  }
  if (std::string why = validate(c); !why.empty()) {
    return curve_fail(why + "; expected a curve as docs/gcode.md (NURBS) describes");
  }
  bool moves = false;
  for (const Vec3& p : c.points) moves = moves || norm(p - c.points.front()) > 1e-9;
  if (!moves) return curve_fail("all its control points coincide; expected a curve that moves");
  Move m;
  m.kind = MoveKind::kNurbs;
  m.line = g.line;
  m.column = g.column;
  m.start = c.points.front();
  m.end = c.points.back();
  m.feed_mm_s = g.feed_mm_s;
  m.contouring = contouring_;
  m.known = g.known;
  m.nurbs = std::make_shared<const NurbsCurve>(std::move(c));
  out.push(m);
  return true;
}

void Interpreter::end_of_input(int line) {
  if (!nurbs_.open) return;
  const NurbsGroup& g = nurbs_;
  const bool report = !g.failed;
  const std::string message =
      g.fanuc ? "the program ends inside the G6.2 NURBS curve opened here (" + std::to_string(g.closing) + " of its " +
                    std::to_string(g.order) + " closing knot-only lines); expected " + std::to_string(g.order) +
                    " K lines to finish it"
              : std::string("the program ends inside the G5.2 NURBS curve opened here; expected G5.3 to close it");
  const int at_line = g.line, at_col = g.column;
  nurbs_abandon();
  (void)line;
  if (report) sink_.error(at_line, at_col, message);
}

}  // namespace pcnc
