// interpreter_motion.cpp — straight moves (G0/G1, G53): the axis words of a line in the
// program's units (G20/G21), distance mode (G90/G91) and offsets (G54-G59.3, G92/G52, tool
// length), turned into machine millimetres, polar coordinates (@ ^) among them; and the feed a
// move runs at.
#include <cmath>
#include <numbers>
#include <string>

#include "gcode/interpreter.hpp"
#include "gcode/interpreter_text.hpp"
#include "gcode/rotary_move.hpp"

namespace pcnc {

using namespace interp;

bool Interpreter::feed_for_move(const ParsedLine& l, int column, double& feed_mm_s, int motion) {
  if (inverse_time_) {  // G93: this line's F; the feed itself follows from the move's length
    feed_mm_s = 0.0;
    return inverse_time_check(l, column, motion);
  }
  if (!(feed_ > 0.0)) {
    return fail(l, column,
                "feed move with no feed rate in effect (F0 or no F yet" +
                    (feed_cleared_line_ > 0 ? "; G94 on line " + std::to_string(feed_cleared_line_) +
                                                  " set it to 0, as in LinuxCNC"
                                            : std::string()) +
                    "); expected an F word > 0 (units per minute)");
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

// The program point (job frame, mm) the X/Y/Z words of `l` name, starting from `from` (an
// axis not written keeps its value): the program's units (G20/G21), distance mode (G90/G91)
// and offsets (origin_: the G5x, G92/G52 and tool offsets, relative to G54). Axes written in G90 become known; first_col is
// the column of the first axis word (0: none).
Vec3 Interpreter::axis_target(const ParsedLine& l, const Vec3& from, std::uint8_t& known, int& first_col) const {
  const double u = inches_ ? kInch : 1.0;
  const Vec3& wofs = origin_;
  Vec3 q = from;
  first_col = 0;
  for (int i = 0; i < kAxes; ++i) {
    const char c = static_cast<char>('X' + i);
    if (!l.has(c)) continue;
    if (first_col == 0) first_col = l.column(c);
    const auto k = static_cast<std::size_t>(i);
    const double v = l.get(c) * u;
    if (incremental_) {
      q[k] += v;
    } else {
      q[k] = v + wofs[k];
      known = static_cast<std::uint8_t>(known | (1u << i));
    }
  }
  if ((l.present & kPolarBits) != 0) {
    // LinuxCNC's polar coordinates (G17 only, never with X or Y: polar_words_fit): @ is the
    // distance from the current coordinate system's origin in the XY plane, ^ the angle from
    // +X in degrees; the one not written keeps the current point's. In G91 both are added to
    // the current point's.
    const Vec3 p = q - wofs;
    double r = std::hypot(p[0], p[1]);
    double a = std::atan2(p[1], p[0]);
    const double deg = std::numbers::pi / 180.0;
    if (l.has('@')) r = incremental_ ? r + l.get('@') * u : l.get('@') * u;
    if (l.has('^')) a = incremental_ ? a + l.get('^') * deg : l.get('^') * deg;
    q[0] = wofs[0] + r * std::cos(a);
    q[1] = wofs[1] + r * std::sin(a);
    if (!incremental_ && l.has('@') && l.has('^')) known = static_cast<std::uint8_t>(known | 3u);
    for (const char c : {'@', '^'}) {
      if (l.has(c) && (first_col == 0 || l.column(c) < first_col)) first_col = l.column(c);
    }
  }
  return q;
}

// Polar coordinates (@ ^) on this line: only in the XY plane, never with X or Y, and (but for a
// canned cycle, whose repeats check their own holes) with an angle defined: not G91 at the
// origin, nor @ alone there in G90.
bool Interpreter::polar_words_fit(const ParsedLine& l, int motion, int normal) {
  const int col = l.has('@') ? l.column('@') : l.column('^');
  if (normal != 2) {
    return fail(l, col, "polar coordinates (@ ^) in the " + std::string(plane_name(normal)) +
                            " plane; expected G17: they name a point in the XY plane");
  }
  if (l.has('X') || l.has('Y')) {
    return fail(l, l.column(l.has('X') ? 'X' : 'Y'), std::string(1, l.has('X') ? 'X' : 'Y') +
                                                          " word with polar coordinates (@ ^); expected either X and Y or @ and ^");
  }
  if (is_cycle(motion)) return true;
  const Vec3 p = program_point();
  if (std::hypot(p[0], p[1]) > 1e-9) return true;
  if (incremental_) {
    return fail(l, col, "polar coordinates (@ ^) in G91 at the origin: the current point has no angle; expected G90, "
                        "or a move off the origin first");
  }
  if (!l.has('^')) {
    return fail(l, col, "@ without ^ at the origin: the current point has no angle; expected ^ (degrees) too");
  }
  return true;
}

bool Interpreter::straight(const ParsedLine& l, int motion, bool g53, MoveList& out) {
  Vec3 q = q_;
  Vec3 end = to_machine(q_);
  std::uint8_t known = known_;
  int column = motion == l.g[kGMotion] ? l.g_col[kGMotion] : 0;
  if (g53 && incremental_) return fail(l, l.g_col[kGNonModal], "G53 in incremental mode (G91); expected G90 with G53");
  if (g53) {
    // machine coordinates: units only, no offset, no --fit frame
    const double u = inches_ ? kInch : 1.0;
    for (int i = 0; i < kAxes; ++i) {
      const char c = static_cast<char>('X' + i);
      if (!l.has(c)) continue;
      const auto k = static_cast<std::size_t>(i);
      end[k] = l.get(c) * u;
      q[k] = (end[k] - frame_.offset[k]) / frame_.scale;
      known = static_cast<std::uint8_t>(known | (1u << i));
    }
    column = l.g_col[kGNonModal];
  } else {
    int first_col = 0;
    q = axis_target(l, q_, known, first_col);
    if (column == 0) column = first_col;
  }
  Move m = base_move(motion == 0 ? MoveKind::kRapid : MoveKind::kLine, l, column);
  const Rot3 rot = rotary_target(l);
  // only the tool turns: F is in deg/min, not limited by the linear axes' maximum feed
  const bool turn_only = !g53 && rot != rot_ && norm(to_machine(q) - to_machine(q_)) <= 1e-9;
  if (rot != rot_ && comp_.side != 0) {
    return fail(l, column > 0 ? column : l.g_col[kGMotion],
                "a rotary joint does not turn under cutter radius compensation (G41/G42); expected G40 first");
  }
  m.rot_end = rot;
  if (column == 0) {
    for (int i = 0; i < kRotaryJoints; ++i) {
      if (column == 0 && l.has(joint_letter(i))) column = l.column(joint_letter(i));
    }
    m.column = column;
  }
  if (motion == 10 && turn_only && !inverse_time_ && !(feed_ > 0.0)) {
    rot_ = rot;
    return fail(l, column, "feed move with no feed rate in effect (F0 or no F yet); expected an F word > 0 (deg/min for a move that only turns the tool)");
  }
  if (motion == 10 && !(turn_only && !inverse_time_) && !feed_for_move(l, column, m.feed_mm_s)) {
    q_ = q;  // keep following the program after the error
    known_ = known;
    return false;
  }
  if (!g53) end = to_machine(q);
  m.end = end;
  rot_ = rot;
  if (motion == 10 && !inverse_time_ && angular_move(m)) m.feed_mm_s = feed_ * kRadPerDeg / 60.0;  // F in deg/min
  if (motion == 10 && inverse_time_ && !inverse_time_feed(l, m)) {
    q_ = q;
    known_ = known;
    return false;
  }
  m.machine_frame = g53;
  m.known = known;
  q_ = q;
  known_ = known;
  out.push(m);  // even with no displacement: under --fit the same line may move (the stream skips it)
  return true;
}

}  // namespace pcnc
