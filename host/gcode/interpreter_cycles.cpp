// interpreter_cycles.cpp — canned cycles (G73, G81, G82, G83, G85, G89) in the interpreter:
// the line's words in mm, expanded by canned_cycle.hpp into rapids, feeds and dwells in
// program coordinates, then placed like any other move (offsets, --fit).
#include <cmath>
#include <string>
#include <vector>

#include "gcode/interpreter.hpp"
#include "gcode/interpreter_text.hpp"
#include "gcode/words.hpp"

namespace pcnc {

using namespace interp;

bool Interpreter::cycle(const ParsedLine& l, int motion, bool first_of_series, MoveList& out) {
  const double u = inches_ ? kInch : 1.0;
  const int column = l.g[kGMotion] == motion ? l.g_col[kGMotion]
                     : l.column(l.has('X') ? 'X' : l.has('Y') ? 'Y' : l.has('@') ? '@' : l.has('^') ? '^' : 'Z');
  if (inverse_time_ && !inverse_time_check(l, column, motion)) return false;
  CycleInput in{};
  in.code10 = motion;
  in.normal_axis = normal_axis_;
  in.retract_r = retract_r_;
  in.incremental = incremental_;
  in.first_of_series = first_of_series;
  in.position = program_point();
  for (int i = 0; i < kAxes; ++i) {
    const char c = static_cast<char>('X' + i);
    in.has[static_cast<std::size_t>(i)] = l.has(c);
    in.axis[static_cast<std::size_t>(i)] = l.has(c) ? l.get(c) * u : 0.0;
  }
  in.has_radius = l.has('@');
  in.radius = l.has('@') ? l.get('@') * u : 0.0;
  in.has_angle = l.has('^');
  in.angle_deg = l.has('^') ? l.get('^') : 0.0;
  in.has_r = l.has('R');
  in.r = l.has('R') ? l.get('R') * u : 0.0;
  in.has_p = l.has('P');
  in.p = l.has('P') ? l.get('P') : 0.0;
  in.has_q = l.has('Q');
  in.q = l.has('Q') ? l.get('Q') * u : 0.0;
  in.has_l = l.has('L');
  in.l = l.has('L') ? static_cast<long>(std::lround(l.get('L'))) : 1;
  if (l.has('L') && l.get('L') != std::floor(l.get('L')))
    return fail(l, l.column('L'), "L" + num(l.get('L')) + ": expected a whole number of repeats");
  std::vector<CycleStep> steps;
  const CycleResult r = expand_canned_cycle(in, cycle_, steps);
  if (!r.ok) return fail(l, r.error_letter != 0 && l.has(r.error_letter) ? l.column(r.error_letter) : column, r.error);
  double feed = 0.0;
  bool have_feed = false;
  for (const CycleStep& s : steps) {
    if (out.count >= MoveList::kMaxPerLine)
      return fail(l, column, "the canned cycle makes more than 100000 moves; expected fewer repeats or deeper pecks");
    if (s.kind == CycleStepKind::kDwell) {
      Move m = base_move(MoveKind::kDwell, l, column);
      m.dwell_s = s.dwell_s;
      out.push(m);
      continue;
    }
    Move m = base_move(s.kind == CycleStepKind::kFeed ? MoveKind::kLine : MoveKind::kRapid, l, column);
    if (s.kind == CycleStepKind::kFeed) {
      if (!have_feed && !feed_for_move(l, column, feed)) return false;
      have_feed = true;
      m.feed_mm_s = feed;
    }
    const Vec3 q = s.target + origin_;
    m.end = to_machine(q);
    known_ = 7;
    m.known = known_;
    q_ = q;
    out.push(m);
  }
  return true;
}

}  // namespace pcnc
