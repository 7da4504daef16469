// biarc_rewrite.cpp — NURBS groups and smooth G1 runs as G2/G3 biarcs. See biarc_rewrite.hpp.
#include "biarc_rewrite.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "biarc_program.hpp"
#include "geometry/biarc.hpp"
#include "geometry/plane.hpp"

namespace pcnc {
namespace {

using Kind = BiarcLineKind;
constexpr char kAxisLetter[3] = {'X', 'Y', 'Z'};
constexpr char kOffset[3] = {'I', 'J', 'K'};

// At most 6 decimals, trailing zeros trimmed, never "-0".
std::string num6(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.6f", v);
  std::string s = buf;
  while (!s.empty() && s.back() == '0') s.pop_back();
  if (!s.empty() && s.back() == '.') s.pop_back();
  if (s == "-0" || s.empty()) s = "0";
  return s;
}

double round6(double v) { return std::round(v * 1e6) / 1e6; }

// The plane axes of a state can place a run: known absolutely, or all increments with
// relative arc centres.
bool placeable(const BiarcModal& m) {
  const auto pa = plane_axes(m.normal);
  const bool known = m.known[static_cast<std::size_t>(pa[0])] && m.known[static_cast<std::size_t>(pa[1])];
  return !m.inverse_time && (known || (m.incremental && !m.arc_absolute));
}

// A later line moves by the modal motion mode before any line names one (a G5/G5.1 line that
// is rewritten itself does not count: `spline_rewritten`).
bool modal_motion_follows(const std::vector<BiarcLine>& lines, std::size_t from, bool spline_rewritten = false) {
  for (std::size_t k = from; k < lines.size(); ++k) {
    if (lines[k].kind == Kind::kOpaque) return true;
    if (spline_rewritten && lines[k].kind == Kind::kSpline) continue;
    if (lines[k].explicit_motion) return false;
    if (lines[k].uses_modal_motion) return true;
  }
  return false;
}

// Writes arcs (plane coordinates, mm) as G-code lines in the state `m`, from the written
// point `start` (program units, plane coordinates) to `end` exactly.
struct ArcWriter {
  const BiarcModal& m;
  std::string eol;
  std::string out;
  int lines = 0;

  void write(const std::vector<Arc2>& arcs, Vec2 start, Vec2 end, bool with_feed) {
    const auto pa = plane_axes(m.normal);
    const double s = 1.0 / m.scale;
    Vec2 q = start;  // where the controller stands
    for (std::size_t i = 0; i < arcs.size(); ++i) {
      const Arc2& a = arcs[i];
      const bool last = i + 1 == arcs.size();
      const Vec2 t = last ? end : Vec2{round6(a.end.x * s), round6(a.end.y * s)};
      const double chord = distance(q, t);
      const double sagitta = a.line ? 0.0 : a.radius * (1.0 - std::cos(0.5 * std::abs(a.sweep)));
      const bool as_line = a.line || sagitta < 1e-6 || chord < 1e-5 || std::abs(a.sweep) > 1.999 * std::numbers::pi;
      std::string l = as_line ? "G1" : a.sweep > 0.0 ? "G3" : "G2";
      const Vec2 d = m.incremental ? t - q : t;
      // axis words in X Y Z order
      const double v0 = d.x, v1 = d.y;
      if (pa[0] < pa[1]) l += std::string(" ") + kAxisLetter[pa[0]] + num6(v0) + " " + kAxisLetter[pa[1]] + num6(v1);
      else l += std::string(" ") + kAxisLetter[pa[1]] + num6(v1) + " " + kAxisLetter[pa[0]] + num6(v0);
      if (!as_line) {
        const Vec2 c{a.centre.x * s, a.centre.y * s};
        const Vec2 off = m.arc_absolute ? c : c - q;
        if (pa[0] < pa[1]) l += std::string(" ") + kOffset[pa[0]] + num6(off.x) + " " + kOffset[pa[1]] + num6(off.y);
        else l += std::string(" ") + kOffset[pa[1]] + num6(off.y) + " " + kOffset[pa[0]] + num6(off.x);
      }
      if (with_feed && i == 0) l += " F" + num6(m.feed);
      out += l + eol;
      ++lines;
      q = t;
    }
  }
};

struct Rewriter {
  const BiarcRewriteOptions& opt;
  BiarcRewriteReport& rep;
  const std::vector<BiarcLine>& lines;
  std::string out;

  void pass(std::size_t i) {
    out += lines[i].text + (i + 1 < lines.size() || trailing_newline ? "\n" : "");
    ++rep.lines_out;
  }
  bool trailing_newline = true;

  Vec2 plane_point(const Vec3& p, int normal) const { return to_plane(p, normal); }

  // Loop removal for the configured tool, on the side(s) that apply.
  std::vector<Arc2> without_loops(std::vector<Arc2> arcs, const BiarcModal& m, BiarcRewriteItem& item) const {
    if (!(opt.max_tool_radius_mm > 0.0)) return arcs;
    std::vector<int> sides;
    if (opt.side != 0) sides = {opt.side};
    else if (m.comp != 0) sides = {m.comp};
    else sides = {1, -1};
    const std::vector<Arc2> original = arcs;
    for (int side : sides) {
      const LoopRemoval r = remove_loops(arcs, opt.max_tool_radius_mm, side);
      item.loops_removed += r.loops_removed;
      item.unresolved += r.unresolved;
      arcs = r.arcs;
    }
    if (item.loops_removed > 0)
      for (const Arc2& a : arcs)
        for (int k = 0; k <= 16; ++k) item.loop_change_mm = std::max(item.loop_change_mm, nearest_on_arcs(original, arc_point(a, k / 16.0)));
    return arcs;
  }

  void emit(const std::vector<Arc2>& arcs, const BiarcModal& m, Vec3 start_mm, Vec3 end_mm, bool with_feed,
            std::size_t first, BiarcRewriteItem& item) {
    const std::string& t = lines[first].text;
    ArcWriter w{m, (!t.empty() && t.back() == '\r') ? "\r\n" : "\n", {}, 0};
    const double s = 1.0 / m.scale;
    // the controller's own start (unrounded) and the program's end exactly
    w.write(arcs, s * plane_point(start_mm, m.normal), s * plane_point(end_mm, m.normal), with_feed);
    out += w.out;
    rep.lines_out += w.lines;
    item.moves_out = w.lines;
    rep.items.push_back(item);
  }

  // G5.2 at i: returns the index after the group, or i when it was not rewritten.
  std::size_t nurbs(std::size_t i) {
    std::size_t j = i + 1;
    while (j < lines.size() && lines[j].kind == Kind::kNurbsPoint) ++j;
    if (j >= lines.size() || lines[j].kind != Kind::kNurbsEnd) return i;
    const BiarcModal& m = lines[i].before;
    const std::string at = "line " + std::to_string(lines[i].number) + ": ";
    if (!placeable(m)) {
      rep.notes.push_back(at + "G5.2 left as it is: " + (m.inverse_time ? "G93 inverse time feed" : "its start point is not known"));
      return i;
    }
    if (modal_motion_follows(lines, j + 1)) {
      rep.notes.push_back(at + "G5.2 left as it is: a later line moves by the modal motion mode after G5.3");
      return i;
    }
    NurbsCurve c;
    c.points.push_back(m.pos);
    const bool point_on_start = lines[i].has_plane_axes;
    c.weights.push_back(point_on_start ? 1.0 : lines[i].weight);
    if (point_on_start) c.points.push_back(lines[i].after.pos), c.weights.push_back(lines[i].weight);
    for (std::size_t k = i + 1; k < j; ++k) c.points.push_back(lines[k].after.pos), c.weights.push_back(lines[k].weight);
    const int order = lines[i].order;
    if (order < 2 || order > kMaxNurbsDegree + 1 || static_cast<int>(c.points.size()) < order) {
      rep.notes.push_back(at + "G5.2 left as it is: order L" + std::to_string(order) + " with " +
                          std::to_string(c.points.size()) + " control points");
      return i;
    }
    c = make_nurbs(c.points, c.weights, order);
    if (const std::string why = validate(c); !why.empty()) {
      rep.notes.push_back(at + "G5.2 left as it is: " + why);
      return i;
    }
    BiarcOptions bo;
    bo.tolerance_mm = opt.tolerance_mm;
    const BiarcFit fit = fit_biarcs(c, m.normal, bo);
    BiarcRewriteItem item;
    item.first_line = lines[i].number;
    item.last_line = lines[j].number;
    item.nurbs = true;
    item.moves_in = 1;
    item.deviation_mm = fit.max_deviation_mm;
    item.within_tolerance = fit.within_tolerance;
    const bool feed = lines[i].has_feed || lines[j].has_feed;
    emit(without_loops(fit.arcs, m, item), lines[j].after, c.points.front(), c.points.back(), feed, i, item);
    return j + 1;
  }

  // A G5/G5.1 line at i: its Bézier curve as biarcs; false when it is left as it is.
  bool spline(std::size_t i) {
    const BiarcLine& l = lines[i];
    const BiarcModal& m = l.before;
    const std::string at = "line " + std::to_string(l.number) + ": ";
    const std::string g = l.spline_degree == 3 ? "G5" : "G5.1";
    if (!placeable(m)) {
      rep.notes.push_back(at + g + " left as it is: its start point is not known");
      return false;
    }
    if (modal_motion_follows(lines, i + 1, true)) {
      rep.notes.push_back(at + g + " left as it is: a later line moves by the modal motion mode");
      return false;
    }
    // the next move continues this G5 (no I J) but stays a G5 line: this one must stay a G5 too
    for (std::size_t k = i + 1; k < lines.size(); ++k) {
      if (lines[k].kind == Kind::kSpline) break;
      if (lines[k].spline_continuation) {
        rep.notes.push_back(at + g + " left as it is: line " + std::to_string(lines[k].number) + " continues it and is not rewritten");
        return false;
      }
      if (lines[k].explicit_motion || lines[k].uses_modal_motion || lines[k].kind == Kind::kOpaque) break;
    }
    const Vec3 s = m.pos, e = l.after.pos;
    std::vector<Vec3> points = {s, s + l.spline_c1};
    if (l.spline_degree == 3) points.push_back(e + l.spline_c2);
    points.push_back(e);
    bool moves = false;
    for (const Vec3& p : points) moves = moves || norm(p - s) > 1e-9;
    if (!moves) {
      rep.notes.push_back(at + g + " left as it is: its control points all coincide");
      return false;
    }
    NurbsCurve c = make_nurbs(points, std::vector<double>(points.size(), 1.0), l.spline_degree + 1);
    if (const std::string why = validate(c); !why.empty()) {
      rep.notes.push_back(at + g + " left as it is: " + why);
      return false;
    }
    BiarcOptions bo;
    bo.tolerance_mm = opt.tolerance_mm;
    const BiarcFit fit = fit_biarcs(c, m.normal, bo);
    BiarcRewriteItem item;
    item.first_line = item.last_line = l.number;
    item.nurbs = true;
    item.spline_degree = l.spline_degree;
    item.moves_in = 1;
    item.deviation_mm = fit.max_deviation_mm;
    item.within_tolerance = fit.within_tolerance;
    emit(without_loops(fit.arcs, m, item), l.after, s, e, l.has_feed, i, item);
    return true;
  }

  // Plain G1 lines first..last (inclusive): smooth runs rewritten, the rest passed.
  void g1_lines(std::size_t first, std::size_t last) {
    const double max_turn = opt.max_turn_deg * std::numbers::pi / 180.0;
    const int n = lines[first].before.normal;
    std::size_t a = first;
    while (a <= last) {
      // the run from a: short segments turning little at each junction
      std::size_t b = a;
      Vec2 dir{};
      auto seg = [&](std::size_t k) { return plane_point(lines[k].after.pos, n) - plane_point(lines[k].before.pos, n); };
      if (norm(seg(a)) < opt.max_segment_mm) {
        dir = normalized(seg(a));
        while (b + 1 <= last) {
          const Vec2 v = seg(b + 1);
          if (!(norm(v) < opt.max_segment_mm)) break;
          if (norm(v) > 0.0) {
            const Vec2 u = normalized(v);
            if (norm(dir) > 0.0 && std::abs(std::atan2(cross(dir, u), dot(dir, u))) >= max_turn) break;
            dir = u;
          }
          ++b;
        }
      }
      const int count = static_cast<int>(b - a + 1);
      if (norm(seg(a)) >= opt.max_segment_mm || count < opt.min_moves) {
        for (std::size_t k = a; k <= b; ++k) pass(k);
        a = b + 1;
        continue;
      }
      // G1 stays in force when a later line relies on it: the last move is written as G1
      run(a, b, modal_motion_follows(lines, b + 1));
      a = b + 1;
    }
  }

  void run(std::size_t a, std::size_t b, bool last_as_g1) {
    const BiarcModal& m = lines[a].before;
    const int n = m.normal;
    std::vector<Vec2> pts{plane_point(m.pos, n)};
    bool feed = false;
    for (std::size_t k = a; k <= b; ++k) pts.push_back(plane_point(lines[k].after.pos, n)), feed = feed || lines[k].has_feed;
    const Vec2 last = pts.back();
    if (last_as_g1) pts.pop_back();
    BiarcOptions bo;
    bo.tolerance_mm = opt.tolerance_mm;
    const PolylineFit fit = fit_biarcs_polyline(pts, bo);
    BiarcRewriteItem item;
    item.first_line = lines[a].number;
    item.last_line = lines[b].number;
    item.moves_in = static_cast<int>(b - a + 1);
    item.deviation_mm = fit.max_point_deviation_mm;
    item.segment_deviation_mm = fit.max_segment_deviation_mm;
    item.sagitta_mm = fit.max_sagitta_mm;
    item.within_tolerance = fit.within_tolerance;
    if (fit.arcs.empty() || fit.arcs.size() + (last_as_g1 ? 1 : 0) >= b - a + 1) {  // null moves, or no fewer blocks
      if (!fit.arcs.empty())
        rep.notes.push_back("lines " + std::to_string(lines[a].number) + "-" + std::to_string(lines[b].number) + ": " +
                            std::to_string(b - a + 1) + " G1 moves left as they are: the biarcs within the tolerance need " +
                            std::to_string(fit.arcs.size()));
      for (std::size_t k = a; k <= b; ++k) pass(k);
      return;
    }
    std::vector<Arc2> arcs = without_loops(fit.arcs, m, item);
    if (last_as_g1) arcs.push_back(make_segment(arcs.back().end, last));
    emit(arcs, lines[b].after, m.pos, lines[b].after.pos, feed, a, item);
  }
};

}  // namespace

std::string rewrite_biarcs(const std::string& text, const BiarcRewriteOptions& options, BiarcRewriteReport& report) {
  const std::vector<BiarcLine> lines = read_biarc_program(text);
  Rewriter r{options, report, lines, {}};
  r.trailing_newline = !text.empty() && text.back() == '\n';
  report.lines_in = static_cast<int>(lines.size());
  bool told_opaque = false;
  std::size_t i = 0;
  while (i < lines.size()) {
    const BiarcLine& l = lines[i];
    if (l.kind == Kind::kOpaque && !told_opaque) {
      report.notes.push_back("line " + std::to_string(l.number) +
                             ": control flow, parameters or expressions: nothing is rewritten from here on");
      told_opaque = true;
    }
    if (l.kind == Kind::kNurbsStart) {
      const std::size_t next = r.nurbs(i);
      if (next != i) {
        i = next;
        continue;
      }
    }
    if (l.kind == Kind::kSpline && r.spline(i)) {
      ++i;
      continue;
    }
    if (l.kind == Kind::kG1 && placeable(l.before)) {
      // the plain G1 lines that follow at one feed
      std::size_t j = i;
      while (j + 1 < lines.size() && lines[j + 1].kind == Kind::kG1 && lines[j + 1].after.feed == l.after.feed) ++j;
      r.g1_lines(i, j);
      i = j + 1;
      continue;
    }
    r.pass(i);
    ++i;
  }
  return r.out;
}

}  // namespace pcnc
