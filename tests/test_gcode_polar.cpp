// test_gcode_polar.cpp — LinuxCNC's polar coordinates: @ (distance from the current coordinate
// system's origin in the XY plane) and ^ (angle from +X, degrees) in place of X and Y, on moves,
// arcs and canned-cycle holes (G90: the point, the word not written keeps the current point's;
// G91: added to the current point's, turning about the origin), and every refusal with its
// column. The figures are worked by hand from the definitions in LinuxCNC's G-code manual.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "gcode_test_util.hpp"
#include "test_constants.hpp"

namespace pcnc {
namespace {

using test::run_program;
using test::wide_config;


// The ends of the feed moves: a canned cycle's hole bottoms.
std::vector<Vec3> feed_ends(const test::RunResult& r) {
  std::vector<Vec3> ends;
  for (const Block& b : r.motion()) {
    if (b.kind == BlockKind::kLine) ends.push_back(b.end);
  }
  return ends;
}

void expect_xy(const Vec3& p, double x, double y, double tol = 1e-9) {
  EXPECT_NEAR(p[0], x, tol);
  EXPECT_NEAR(p[1], y, tol);
}

TEST(Polar, G90NamesThePointAndAMissingWordKeepsTheCurrentPoints) {
  const auto r = run_program(
      "G21 G90 G17\n"
      "G0 @10 ^30\n"   // radius 10 at 30 degrees
      "G0 ^90\n"       // the same radius, at 90 degrees
      "G1 @4 F600\n"   // the same angle, radius 4
      "G1 @5 ^-45 Z2\n"
      "M2\n",
      wide_config());
  ASSERT_TRUE(r.check.ok) << (r.first_error() ? r.first_error()->message : "");
  const auto m = r.motion();
  ASSERT_EQ(m.size(), 4u);
  expect_xy(m[0].end, 10 * std::cos(30 * kDeg), 10 * std::sin(30 * kDeg));
  expect_xy(m[1].end, 0.0, 10.0);
  expect_xy(m[2].end, 0.0, 4.0);
  expect_xy(m[3].end, 5 * std::cos(45 * kDeg), -5 * std::sin(45 * kDeg));
  EXPECT_NEAR(m[3].end[2], 2.0, 1e-12) << "Z is written as usual beside @ and ^";
}

TEST(Polar, G91AddsToTheCurrentRadiusAndAngleAboutTheOrigin) {
  const auto r = run_program("G21 G90\nG0 X10 Y0\nG91 G0 ^90\nG0 @5\nG0 ^-45 @-5\nM2\n", wide_config());
  ASSERT_TRUE(r.check.ok) << (r.first_error() ? r.first_error()->message : "");
  const auto m = r.motion();
  ASSERT_EQ(m.size(), 4u);
  expect_xy(m[1].end, 0.0, 10.0);  // turned by 90 degrees about the origin, not moved by a vector
  expect_xy(m[2].end, 0.0, 15.0);
  expect_xy(m[3].end, 10 * std::cos(45 * kDeg), 10 * std::sin(45 * kDeg));
}

TEST(Polar, TheOriginIsTheCurrentCoordinateSystemsAndTheRadiusIsInTheProgramsUnits) {
  // G55 at (100, 50): @ and ^ are measured from it; G20: @1 is 25.4 mm
  MachineConfig c = wide_config();
  c.gcode.work_offsets[1] = Vec3{100.0, 50.0, 0.0};
  const auto r = run_program("G20 G55 G90\nG0 @1 ^180\nG92 X0 Y0\nG0 @1 ^90\nM2\n", c);
  ASSERT_TRUE(r.check.ok) << (r.first_error() ? r.first_error()->message : "");
  const auto m = r.motion();
  ASSERT_EQ(m.size(), 2u);
  expect_xy(m[0].end, 100.0 - 25.4, 50.0);
  expect_xy(m[1].end, 100.0 - 25.4, 50.0 + 25.4);  // after G92 the origin is where the tool stood
}

TEST(Polar, AnArcEndsAtThePolarPoint) {
  // a quarter circle about the origin from (10, 0) to @10 ^90
  const auto r = run_program("G21 G90 G17\nG0 X10 Y0\nG3 @10 ^90 I-10 J0 F600\nM2\n", wide_config());
  ASSERT_TRUE(r.check.ok) << (r.first_error() ? r.first_error()->message : "");
  const auto m = r.motion();
  ASSERT_EQ(m.size(), 2u);
  ASSERT_EQ(m[1].kind, BlockKind::kArc);
  expect_xy(m[1].end, 0.0, 10.0);
  EXPECT_NEAR(m[1].arc.radius, 10.0, 1e-9);
  EXPECT_NEAR(m[1].arc.sweep, 90 * kDeg, 1e-9);
}

TEST(Polar, IncrementalCannedCycleRepeatsTurnAboutTheOrigin) {
  // LinuxCNC's bolt circle: six holes 60 degrees apart on a 30 mm circle (the sixth where it started)
  const auto r = run_program("G21 G17 G90\nG0 X30 Y0 Z10\nG91 G81 R-8 Z-5 ^60 L6 F300\nM2\n", wide_config());
  ASSERT_TRUE(r.check.ok) << (r.first_error() ? r.first_error()->message : "");
  const std::vector<Vec3> bottoms = feed_ends(r);
  ASSERT_EQ(bottoms.size(), 6u);
  for (std::size_t k = 0; k < 6; ++k) {
    const double a = 60.0 * static_cast<double>(k + 1) * kDeg;
    expect_xy(bottoms[k], 30 * std::cos(a), 30 * std::sin(a), 1e-9);
    EXPECT_NEAR(bottoms[k][2], -3.0, 1e-12) << "R 8 below the initial level, the bottom 5 below R";
  }
  // a row along 33 degrees, 10 mm apart: the radius grows, the angle stays
  const auto row = run_program("G21 G17 G90\nG0 @10 ^33 Z10\nG91 G81 @10 R-8 Z-5 L3 F300\nM2\n", wide_config());
  ASSERT_TRUE(row.check.ok) << (row.first_error() ? row.first_error()->message : "");
  const std::vector<Vec3> holes = feed_ends(row);
  ASSERT_EQ(holes.size(), 3u);
  for (std::size_t k = 0; k < 3; ++k) {
    const double rad = 10.0 * static_cast<double>(k + 2);
    expect_xy(holes[k], rad * std::cos(33 * kDeg), rad * std::sin(33 * kDeg));
  }
}

TEST(Polar, AbsoluteCannedCycleDrillsAtThePolarPointAndAModalLineMayHoldOnlyTheAngle) {
  const auto r = run_program("G21 G17 G90 G98\nG0 X25 Y0 Z10\nG81 R2 Z-1 F300\n^120\n^240\nM2\n", wide_config());
  ASSERT_TRUE(r.check.ok) << (r.first_error() ? r.first_error()->message : "");
  const std::vector<Vec3> holes = feed_ends(r);
  ASSERT_EQ(holes.size(), 3u);
  expect_xy(holes[0], 25.0, 0.0);
  expect_xy(holes[1], 25 * std::cos(120 * kDeg), 25 * std::sin(120 * kDeg));
  expect_xy(holes[2], 25 * std::cos(240 * kDeg), 25 * std::sin(240 * kDeg));
}

TEST(Polar, RefusedWhereTheyMeanNothingWithTheirColumn) {
  struct Case {
    const char* program;
    int line, column;
    const char* fragment;
  };
  const Case cases[] = {
      {"G90\nG0 X1 @2 ^3\nM2\n", 2, 4, "X word with polar coordinates"},
      {"G18\nG0 @2 ^3\nM2\n", 2, 4, "polar coordinates (@ ^) in the G18 plane; expected G17"},
      {"G90 G0 X0 Y0\nG91 G0 ^30\nM2\n", 2, 8, "in G91 at the origin"},
      {"G90 G0 X0 Y0\nG0 @5\nM2\n", 2, 4, "@ without ^ at the origin"},
      {"G90\nG53 G0 @5 ^1\nM2\n", 2, 8, "@ (polar radius) with no move that uses it"},
      {"G10 L2 P1 ^30\nM2\n", 1, 11, "^ (polar angle) with no move that uses it"},
      {"G90 G0 X0 Y0 Z5\nG91 G81 R-1 Z-1 ^60 L2\nM2\n", 2, 17, "G81: polar coordinates (@ ^) in G91 at the origin"},
      {"G90\nG0 @1 @2\nM2\n", 2, 7, "second @ word"},
  };
  for (const Case& c : cases) {
    const auto r = run_program(c.program, wide_config());
    EXPECT_FALSE(r.check.ok) << c.program;
    const Diagnostic* e = r.first_error();
    ASSERT_NE(e, nullptr) << c.program;
    EXPECT_NE(e->message.find(c.fragment), std::string::npos) << c.program << " -> " << e->message;
    EXPECT_EQ(e->line, c.line) << c.program;
    EXPECT_EQ(e->column, c.column) << c.program << " -> " << e->message;
  }
}

}  // namespace
}  // namespace pcnc
