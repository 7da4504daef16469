// interpreter_nurbs.cpp — the NURBS groups: LinuxCNC's G5.2 ... G5.3 and Fanuc's G6.2 ...
// closing knots, collected line by line and handed on as one Move.
#include <cmath>
#include <limits>
#include <memory>
#include <string>

#include "geometry/nurbs.hpp"
#include "gcode/interpreter.hpp"
#include "gcode/interpreter_text.hpp"
#include "gcode/nurbs_move.hpp"

namespace pcnc {

using namespace interp;

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
  if (!feed_for_move(l, col, g.feed_mm_s, motion)) return false;
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
      int first_col = 0;
      const Vec3 q = axis_target(l, q_, g.known, first_col);
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
  int axis_col = 0;
  g.points.push_back(axis_target(l, g.points.back(), g.known, axis_col));
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
  m.path_tolerance_mm = path_tolerance_;
  m.known = g.known;
  m.comp = comp_;  // under G41/G42 the compensation fits it with biarcs
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
