// test_biarc_rewrite.cpp — the text transformation of `pcnc biarc` (tools/biarc_rewrite.hpp)
// on small programs written here: incremental (G91) and inch (G20) runs, CRLF line endings,
// the feed, a run too short or too sharp to rewrite, a program with parameters (nothing
// rewritten after them), G93 (nothing rewritten), a G18 run; G5/G5.1 splines as arcs.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "biarc_rewrite.hpp"
#include "text_lines.hpp"

namespace pcnc {
namespace {

// `count` moves along a circle of radius r (mm), 2 degrees each, as plain axis lines in the
// given units and distance mode; a G1 line with F first. Returns the program.
std::string circle_run(int count, double r, bool inch, bool incremental, const std::string& eol = "\n") {
  const double u = inch ? 25.4 : 1.0;
  std::string p = std::string(inch ? "G20" : "G21") + (incremental ? " G91" : " G90") + " G17" + eol;
  p += "G0 X0 Y0" + eol;  // absolute or a zero increment: the start is known or relative
  double px = 0, py = 0;
  for (int i = 1; i <= count; ++i) {
    const double a = i * M_PI / 90.0;
    const double x = r * std::sin(a) / u, y = (r - r * std::cos(a)) / u;
    char l[96];
    std::snprintf(l, sizeof l, "%sX%.5f Y%.5f%s", i == 1 ? "G1 " : "", incremental ? x - px : x, incremental ? y - py : y,
                  i == 1 ? " F300" : "");
    p += l + eol;
    px = x, py = y;
  }
  p += "G0 Z1" + eol + "M2" + eol;
  return p;
}


double word(const std::string& line, char letter) {
  const std::size_t at = line.find(letter);
  return at == std::string::npos ? 0.0 : std::atof(line.c_str() + at + 1);
}

TEST(BiarcRewrite, AbsoluteRunBecomesArcsOnTheCircle) {
  const std::string in = circle_run(40, 10.0, false, false);
  BiarcRewriteReport rep;
  const std::string out = rewrite_biarcs(in, {}, rep);
  ASSERT_EQ(rep.items.size(), 1u);
  EXPECT_LE(rep.items[0].moves_out, 3);
  const std::vector<std::string> l = test::split_lines(out);
  EXPECT_EQ(l[0], "G21 G90 G17");
  EXPECT_EQ(l[1], "G0 X0 Y0");
  ASSERT_EQ(l[2].rfind("G3 ", 0), 0u) << l[2];
  EXPECT_NE(l[2].find(" F300"), std::string::npos);  // the run's feed on its first line
  // every arc near the circle about (0, 10): radius 10, and every programmed point within the
  // tolerance of the arcs read back from the text
  struct A {
    double x0, y0, x1, y1, cx, cy;
  };
  std::vector<A> arcs;
  std::size_t k = 2;
  double x = 0, y = 0;
  for (; k < l.size() && l[k].rfind("G3 ", 0) == 0; ++k) {
    A a{x, y, word(l[k], 'X'), word(l[k], 'Y'), x + word(l[k], 'I'), y + word(l[k], 'J')};
    EXPECT_NEAR(std::hypot(a.x0 - a.cx, a.y0 - a.cy), 10.0, 0.01);
    arcs.push_back(a);
    x = a.x1, y = a.y1;
  }
  for (const std::string& s : test::split_lines(in)) {
    if (s.find('X') == std::string::npos || s.rfind("G0", 0) == 0) continue;
    const double px = word(s, 'X'), py = word(s, 'Y');
    double best = 1e9;
    for (const A& a : arcs) {  // counter-clockwise arcs under 180 degrees: within the angles
      const double t0 = std::atan2(a.y0 - a.cy, a.x0 - a.cx), t1 = std::atan2(a.y1 - a.cy, a.x1 - a.cx);
      const double t = std::atan2(py - a.cy, px - a.cx);
      const bool inside = std::remainder(t - t0, 2 * M_PI) >= -1e-9 && std::remainder(t1 - t, 2 * M_PI) >= -1e-9;
      best = std::min(best, inside ? std::abs(std::hypot(px - a.cx, py - a.cy) - std::hypot(a.x0 - a.cx, a.y0 - a.cy))
                                   : std::min(std::hypot(px - a.x0, py - a.y0), std::hypot(px - a.x1, py - a.y1)));
    }
    EXPECT_LE(best, 0.001 + 2e-6) << s;
  }
  EXPECT_EQ(l[k], "G0 Z1");
  EXPECT_NEAR(x, 10 * std::sin(40 * M_PI / 90), 1e-5);
}

TEST(BiarcRewrite, IncrementalInchRunKeepsItsEndAndLineEndings) {
  const std::string in = circle_run(40, 10.0, true, true, "\r\n");
  BiarcRewriteReport rep;
  const std::string out = rewrite_biarcs(in, {}, rep);
  ASSERT_EQ(rep.items.size(), 1u);
  const std::vector<std::string> l = test::split_lines(out);
  double sx = 0, sy = 0;  // the increments add up to the programmed end
  for (const std::string& s : l) {
    ASSERT_FALSE(s.empty());
    EXPECT_EQ(s.back(), '\r') << s;
    if (s.rfind("G3 ", 0) == 0 || s.rfind("G2 ", 0) == 0 || s.rfind("G1 ", 0) == 0) sx += word(s, 'X'), sy += word(s, 'Y');
  }
  double ix = 0, iy = 0;
  for (const std::string& s : test::split_lines(in))
    if (s.find('X') != std::string::npos && s.rfind("G0", 0) != 0) ix += word(s, 'X'), iy += word(s, 'Y');
  EXPECT_NEAR(sx, ix, 2e-6 * rep.items[0].moves_out);
  EXPECT_NEAR(sy, iy, 2e-6 * rep.items[0].moves_out);
  // within the tolerance (in mm, whatever the units), the arcs' radii near the circle's 10 mm
  EXPECT_LE(rep.items[0].deviation_mm, 0.001);
  EXPECT_TRUE(rep.items[0].within_tolerance);
  for (const std::string& s : l) {
    if (s.rfind("G3 ", 0) == 0) {
      EXPECT_NEAR(std::hypot(word(s, 'I'), word(s, 'J')) * 25.4, 10.0, 0.5);  // 1e-5 in rounding: noisy points
    }
  }
}

TEST(BiarcRewrite, ShortOrSharpRunsPassUnchanged) {
  BiarcRewriteReport rep;
  const std::string few = circle_run(6, 10.0, false, false);  // fewer than 8 moves
  EXPECT_EQ(rewrite_biarcs(few, {}, rep), few);
  BiarcRewriteOptions o;
  o.max_turn_deg = 1.0;  // each junction turns 2 degrees
  const std::string in = circle_run(40, 10.0, false, false);
  EXPECT_EQ(rewrite_biarcs(in, o, rep), in);
  o = {};
  o.max_segment_mm = 0.3;  // the moves are 0.35 mm
  EXPECT_EQ(rewrite_biarcs(in, o, rep), in);
  EXPECT_TRUE(rep.items.empty());
}

TEST(BiarcRewrite, ParametersAndInverseTimeStopTheRewrite) {
  BiarcRewriteReport rep;
  const std::string in = "#1=5\n" + circle_run(40, 10.0, false, false);
  EXPECT_EQ(rewrite_biarcs(in, {}, rep), in);
  ASSERT_FALSE(rep.notes.empty());
  const std::string g93 = "G93\n" + circle_run(40, 10.0, false, false);
  EXPECT_EQ(rewrite_biarcs(g93, {}, rep), g93);
  // a comment with '#' is not a parameter
  const std::string commented = "(tool #1)\n" + circle_run(40, 10.0, false, false);
  BiarcRewriteReport rep2;
  EXPECT_NE(rewrite_biarcs(commented, {}, rep2), commented);
  EXPECT_EQ(rep2.items.size(), 1u);
}

TEST(BiarcRewrite, G18RunUsesXZAndIK) {
  std::string in = "G21 G90 G18\nG0 X0 Z0\nG1 F200\n";
  for (int i = 1; i <= 30; ++i) {
    char l[64];
    std::snprintf(l, sizeof l, "Z%.5f X%.5f\n", 8 * std::sin(i * M_PI / 90), 8 - 8 * std::cos(i * M_PI / 90));
    in += l;
  }
  in += "M2\n";
  BiarcRewriteReport rep;
  const std::string out = rewrite_biarcs(in, {}, rep);
  ASSERT_EQ(rep.items.size(), 1u);
  const std::vector<std::string> l = test::split_lines(out);
  // plane axes Z (first) -> X: moving +Z and turning toward +X is a positive angle: G3
  ASSERT_EQ(l[3].rfind("G3 X", 0), 0u) << l[3];
  EXPECT_NE(l[3].find(" Z"), std::string::npos);
  EXPECT_NE(l[3].find(" I"), std::string::npos);
  EXPECT_NE(l[3].find(" K"), std::string::npos);
  EXPECT_EQ(l[3].find(" J"), std::string::npos);
}

// ---- G5 / G5.1 splines ----

struct Pt {
  double x, y;
};

// The Bézier of control points `c` at t (de Casteljau), independent of the project's NURBS code.
Pt bezier(std::vector<Pt> c, double t) {
  for (std::size_t n = c.size(); n > 1; --n)
    for (std::size_t i = 0; i + 1 < n; ++i) c[i] = {c[i].x + t * (c[i + 1].x - c[i].x), c[i].y + t * (c[i + 1].y - c[i].y)};
  return c[0];
}

// One G1/G2/G3 line read back: from (x0, y0); an arc's center, radius, start angle and sweep.
struct RewritePiece {
  double x0, y0, x1, y1;
  bool arc = false;
  double cx = 0, cy = 0, r = 0, a0 = 0, sweep = 0;
  Pt at(double t) const {
    if (!arc) return {x0 + (x1 - x0) * t, y0 + (y1 - y0) * t};
    return {cx + r * std::cos(a0 + sweep * t), cy + r * std::sin(a0 + sweep * t)};
  }
  // the distance of p from this piece (exact)
  double distance(Pt p) const {
    if (!arc) {
      const double dx = x1 - x0, dy = y1 - y0, len2 = dx * dx + dy * dy;
      const double t = len2 > 0 ? std::clamp(((p.x - x0) * dx + (p.y - y0) * dy) / len2, 0.0, 1.0) : 0.0;
      return std::hypot(p.x - x0 - t * dx, p.y - y0 - t * dy);
    }
    const double u = std::remainder(std::atan2(p.y - cy, p.x - cx) - a0 - sweep / 2, 2 * M_PI);  // from the mid angle
    if (std::abs(u) <= std::abs(sweep) / 2) return std::abs(std::hypot(p.x - cx, p.y - cy) - r);
    return std::min(std::hypot(p.x - x0, p.y - y0), std::hypot(p.x - x1, p.y - y1));
  }
};

// The G1/G2/G3 lines of `lines` from `first` on (absolute, relative centers), from (x, y); stops
// at the first other line and returns its index in `next`.
std::vector<RewritePiece> read_pieces(const std::vector<std::string>& lines, std::size_t first, double x, double y, std::size_t& next) {
  std::vector<RewritePiece> out;
  std::size_t k = first;
  for (; k < lines.size(); ++k) {
    const std::string& s = lines[k];
    const bool g2 = s.rfind("G2 ", 0) == 0, g3 = s.rfind("G3 ", 0) == 0, g1 = s.rfind("G1 X", 0) == 0;
    if (!g1 && !g2 && !g3) break;
    RewritePiece p{x, y, word(s, 'X'), word(s, 'Y')};
    if (!g1) {
      p.arc = true;
      p.cx = x + word(s, 'I'), p.cy = y + word(s, 'J');
      p.r = std::hypot(x - p.cx, y - p.cy);
      p.a0 = std::atan2(y - p.cy, x - p.cx);
      p.sweep = std::atan2(p.y1 - p.cy, p.x1 - p.cx) - p.a0;
      if (g3) {
        while (p.sweep <= 0) p.sweep += 2 * M_PI;
      } else {
        while (p.sweep >= 0) p.sweep -= 2 * M_PI;
      }
      EXPECT_NEAR(std::hypot(p.x1 - p.cx, p.y1 - p.cy), p.r, 2e-6) << s;
    }
    out.push_back(p);
    x = p.x1, y = p.y1;
  }
  next = k;
  return out;
}

// The largest distance from the curve's points to the pieces, and from the pieces' points to
// the curve's (dense) polyline.
double farthest_from_pieces(const std::vector<Pt>& curve, const std::vector<RewritePiece>& pieces) {
  double worst = 0.0;
  for (const Pt& p : curve) {
    double best = 1e9;
    for (const RewritePiece& a : pieces) best = std::min(best, a.distance(p));
    worst = std::max(worst, best);
  }
  return worst;
}

double farthest_from_curve(const std::vector<RewritePiece>& pieces, const std::vector<Pt>& b) {
  double worst = 0.0;
  for (const RewritePiece& a : pieces) {
    for (int i = 0; i <= 24; ++i) {
      const Pt p = a.at(i / 24.0);
      double best = 1e9;
      for (std::size_t j = 0; j + 1 < b.size(); ++j) {
        const double dx = b[j + 1].x - b[j].x, dy = b[j + 1].y - b[j].y;
        const double len2 = dx * dx + dy * dy;
        const double t = len2 > 0 ? std::clamp(((p.x - b[j].x) * dx + (p.y - b[j].y) * dy) / len2, 0.0, 1.0) : 0.0;
        best = std::min(best, std::hypot(p.x - b[j].x - t * dx, p.y - b[j].y - t * dy));
      }
      worst = std::max(worst, best);
    }
  }
  return worst;
}

std::vector<Pt> sampled(const std::vector<Pt>& c) {
  std::vector<Pt> pts;
  for (int i = 0; i <= 2000; ++i) pts.push_back(bezier(c, i / 2000.0));
  return pts;
}

// A G5 with I J, a G5 by the modal motion mode that continues it (no I J: its first control
// point mirrors the previous P Q), and a G5.1: each becomes G2/G3 lines within the tolerance of
// its Bézier, both ways, ending exactly at the programmed point; the lines around pass unchanged.
TEST(BiarcRewrite, G5AndG51SplinesBecomeArcsWithinTheTolerance) {
  const std::string in =
      "G21 G90 G17\nG0 X0 Y0\nG5 X10 Y0 I3 J4 P-3 Q4 F300\nX20 Y0 P-3 Q-4\nG5.1 X30 Y0 I5 J6\nG1 X31\nM2\n";
  BiarcRewriteReport rep;
  const std::string out = rewrite_biarcs(in, {}, rep);
  ASSERT_EQ(rep.items.size(), 3u) << out;
  EXPECT_EQ(rep.items[0].spline_degree, 3);
  EXPECT_EQ(rep.items[1].spline_degree, 3);
  EXPECT_EQ(rep.items[2].spline_degree, 2);
  for (const auto& it : rep.items) EXPECT_TRUE(it.within_tolerance);
  const std::vector<std::string> l = test::split_lines(out);
  ASSERT_GE(l.size(), 6u);
  EXPECT_EQ(l[0], "G21 G90 G17");
  EXPECT_EQ(l[1], "G0 X0 Y0");
  EXPECT_NE(l[2].find(" F300"), std::string::npos) << "the G5 line's feed on its first arc: " << l[2];
  const std::vector<std::vector<Pt>> curves = {
      {{0, 0}, {3, 4}, {7, 4}, {10, 0}}, {{10, 0}, {13, -4}, {17, -4}, {20, 0}}, {{20, 0}, {25, 6}, {30, 0}}};
  std::size_t k = 2;
  double x = 0, y = 0;
  for (std::size_t c = 0; c < curves.size(); ++c) {
    // each spline's lines end at its programmed end point
    std::size_t end = k + static_cast<std::size_t>(rep.items[c].moves_out);
    std::size_t next = 0;
    const std::vector<RewritePiece> arcs = read_pieces(std::vector<std::string>(l.begin(), l.begin() + static_cast<long>(end)), k, x, y, next);
    ASSERT_EQ(next, end) << c;
    EXPECT_EQ(word(l[end - 1], 'X'), curves[c].back().x) << l[end - 1];
    EXPECT_EQ(word(l[end - 1], 'Y'), curves[c].back().y) << l[end - 1];
    const std::vector<Pt> curve = sampled(curves[c]);
    EXPECT_LE(farthest_from_pieces(curve, arcs), 0.001 + 2e-6) << "spline " << c;
    EXPECT_LE(farthest_from_curve(arcs, curve), 0.001 + 2e-6) << "spline " << c;
    x = curves[c].back().x, y = curves[c].back().y;
    k = end;
  }
  EXPECT_EQ(l[k], "G1 X31");
  EXPECT_EQ(l[k + 1], "M2");
}

// What stays a spline, with a note: a G5 whose continuation is not rewritten (a comment on it:
// the continuation needs the G5 before it), a later line moving by the modal G5, a spline
// outside G17 (LinuxCNC refuses it; the tool leaves it to the machine's check).
TEST(BiarcRewrite, SplinesTheRewriteCannotKeepStayAsTheyAre) {
  BiarcRewriteReport rep;
  const std::string chained = "G17 G0 X0 Y0\nG5 X10 Y0 I3 J4 P-3 Q4 F300\nG5 X20 Y0 P-3 Q-4 (continues)\nG1 X21\nM2\n";
  EXPECT_EQ(rewrite_biarcs(chained, {}, rep), chained);
  ASSERT_FALSE(rep.notes.empty());
  EXPECT_NE(rep.notes[0].find("line 2: G5 left as it is: line 3 continues it"), std::string::npos) << rep.notes[0];

  BiarcRewriteReport rep2;
  const std::string modal = "G17 G0 X0 Y0\nG5.1 X10 Y0 I3 J4 F300\nX20 Y0 I3 J4 (modal)\nM2\n";
  EXPECT_EQ(rewrite_biarcs(modal, {}, rep2), modal);
  ASSERT_FALSE(rep2.notes.empty());
  EXPECT_NE(rep2.notes[0].find("a later line moves by the modal motion mode"), std::string::npos) << rep2.notes[0];

  BiarcRewriteReport rep3;
  const std::string g18 = "G18 G0 X0 Z0\nG5 X10 Z0 I3 J4 P-3 Q4 F300\nM2\n";
  EXPECT_EQ(rewrite_biarcs(g18, {}, rep3), g18);
  EXPECT_TRUE(rep3.items.empty());
}

}  // namespace
}  // namespace pcnc
