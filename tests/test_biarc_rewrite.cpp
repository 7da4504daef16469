// test_biarc_rewrite.cpp — the text transformation of `pcnc biarc` (tools/biarc_rewrite.hpp)
// on small programs written here: incremental (G91) and inch (G20) runs, CRLF line endings,
// the feed, a run too short or too sharp to rewrite, a program with parameters (nothing
// rewritten after them), G93 (nothing rewritten), a G18 run.
#include <gtest/gtest.h>

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

}  // namespace
}  // namespace pcnc
