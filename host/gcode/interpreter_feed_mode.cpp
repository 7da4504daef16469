// interpreter_feed_mode.cpp — the feed mode in the interpreter: G94 (F in units per minute,
// the default) and G93 (inverse time, LinuxCNC's semantics): in G93 every G1, G2 and G3 line
// carries its own F and its move takes 1/F minutes, so its feed is the move's length (machine
// mm, after --fit) over that time, capped by the machine like any feed. G94 sets the feed rate
// to 0 (as LinuxCNC does): a G1 after it needs a new F. docs/gcode.md, "Inverse time feed".
#include <string>

#include "gcode/interpreter.hpp"
#include "gcode/interpreter_text.hpp"
#include "gcode/preflight.hpp"
#include "gcode/rotary_move.hpp"
#include "gcode/words.hpp"

namespace pcnc {

using namespace interp;

void Interpreter::feed_mode(const ParsedLine& l) {
  const int code = l.g[kGFeedMode];
  if (code == 930) {
    inverse_time_ = true;
  } else if (code == 940) {
    inverse_time_ = false;
    if (feed_ > 0.0) feed_cleared_line_ = l.line;
    feed_ = 0.0;  // LinuxCNC: G94 sets the feed rate to 0 (an F on the same line then sets it)
  }
}

// G93: what this line must carry for a feed move of `motion` (G number x10), with LinuxCNC's
// errors: an F word > 0 on every G1/G2/G3 line; no canned cycle; (pcnc) no NURBS curve.
bool Interpreter::inverse_time_check(const ParsedLine& l, int column, int motion) {
  if (is_cycle(motion)) {
    return fail(l, column,
                "cannot use inverse time feed with canned cycles (G93 in effect); expected G94 and an F word before "
                "the cycle");
  }
  if (motion == 52 || motion == 62 || motion == 50 || motion == 51) {
    const char* name = motion == 52 ? "G5.2 NURBS curve" : motion == 62 ? "G6.2 NURBS curve" : motion == 50 ? "G5 spline" : "G5.1 spline";
    return fail(l, column,
                std::string(name) + " in inverse time feed mode (G93) is not supported; expected G94 and an F word before "
                                    "the curve");
  }
  if (!l.has('F')) {
    return fail(l, column,
                std::string("F word missing with inverse time ") + (is_arc(motion) ? "arc" : "G1") +
                    " move; expected an F word on every G1, G2 and G3 line in G93 (the move takes 1/F minutes)");
  }
  if (!(l.get('F') > 0.0)) {
    return fail(l, l.column('F'),
                "F0 in inverse time feed mode (G93) would make the move take forever; expected F > 0 (the move takes "
                "1/F minutes)");
  }
  return true;
}

// G93: the feed of a line or arc whose geometry is made: its length over 1/F minutes, clamped
// to the machine maximum (with a warning; an error when the config refuses excess feeds).
bool Interpreter::inverse_time_feed(const ParsedLine& l, Move& m) {
  const double f = l.get('F');
  const double time_s = 60.0 / f;
  m.inverse_time_s = time_s;
  if (angular_move(m)) {  // only the tool turns: the time is the turn's (rad/s)
    m.feed_mm_s = angular_length(m, config_) / time_s;
    return true;
  }
  const double length = move_length(m);
  double feed = length / time_s;
  if (!(feed > 0.0)) feed = max_feed_mm_s_;  // no length: no motion, any feed
  if (feed > max_feed_mm_s_ * (1.0 + 1e-12)) {
    const std::string what = "G93 F" + num(f) + ": " + num(length) + " mm in " + num(time_s) + " s needs " +
                             num(feed) + " mm/s, above the machine maximum feed of " + num(max_feed_mm_s_) + " mm/s";
    if (!config_.gcode.clamp_excess_feed) {
      return fail(l, l.column('F'),
                  what + "; expected F <= " + num(max_feed_mm_s_ * 60.0 / length) + " for this move");
    }
    warn(l, l.column('F'), "feed-clamp-g93", [&] { return what + "; clamped: the move takes longer"; });
    feed = max_feed_mm_s_;
  }
  m.feed_mm_s = feed;
  return true;
}

}  // namespace pcnc
