// interpreter_arc.cpp — G2/G3 arcs and helices in the selected plane: centre from I/J/K or
// R, the radius check (the config's tolerance, LinuxCNC's rule), the sweep, P turns (full
// circles before the arc), and the Moves in machine coordinates.
#include <algorithm>
#include <cmath>
#include <string>

#include "gcode/interpreter.hpp"
#include "gcode/interpreter_text.hpp"
#include "gcode/preflight.hpp"

namespace pcnc {

using namespace interp;

namespace {
// The most turns one G2/G3 line may ask for (P): each is a move of its own.
constexpr int kMaxArcTurns = 10000;
}  // namespace

bool Interpreter::arc(const ParsedLine& l, int motion, MoveList& out) {
  const double u = inches_ ? kInch : 1.0;
  const int n = normal_axis_;
  const auto pa = plane_axes(n);
  const auto a0 = static_cast<std::size_t>(pa[0]);
  const auto a1 = static_cast<std::size_t>(pa[1]);
  const char* plane = plane_name(n);
  std::uint8_t known = known_;
  int column = motion == l.g[kGMotion] ? l.g_col[kGMotion] : 0;
  int first_col = 0;
  const Vec3 e = axis_target(l, q_, known, first_col);
  if (column == 0) column = first_col;
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
  // P: the number of turns (LinuxCNC): P - 1 full circles before the programmed arc, the helix
  // shared along the whole sweep. An integer of at least 1 (LinuxCNC rounds; a fraction is an error there too).
  int turns = 1;
  if (l.has('P')) {
    const double p = l.get('P');
    const double whole_turns = std::round(p);
    if (!(std::fabs(p - whole_turns) < 1e-4) || whole_turns < 1.0) {
      return fail_here(l.column('P'), "P" + num(p) + " on " + gname + " is not a number of turns; expected a positive integer (P2: one more full circle before the arc)");
    }
    if (whole_turns > kMaxArcTurns) {
      return fail_here(l.column('P'), "P" + num(p) + " on " + gname + " asks for more than " + std::to_string(kMaxArcTurns) + " turns; expected at most that many in one line");
    }
    turns = static_cast<int>(whole_turns);
  }
  Move m = base_move(MoveKind::kArc, l, column);
  if (!feed_for_move(l, column, m.feed_mm_s, motion)) {
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
    if (arc_absolute_) {  // G90.1: the center in program coordinates (a missing word: 0)
      cu = (l.has(l0) ? l.get(l0) * u : 0.0) + origin_[a0];
      cv = (l.has(l1) ? l.get(l1) * u : 0.0) + origin_[a1];
    } else {
      cu = su + (l.has(l0) ? l.get(l0) * u : 0.0);
      cv = sv + (l.has(l1) ? l.get(l1) * u : 0.0);
    }
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
    // The rt runs the arc as a spiral from the start radius to the end one and checks both
    // against the block's radius (ipc/block_check.cpp): the mean keeps each within half the
    // difference accepted here, inside the rt's tolerance (bad-block-z.ngc: r_start and r_end
    // 3.5 µm apart in G20, accepted here, refused by the rt against r_start).
    r = 0.5 * (r1 + r2);
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
  const Vec3 start = s;
  q_ = e;
  known_ = known;
  if (turns == 1) {
    if (inverse_time_ && !inverse_time_feed(l, m)) return false;
    out.push(m);
    return true;
  }
  // More turns: the full circles first, then the programmed arc, each a move of its own (so
  // every later stage sees ordinary arcs), the normal axis moving in proportion to the angle.
  const double turn = sweep > 0.0 ? kTwoPi : -kTwoPi;
  const double total = sweep + turn * (turns - 1);
  Move whole = m;  // G93: F is the time of the whole line
  whole.sweep = total;
  if (inverse_time_ && !inverse_time_feed(l, whole)) return false;
  const double whole_length = move_length(whole);
  const auto nk = static_cast<std::size_t>(n);
  Vec3 at = start;
  for (int k = 0; k < turns; ++k) {
    Move piece = m;
    Vec3 to = e;
    if (k < turns - 1) {
      to = start;
      to[nk] += (e[nk] - start[nk]) * turn * (k + 1) / total;
      piece.sweep = turn;
      piece.radius = std::hypot(su - cu, sv - cv) * frame_.scale;  // a full circle: its start radius
    }
    Vec3 cc = c;
    cc[nk] = at[nk];  // the center on the piece's start level
    piece.start = to_machine(at);
    piece.end = to_machine(to);
    piece.center = to_machine(cc);
    if (inverse_time_) {
      piece.feed_mm_s = whole.feed_mm_s;
      piece.inverse_time_s = whole_length > 0.0 ? whole.inverse_time_s * move_length(piece) / whole_length : 0.0;
    }
    out.push(piece);
    at = to;
  }
  return true;
}

}  // namespace pcnc
