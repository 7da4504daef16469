// test_arc_split.cpp — the arc-splitting stage (host/gcode/arc_split.hpp): an M21 arc in a plane
// of unequal axis limits is cut into pieces that chain exactly (the first from the move's start,
// the last to its end, bit for bit), lie on the arc the rt runs for the whole (radius and normal
// axis linear in the angle), keep its line and feed, and each gets a speed cap at least the
// whole's, higher where its normal stays near the faster axis; arcs under M22, in a plane of
// equal limits, or too short are left whole.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "gcode/arc_split.hpp"
#include "gcode/preprocessor.hpp"
#include "geometry/plane.hpp"
#include "machine_runner.hpp"

using namespace pcnc;

namespace {

// An arc about `center` in the plane of `normal` from angle a0 over `sweep`, radius r at the
// start and r_end at the end, rising `rise` along the normal.
Move arc(int normal, double r, double a0, double sweep, double r_end = -1.0, double rise = 0.0, bool m21 = true) {
  if (r_end < 0.0) r_end = r;
  const auto pa = plane_axes(normal);
  const Vec3 c{12.5, 12.5, 12.5};
  Move m;
  m.kind = MoveKind::kArc;
  m.line = 42;
  m.feed_mm_s = 80.0;
  m.contouring = m21;
  m.normal_axis = normal;
  m.center = c;
  m.start = c;
  m.start[pa[0]] += r * std::cos(a0);
  m.start[pa[1]] += r * std::sin(a0);
  m.end = c;
  m.end[pa[0]] += r_end * std::cos(a0 + sweep);
  m.end[pa[1]] += r_end * std::sin(a0 + sweep);
  m.end[normal] += rise;
  m.radius = r;
  m.sweep = sweep;
  return m;
}

}  // namespace

TEST(ArcSplit, PiecesChainExactlyAndLieOnTheArcTheRtRuns) {
  for (const int normal : {0, 1, 2}) {
    for (const double sweep : {1.3, -2.9, 7.0}) {
      const Move m = arc(normal, 3.0, 0.4, sweep, 3.002, normal == 1 ? 1.5 : 0.0);
      const int n = 7;
      const std::vector<Move> p = split_arc(m, n);
      ASSERT_EQ(p.size(), static_cast<std::size_t>(n));
      EXPECT_EQ(p.front().start, m.start);
      EXPECT_EQ(p.back().end, m.end);
      const auto pa = plane_axes(normal);
      double swept = 0.0;
      for (std::size_t k = 0; k < p.size(); ++k) {
        if (k > 0) {
          EXPECT_EQ(p[k].start, p[k - 1].end);
        }
        EXPECT_EQ(p[k].line, 42);
        EXPECT_EQ(p[k].feed_mm_s, 80.0);
        EXPECT_EQ(p[k].kind, MoveKind::kArc);
        EXPECT_EQ(p[k].center[normal], p[k].start[normal]);  // the centre on the piece's start level
        EXPECT_NEAR(p[k].radius, std::hypot(p[k].start[pa[0]] - m.center[pa[0]], p[k].start[pa[1]] - m.center[pa[1]]), 1e-12);
        swept += p[k].sweep;
        // where the whole arc is at this piece's end: radius and the normal linear in the angle
        const double u = static_cast<double>(k + 1) / n;
        const double th = 0.4 + sweep * u, r = 3.0 + 0.002 * u;
        EXPECT_NEAR(p[k].end[pa[0]], m.center[pa[0]] + r * std::cos(th), 1e-12);
        EXPECT_NEAR(p[k].end[pa[1]], m.center[pa[1]] + r * std::sin(th), 1e-12);
        EXPECT_NEAR(p[k].end[normal], m.start[normal] + (m.end[normal] - m.start[normal]) * u, 1e-12);
      }
      EXPECT_NEAR(swept, sweep, 1e-12);
    }
  }
}

TEST(ArcSplit, OnlyM21ArcsInAPlaneOfUnequalLimitsLongEnoughAreCut) {
  const MachineConfig c = test::default_machine_config();  // X, Y 2000 mm/s², Z 1000
  ASSERT_NE(c.axes[0].max_accel_mm_s2, c.axes[2].max_accel_mm_s2);
  ASSERT_EQ(c.axes[0].max_accel_mm_s2, c.axes[1].max_accel_mm_s2);
  const double quarter = std::numbers::pi / 2.0;
  EXPECT_EQ(arc_pieces(arc(2, 3.0, 0.0, quarter), c), 1);  // G17: X and Y alike
  EXPECT_EQ(arc_pieces(arc(0, 3.0, 0.0, quarter), c), 4);  // G19, 90° in pieces of 22.5°
  EXPECT_EQ(arc_pieces(arc(1, 3.0, 0.0, -quarter), c), 4);  // G18, clockwise
  EXPECT_EQ(arc_pieces(arc(0, 3.0, 0.0, quarter, -1.0, 0.0, false), c), 1);  // M22: each piece would stop
  EXPECT_EQ(arc_pieces(arc(0, 0.4, 0.0, quarter), c), 1);  // 0.63 mm: one piece of 0.5 mm at most
  EXPECT_EQ(arc_pieces(arc(0, 0.8, 0.0, quarter), c), 2);  // 1.26 mm: two pieces
  Move turning = arc(0, 3.0, 0.0, quarter);
  turning.rot_end[0] = 0.5;  // a rotary joint's turn is not shared out: left whole
  EXPECT_EQ(arc_pieces(turning, c), 1);
  Move line = arc(0, 3.0, 0.0, quarter);
  line.kind = MoveKind::kLine;
  EXPECT_EQ(arc_pieces(line, c), 1);
}

TEST(ArcSplit, EachPieceRunsAtLeastAsFastAsTheWholeAndFasterNearTheFasterAxis) {
  // A G19 quarter from a normal along Y (2000 mm/s²) to one along Z (1000 mm/s²): the whole is
  // capped by Z over its sweep; the first piece, whose normal stays near Y, is not.
  const MachineConfig c = test::default_machine_config();
  Move m = arc(0, 1.5, 0.0, -std::numbers::pi / 2.0);  // centripetal cap 37.7 mm/s under Z's 50 mm/s
  m.feed_mm_s = 1000.0;  // the caps bind, not the feed
  const Block whole = make_block(m, c);
  const std::vector<Move> p = split_arc(m, arc_pieces(m, c));
  ASSERT_EQ(p.size(), 4u);
  std::vector<double> caps;
  for (const Move& q : p) caps.push_back(make_block(q, c).speed);
  for (const double v : caps) EXPECT_GE(v, whole.speed * (1.0 - 1e-12));
  EXPECT_GT(caps.front(), 1.15 * whole.speed);
  EXPECT_NEAR(caps.back(), whole.speed, 1e-9 * whole.speed);  // the last piece reaches Z's normal
}
