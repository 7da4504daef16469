// test_offset_geometry.cpp — the plane geometry of cutter compensation without processes:
// sweeps (LinuxCNC's find_turn rule), offsets of segments and arcs, corner classes, and the
// exact intersections and distances the gouge test measures with.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "geometry/intersect.hpp"
#include "geometry/offset.hpp"
#include "test_constants.hpp"

namespace pcnc {
namespace {


TEST(OffsetGeometry, TurnAngleFollowsTheDirection) {
  EXPECT_NEAR(turn_angle({1, 0}, {0, 0}, 1, {0, 1}), kPi / 2, 1e-15);
  EXPECT_NEAR(turn_angle({1, 0}, {0, 0}, -1, {0, 1}), -3 * kPi / 2, 1e-15);
  EXPECT_NEAR(turn_angle({1, 0}, {0, 0}, 1, {1, 0}), 2 * kPi, 1e-15);  // same direction: a full turn
  EXPECT_EQ(turn_angle({1, 0}, {0, 0}, 0, {0, 1}), 0.0);
}

TEST(OffsetGeometry, SegmentOffsetsAlongItsNormal) {
  bool ok = false;
  const Piece l = offset_piece(segment({0, 0}, {10, 0}), CompSide::kLeft, 2.0, ok);
  EXPECT_TRUE(ok);
  EXPECT_DOUBLE_EQ(l.a.y, 2.0);
  EXPECT_DOUBLE_EQ(l.b.x, 10.0);
  const Piece r = offset_piece(segment({0, 0}, {0, 5}), CompSide::kRight, 1.0, ok);
  EXPECT_DOUBLE_EQ(r.a.x, 1.0);  // right of +Y is +X
  EXPECT_DOUBLE_EQ(r.b.y, 5.0);
}

TEST(OffsetGeometry, ArcOffsetGrowsOutsideAndShrinksInside) {
  const Piece ccw = arc_piece({5, 0}, {0, 5}, {0, 0}, 1);  // quarter circle, radius 5
  bool ok = false;
  const Piece in = offset_piece(ccw, CompSide::kLeft, 2.0, ok);  // G41 on a G3: inside
  EXPECT_TRUE(ok);
  EXPECT_DOUBLE_EQ(in.r, 3.0);
  EXPECT_NEAR(in.b.y, 3.0, 1e-15);
  const Piece out = offset_piece(ccw, CompSide::kRight, 2.0, ok);
  EXPECT_DOUBLE_EQ(out.r, 7.0);
  offset_piece(ccw, CompSide::kLeft, 5.0, ok);  // the tool does not fit inside
  EXPECT_FALSE(ok);
}

TEST(OffsetGeometry, CornersAreConvexOrConcaveForTheToolsSide) {
  const Vec2 east{1, 0}, north{0, 1}, south{0, -1};
  double turn = 0;
  EXPECT_EQ(classify_corner(east, north, CompSide::kLeft, 0.05, &turn), Corner::kConcave);  // left turn, tool left
  EXPECT_NEAR(turn, kPi / 2, 1e-15);
  EXPECT_EQ(classify_corner(east, north, CompSide::kRight, 0.05), Corner::kConvex);
  EXPECT_EQ(classify_corner(east, south, CompSide::kLeft, 0.05), Corner::kConvex);
  EXPECT_EQ(classify_corner(east, Vec2{1, 0.04}, CompSide::kLeft, 0.05), Corner::kTangent);
}

TEST(OffsetGeometry, LineLineAndLineCircleAndCircleCircleIntersections) {
  Hits h = intersect_lines({0, 0}, {1, 1}, {0, 2}, {2, 0});
  ASSERT_EQ(h.count, 1);
  EXPECT_NEAR(h.p[0].x, 1.0, 1e-15);
  EXPECT_NEAR(h.p[0].y, 1.0, 1e-15);
  EXPECT_EQ(intersect_lines({0, 0}, {1, 0}, {0, 1}, {1, 1}).count, 0);  // parallel

  h = intersect_line_circle({-10, 3}, {10, 3}, {0, 0}, 5);
  ASSERT_EQ(h.count, 2);
  EXPECT_NEAR(std::fabs(h.p[0].x), 4.0, 1e-12);
  EXPECT_NEAR(h.p[0].x, -h.p[1].x, 1e-12);
  EXPECT_EQ(intersect_line_circle({-10, 6}, {10, 6}, {0, 0}, 5).count, 0);

  h = intersect_circles({0, 0}, 5, {8, 0}, 5);
  ASSERT_EQ(h.count, 2);
  EXPECT_NEAR(h.p[0].x, 4.0, 1e-12);
  EXPECT_NEAR(std::fabs(h.p[0].y), 3.0, 1e-12);
  EXPECT_EQ(intersect_circles({0, 0}, 5, {0, 0}, 3).count, 0);  // concentric
  EXPECT_EQ(intersect_circles({0, 0}, 1, {5, 0}, 1).count, 0);  // apart
}

TEST(OffsetGeometry, WithinSweepRespectsDirection) {
  const Piece ccw = arc_piece({1, 0}, {0, 1}, {0, 0}, 1);
  EXPECT_TRUE(within_sweep(ccw, {1, 1}));
  EXPECT_FALSE(within_sweep(ccw, {-1, -1}));
  const Piece cw = arc_piece({1, 0}, {0, 1}, {0, 0}, -1);  // three quarters, the long way
  EXPECT_FALSE(within_sweep(cw, {1, 1}));
  EXPECT_TRUE(within_sweep(cw, {-1, -1}));
}

TEST(OffsetGeometry, ExactDistancesBetweenPieces) {
  // Two parallel segments 3 apart, overlapping: 3.
  EXPECT_NEAR(distance(segment({0, 0}, {10, 0}), segment({2, 3}, {5, 3})), 3.0, 1e-15);
  // Crossing segments: 0.
  EXPECT_EQ(distance(segment({0, 0}, {2, 2}), segment({0, 2}, {2, 0})), 0.0);
  // End to end, at an angle: from (10,0) to (13,4) = 5.
  EXPECT_NEAR(distance(segment({0, 0}, {10, 0}), segment({13, 4}, {13, 10})), 5.0, 1e-12);
  // A segment passing over a circle's top, interior to interior: 7 - 5 = 2.
  const Piece top = arc_piece({5, 0}, {-5, 0}, {0, 0}, 1);  // upper half circle
  Vec2 at;
  EXPECT_NEAR(distance(segment({-10, 7}, {10, 7}), top, &at), 2.0, 1e-12);
  EXPECT_NEAR(at.x, 0.0, 1e-12);
  EXPECT_NEAR(at.y, 7.0, 1e-12);
  // ... but below it the lower half is missing: the nearest points are the arc's ends.
  EXPECT_NEAR(distance(segment({-10, -7}, {10, -7}), top), 7.0, 1e-12);
  // Two arcs facing each other across their center line: 10 - 3 - 4 = 3.
  const Piece left = arc_piece({0, -3}, {0, 3}, {0, 0}, 1);    // right half of r 3 about the origin
  const Piece right = arc_piece({10, 4}, {10, -4}, {10, 0}, 1);  // left half of r 4 about (10,0)
  EXPECT_NEAR(distance(left, right), 3.0, 1e-12);
  // Point to arc: inside the sweep, radial; outside, to the nearer end.
  EXPECT_NEAR(distance(top, Vec2{0, 2}), 3.0, 1e-12);
  EXPECT_NEAR(distance(top, Vec2{0, -2}), std::hypot(5.0, 2.0), 1e-12);
}

}  // namespace
}  // namespace pcnc
