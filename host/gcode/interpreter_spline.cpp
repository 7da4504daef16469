// interpreter_spline.cpp — LinuxCNC's G5 (cubic spline) and G5.1 (quadratic spline) in the XY
// plane, as the exact NURBS curves they are: a G5 is the cubic Bézier from the current point to
// X Y whose inner control points are the start + (I, J) and the end + (P, Q); a G5.1 the
// quadratic Bézier with its control point at the start + (I, J). The Move is a NURBS move
// (degree 3 or 2, weights 1, one span), planned and run like a G5.2 curve.
//
// LinuxCNC's rules (its G-code reference): P and Q on every G5; I and J both or neither, and
// neither only after a G5 of the same series, whose end direction the new cubic then takes (I, J
// = the previous -P, -Q); G5.1 needs I and J; only X and Y move; the plane must be G17.
#include <memory>
#include <string>
#include <vector>

#include "gcode/interpreter.hpp"
#include "gcode/interpreter_text.hpp"
#include "geometry/nurbs.hpp"

namespace pcnc {

using namespace interp;

bool Interpreter::spline(const ParsedLine& l, int motion, MoveList& out) {
  const double u = inches_ ? kInch : 1.0;
  const bool cubic = motion == 50;
  const std::string gname = cubic ? "G5" : "G5.1";
  std::uint8_t known = known_;
  int column = motion == l.g[kGMotion] ? l.g_col[kGMotion] : 0;
  int first_col = 0;
  const Vec3 e = axis_target(l, q_, known, first_col);
  if (column == 0) column = first_col;
  for (const char c : {'I', 'J', 'P', 'Q'}) {
    if (column == 0 && l.has(c)) column = l.column(c);
  }
  // On an error the position still moves to the programmed end point (as for arcs): the lines
  // after it are checked from where the program believes it is. The series ends.
  auto fail_here = [&](int col, std::string message) {
    q_ = e;
    known_ = known;
    spline_series_ = false;
    return fail(l, col, std::move(message));
  };
  if (normal_axis_ != 2)
    return fail_here(column, gname + " spline outside the XY plane; expected G17 (a spline moves X and Y only, as in LinuxCNC)");
  if (l.has('Z'))
    return fail_here(l.column('Z'), "Z word on a " + gname + " spline: a spline moves X and Y only; expected Z on a move of its own");
  if (!l.has('I') != !l.has('J')) {
    return fail_here(l.column(l.has('I') ? 'I' : 'J'),
                     gname + " with only one of I and J; expected both (the first control point's offset from the "
                             "start)" + (cubic ? std::string(" or neither (to continue the previous G5 smoothly)") : std::string()));
  }
  Move m = base_move(MoveKind::kNurbs, l, column);
  if (!feed_for_move(l, column, m.feed_mm_s, motion)) {
    q_ = e;
    known_ = known;
    spline_series_ = false;
    return false;
  }
  const Vec3& s = q_;
  const Vec3 ij{l.has('I') ? l.get('I') * u : 0.0, l.has('J') ? l.get('J') * u : 0.0, 0.0};
  std::vector<Vec3> points;  // job frame
  if (cubic) {
    if (!l.has('P') || !l.has('Q'))
      return fail_here(column, "G5 without both P and Q; expected P and Q (the second control point's offset from the end point) on every G5");
    Vec3 c1;
    if (l.has('I')) {
      c1 = s + ij;
    } else if (spline_series_) {
      c1 = s + spline_next_;  // the previous cubic's end direction
    } else {
      return fail_here(column, "G5 without I and J that does not follow a G5; expected I and J (the first control "
                               "point's offset from the start) on the first G5 of a series");
    }
    const Vec3 pq{l.get('P') * u, l.get('Q') * u, 0.0};
    points = {s, c1, e + pq, e};
    spline_next_ = -1.0 * pq;
  } else {
    if (!l.has('I'))
      return fail_here(column, "G5.1 without I and J; expected I and J (the control point's offset from the start)");
    points = {s, s + ij, e};
  }
  NurbsCurve c;
  c.degree = cubic ? 3 : 2;
  for (const Vec3& p : points) c.points.push_back(to_machine(p));
  c.weights.assign(points.size(), 1.0);
  c.knots.assign(static_cast<std::size_t>(c.degree + 1), 0.0);
  c.knots.insert(c.knots.end(), static_cast<std::size_t>(c.degree + 1), 1.0);
  bool moves = false;
  for (const Vec3& p : c.points) moves = moves || norm(p - c.points.front()) > 1e-9;
  if (!moves) return fail_here(column, gname + " spline whose control points all coincide; expected a spline that moves");
  if (std::string why = validate(c); !why.empty()) return fail_here(column, gname + " spline: " + why);
  m.start = c.points.front();
  m.end = c.points.back();
  m.known = known;
  m.nurbs = std::make_shared<const NurbsCurve>(std::move(c));
  q_ = e;
  known_ = known;
  spline_series_ = cubic;
  out.push(m);
  return true;
}

}  // namespace pcnc
