// test_smoothing.cpp — the smoothing stage alone (host/gcode/smoothing.hpp): runs of G1 moves
// under M21 become curves that start and end exactly at the run's ends, a real corner stays a
// corner between two curves, and what must not be smoothed passes unchanged.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "gcode/smoothing.hpp"
#include "geometry/nurbs.hpp"
#include "gcode_test_util.hpp"
#include "move_stage.hpp"

namespace pcnc {
namespace {

Move line(const Vec3& a, const Vec3& b, int n, double tol = 0.005, bool m21 = true) {
  return test::line_move(a, b, n, 10.0, m21, tol);
}

// 20 chords of a gentle bend from `from`, heading along `dir` (unit, in XY), turning left 2° each.
std::vector<Move> bend(Vec3 from, double heading, int first_line, double tol = 0.005, bool m21 = true) {
  std::vector<Move> v;
  for (int i = 0; i < 20; ++i) {
    const double h = heading + i * 2.0 * M_PI / 180.0;
    const Vec3 to = from + Vec3{0.2 * std::cos(h), 0.2 * std::sin(h), 0.0};
    v.push_back(line(from, to, first_line + i, tol, m21));
    from = to;
  }
  return v;
}

std::vector<Move> smooth(const std::vector<Move>& in, const MachineConfig& c) {
  Smoother s(c);
  return test::run_move_stage(s, in);
}

std::vector<Move> smooth(const std::vector<Move>& in) { return smooth(in, load_config(test::default_config())); }

TEST(Smoothing, ARealCornerStaysACornerBetweenTwoCurves) {
  std::vector<Move> in = bend({1, 1, 0}, 0.0, 1);
  const Vec3 corner = in.back().end;
  const std::vector<Move> after = bend(corner, M_PI / 2.0 + 0.7, 21);  // turns ~85° at the corner
  in.insert(in.end(), after.begin(), after.end());
  const std::vector<Move> out = smooth(in);
  ASSERT_EQ(out.size(), 2u);
  for (const Move& m : out) {
    EXPECT_EQ(m.kind, MoveKind::kNurbs);
    EXPECT_TRUE(m.smoothed);
    ASSERT_TRUE(m.nurbs);
    EXPECT_EQ(validate(*m.nurbs), "");
    EXPECT_EQ(m.nurbs->points.front(), m.start);
    EXPECT_EQ(m.nurbs->points.back(), m.end);
  }
  EXPECT_EQ(out[0].start, in.front().start);
  EXPECT_EQ(out[0].end, corner);  // the corner point exactly
  EXPECT_EQ(out[1].start, corner);
  EXPECT_EQ(out[1].end, in.back().end);
  // the tangents at the corner still turn by about 85°: the corner was kept
  const Vec3 t0 = nurbs_tangent(out[0].nurbs->view(), out[0].nurbs->u_max(), false);
  const Vec3 t1 = nurbs_tangent(out[1].nurbs->view(), out[1].nurbs->u_min(), true);
  EXPECT_LT(dot(t0, t1), std::cos(60.0 * M_PI / 180.0));
  // each curve carries the programmed lines along it
  ASSERT_TRUE(out[1].line_marks);
  EXPECT_EQ(out[1].line_marks->front().line, 21);
  EXPECT_EQ(out[1].line_marks->back().line, 40);
}

// Two 1 mm moves turning 8° (under the smoothing angle): the rt passes their junction as a corner
// at its junction-deviation speed for 5 µm (about 64 mm/s on the desktop mill). A curve within
// the tolerance rounds it about as tightly, so at a feed of 100 mm/s the moves stay lines, passed as a
// corner; at 10 mm/s the corner does not bind and they become one curve as before.
TEST(Smoothing, TwoMovesWhoseCornerIsSlowerThanTheirFeedStayLines) {
  const Vec3 a{1, 1, 0}, b{2, 1, 0};
  const double h = 8.0 * M_PI / 180.0;
  const Vec3 c = b + Vec3{std::cos(h), std::sin(h), 0.0};
  for (const double feed : {100.0, 10.0}) {
    const std::vector<Move> in{test::line_move(a, b, 1, feed, true, 0.005), test::line_move(b, c, 2, feed, true, 0.005)};
    const std::vector<Move> out = smooth(in);
    if (feed > 64.0) {
      ASSERT_EQ(out.size(), 2u);
      EXPECT_EQ(out[0].kind, MoveKind::kLine);
      EXPECT_EQ(out[1].kind, MoveKind::kLine);
      EXPECT_EQ(out[0].end, b);
    } else {
      ASSERT_EQ(out.size(), 1u);
      EXPECT_EQ(out[0].kind, MoveKind::kNurbs);
      EXPECT_EQ(out[0].end, c);
    }
  }
}

// A zigzag of 3 mm moves turning 9° each (under the smoothing angle) at 0.5 µm: no cubic with
// knots at most about two per move follows it, so every fit fails and the run is cut again and
// again, down to the programmed lines, in order (the cut-and-refit recursion has a work bound
// on such runs; what it gives back is always the programmed moves).
TEST(Smoothing, ARunNoCurveCanFollowComesBackAsItsLines) {
  std::vector<Move> in;
  Vec3 p{1, 1, 0};
  for (int i = 0; i < 400; ++i) {
    const double h = (i % 2 ? 4.5 : -4.5) * M_PI / 180.0;
    const Vec3 q = p + Vec3{3.0 * std::cos(h), 3.0 * std::sin(h), 0.0};
    in.push_back(line(p, q, i + 1, 0.0005));
    p = q;
  }
  const std::vector<Move> out = smooth(in);
  ASSERT_EQ(out.size(), in.size());
  for (std::size_t i = 0; i < in.size(); ++i) {
    EXPECT_EQ(out[i].kind, MoveKind::kLine) << i;
    EXPECT_EQ(out[i].start, in[i].start) << i;
    EXPECT_EQ(out[i].end, in[i].end) << i;
  }
}

// A run that touches the travel (as --fit makes a program touch both ends of an axis): the bend's
// apex is the highest programmed point, and a curve's control polygon lies outside a convex
// bend, so a curve over the apex would leave the travel the moves keep. The stage fits smaller
// pieces (at worst the moves as programmed) until every curve's control points are inside; with
// room above, the run is one curve as before.
TEST(Smoothing, ACurveNeverLeavesTheTravelTheMovesKeep) {
  MachineConfig c = load_config(test::default_config());
  const std::vector<Move> run = bend({15.0, 10.0, 5.0}, 160.0 * M_PI / 180.0, 100);  // a hill: up, over, down
  double top = 0.0;
  for (const Move& m : run) top = std::max({top, m.start[1], m.end[1]});
  c.axes[1].travel_max_mm = top + 1.0;
  const auto roomy = smooth(run, c);
  ASSERT_EQ(roomy.size(), 1u);
  ASSERT_EQ(roomy[0].kind, MoveKind::kNurbs);
  double cp_top = 0.0;
  for (const Vec3& p : roomy[0].nurbs->points) cp_top = std::max(cp_top, p[1]);
  ASSERT_GT(cp_top, top + 1e-7) << "the control polygon of the one curve rises above the apex by " << cp_top - top;

  c.axes[1].travel_max_mm = top;
  const auto tight = smooth(run, c);
  ASSERT_GT(tight.size(), 1u);
  EXPECT_EQ(tight.front().start, run.front().start);
  EXPECT_EQ(tight.back().end, run.back().end);
  int curves = 0;
  for (std::size_t k = 0; k < tight.size(); ++k) {
    if (k > 0) {
      EXPECT_EQ(tight[k].start, tight[k - 1].end) << "the pieces join";
    }
    if (tight[k].kind != MoveKind::kNurbs) continue;
    ++curves;
    for (const Vec3& p : tight[k].nurbs->points) {
      EXPECT_LE(p[1], top + 1e-7) << "piece " << k;
    }
  }
  EXPECT_GT(curves, 0) << "the sides away from the apex are still curves";
}

TEST(Smoothing, WhatMustNotBeSmoothedPassesUnchanged) {
  // under M22, with tolerance 0, and a single move between corners: lines, as they came
  for (const std::vector<Move>& in : {bend({1, 1, 0}, 0.0, 1, 0.005, false), bend({1, 1, 0}, 0.0, 1, 0.0, true)}) {
    const std::vector<Move> out = smooth(in);
    ASSERT_EQ(out.size(), in.size());
    for (std::size_t i = 0; i < in.size(); ++i) {
      EXPECT_EQ(out[i].kind, MoveKind::kLine);
      EXPECT_EQ(out[i].start, in[i].start);
      EXPECT_EQ(out[i].end, in[i].end);
    }
  }
  // an arc between two runs passes unchanged and ends both runs; a feed change ends a run
  std::vector<Move> in = bend({1, 1, 0}, 0.0, 1);
  Move arc = line(in.back().end, in.back().end + Vec3{1, 1, 0}, 21);
  arc.kind = MoveKind::kArc;
  arc.center = in.back().end + Vec3{0, 1, 0};
  arc.radius = 1.0;
  arc.sweep = M_PI / 2.0;
  in.push_back(arc);
  std::vector<Move> b = bend(arc.end, M_PI / 2.0, 22);
  for (std::size_t i = 10; i < b.size(); ++i) b[i].feed_mm_s = 20.0;
  in.insert(in.end(), b.begin(), b.end());
  const std::vector<Move> out = smooth(in);
  ASSERT_EQ(out.size(), 4u);
  EXPECT_EQ(out[0].kind, MoveKind::kNurbs);
  EXPECT_EQ(out[1].kind, MoveKind::kArc);
  EXPECT_EQ(out[1].start, arc.start);
  EXPECT_EQ(out[1].center, arc.center);
  EXPECT_EQ(out[2].kind, MoveKind::kNurbs);
  EXPECT_EQ(out[2].feed_mm_s, 10.0);
  EXPECT_EQ(out[3].kind, MoveKind::kNurbs);
  EXPECT_EQ(out[3].feed_mm_s, 20.0);
  EXPECT_EQ(out[3].end, in.back().end);
}

}  // namespace
}  // namespace pcnc
