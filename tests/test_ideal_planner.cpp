// test_ideal_planner.cpp — the yardstick of issue 14 (report/ideal_planner.hpp): trapezoids
// between junction-deviation speeds, with unlimited look-ahead, checked against closed forms:
// one line, a straight run cut in pieces, a 90° corner, a reversal and an exact stop, an arc
// whole and as chords, what its speeds ask of a finely drawn circle, and the floor that keeps the limits there.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "config/config.hpp"
#include "gcode_test_util.hpp"
#include "report/ideal_planner.hpp"

namespace pcnc {
namespace {

MachineConfig ideal_mill() {
  MachineConfig c;
  for (std::size_t i = 0; i < 3; ++i) {
    c.axes[i].max_velocity_mm_s = 100.0;
    c.axes[i].max_accel_mm_s2 = i == 2 ? 1000.0 : 2000.0;
  }
  return c;
}

Move line(const Vec3& a, const Vec3& b, double feed) { return test::line_move(a, b, 0, feed); }

// A counter-clockwise XY arc of `radius` about `center` from `from` (radians) through `sweep`.
Move xy_arc(const Vec3& center, double radius, double from, double sweep, double feed) {
  Move arc;
  arc.kind = MoveKind::kArc;
  arc.contouring = true;
  arc.normal_axis = 2;
  arc.center = center;
  arc.radius = radius;
  arc.sweep = sweep;
  arc.start = center + radius * Vec3{std::cos(from), std::sin(from), 0.0};
  arc.end = center + radius * Vec3{std::cos(from + sweep), std::sin(from + sweep), 0.0};
  arc.feed_mm_s = feed;
  return arc;
}

// Rest to rest over l at most at v, accelerating and braking at a.
double trapezoid(double l, double v, double a) {
  if (v * v / a >= l) return 2.0 * std::sqrt(l / a);
  return l / v + v / a;
}

// From v0 to v1 over l, top speed v, at a.
double trapezoid(double l, double v0, double v1, double v, double a) {
  const double vp = std::min(v, std::sqrt((2.0 * a * l + v0 * v0 + v1 * v1) / 2.0));
  const double cruise = l - (vp * vp - v0 * v0) / (2.0 * a) - (vp * vp - v1 * v1) / (2.0 * a);
  return (vp - v0) / a + (vp - v1) / a + cruise / vp;
}

TEST(IdealPlanner, OneLineIsATrapezoidAtItsAxisLimits) {
  const MachineConfig c = ideal_mill();
  // along X at F50: 2000 mm/s²
  IdealPlan p = ideal_planner_time({line({0, 0, 0}, {10, 0, 0}, 50.0)}, c);
  EXPECT_NEAR(p.time_s, trapezoid(10.0, 50.0, 2000.0), 1e-12);
  EXPECT_EQ(p.segments, 1u);
  EXPECT_EQ(p.stops, 1u);
  EXPECT_NEAR(p.length_mm, 10.0, 1e-12);
  // along XZ at 45°: Z's 1000 mm/s² over 1/√2 of the path acceleration; F200 above the axes'
  // 100 mm/s over √2... capped at 100·√2
  const double s = std::sqrt(0.5);
  p = ideal_planner_time({line({0, 0, 0}, {5, 0, 5}, 1000.0)}, c);
  EXPECT_NEAR(p.time_s, trapezoid(5.0 * std::sqrt(2.0), 100.0 / s, 1000.0 / s), 1e-9);
}

TEST(IdealPlanner, AStraightRunInPiecesTakesWhatOneMoveTakes) {
  const MachineConfig c = ideal_mill();
  std::vector<Move> run;
  for (int i = 0; i < 10; ++i) run.push_back(line({1.0 * i, 0, 0}, {1.0 * (i + 1), 0, 0}, 80.0));
  const IdealPlan p = ideal_planner_time(run, c);
  EXPECT_NEAR(p.time_s, trapezoid(10.0, 80.0, 2000.0), 1e-9);
  EXPECT_EQ(p.stops, 1u);
  ASSERT_EQ(p.line_times.size(), 1u);  // every move on line 0
  EXPECT_NEAR(p.line_times[0].time_s, p.time_s, 1e-12);
}

TEST(IdealPlanner, ACornerIsPassedAtTheJunctionDeviationSpeed) {
  const MachineConfig c = ideal_mill();
  IdealPlannerOptions o;
  o.tolerance_mm = 0.01;
  Move a = line({0, 0, 0}, {20, 0, 0}, 60.0);
  Move b = line({20, 0, 0}, {20, 20, 0}, 60.0);
  a.line = 1;
  b.line = 2;
  const IdealPlan p = ideal_planner_time({a, b}, c, o);
  // 90°: sin of half the enclosed angle √½; the change of direction (−1, 1)/√2 gets 2000·√2
  const double sh = std::sqrt(0.5);
  const double vj = std::sqrt(2000.0 * std::sqrt(2.0) * 0.01 * sh / (1.0 - sh));
  EXPECT_NEAR(p.time_s, 2.0 * trapezoid(20.0, 0.0, vj, 60.0, 2000.0), 1e-9);
  ASSERT_EQ(p.line_times.size(), 2u);
  EXPECT_EQ(p.line_times[1].line, 2);
  EXPECT_NEAR(p.line_times[0].time_s, p.line_times[1].time_s, 1e-12);
  EXPECT_EQ(p.bends, 0u) << "a 90° turn is a corner, not a bend";
}

TEST(IdealPlanner, AReversalAndAnExactStopStop) {
  const MachineConfig c = ideal_mill();
  const IdealPlan back =
      ideal_planner_time({line({0, 0, 0}, {5, 0, 0}, 50.0), line({5, 0, 0}, {0, 0, 0}, 50.0)}, c);
  EXPECT_NEAR(back.time_s, 2.0 * trapezoid(5.0, 50.0, 2000.0), 1e-9);
  EXPECT_EQ(back.stops, 2u);
  Move a = line({0, 0, 0}, {5, 0, 0}, 50.0);
  a.contouring = false;  // G61
  const IdealPlan exact = ideal_planner_time({a, line({5, 0, 0}, {10, 0, 0}, 50.0)}, c);
  EXPECT_NEAR(exact.time_s, 2.0 * trapezoid(5.0, 50.0, 2000.0), 1e-9);
  EXPECT_EQ(exact.stops, 2u);
  Move dwell;
  dwell.kind = MoveKind::kDwell;
  dwell.dwell_s = 0.5;
  dwell.contouring = true;
  const IdealPlan dwelt =
      ideal_planner_time({line({0, 0, 0}, {5, 0, 0}, 50.0), dwell, line({5, 0, 0}, {10, 0, 0}, 50.0)}, c);
  EXPECT_NEAR(dwelt.time_s, 0.5 + 2.0 * trapezoid(5.0, 50.0, 2000.0), 1e-9);
}

TEST(IdealPlanner, AnArcIsOneSegmentAtItsCentripetalLimit) {
  const MachineConfig c = ideal_mill();
  // a half circle of radius 2 in XY at F100: sqrt(2000·2) = 63.2 mm/s, entered along the tangent
  // of a 10 mm line (no junction limit), ramps at 2000 mm/s² on both
  Move arc = xy_arc({10, 2, 0}, 2.0, -std::numbers::pi / 2.0, std::numbers::pi, 100.0);
  arc.line = 2;
  Move in = line({0, 0, 0}, {10, 0, 0}, 100.0);
  in.line = 1;
  const IdealPlan p = ideal_planner_time({in, arc}, c);
  EXPECT_EQ(p.segments, 2u);
  EXPECT_NEAR(p.length_mm, 10.0 + 2.0 * std::numbers::pi, 1e-12);
  const double v_arc = std::sqrt(2000.0 * 2.0);
  ASSERT_EQ(p.line_times.size(), 2u);
  EXPECT_NEAR(p.line_times[0].time_s, trapezoid(10.0, 0.0, v_arc, 100.0, 2000.0), 1e-9);
  EXPECT_NEAR(p.line_times[1].time_s, trapezoid(2.0 * std::numbers::pi, v_arc, 0.0, v_arc, 2000.0), 1e-9);
  EXPECT_EQ(p.bends, 0u) << "an arc's junction is no bend of a polyline";

  // entered across a 90° corner instead (down −Y into the arc's start tangent +X): the junction
  // deviation between the line and the tangent
  Move down = line({10, 5, 0}, {10, 0, 0}, 100.0);
  IdealPlannerOptions o;
  o.tolerance_mm = 0.01;
  const IdealPlan q = ideal_planner_time({down, arc}, c, o);
  const double sh = std::sqrt(0.5);
  const double vj = std::sqrt(2000.0 * std::sqrt(2.0) * 0.01 * sh / (1.0 - sh));
  EXPECT_NEAR(q.time_s,
              trapezoid(5.0, 0.0, vj, 100.0, 2000.0) + trapezoid(2.0 * std::numbers::pi, vj, 0.0, v_arc, 2000.0),
              1e-9);

  // a helix: the tangent's share on Z (1000 mm/s²) limits its path acceleration
  Move helix = arc;
  helix.end = {10, 4, 4};
  const IdealPlan hx = ideal_planner_time({helix}, c);
  const double planar = 2.0 * std::numbers::pi, l = std::hypot(planar, 4.0);
  const double a = std::min(2000.0 * l / planar, 1000.0 * l / 4.0);
  const double v = std::min({v_arc, 100.0, 50.0 * l / 4.0});
  EXPECT_NEAR(hx.time_s, trapezoid(l, v, a), 1e-9);
}

TEST(IdealPlanner, AnArcIsCutIntoChordsWithinTheChordTolerance) {
  const MachineConfig c = ideal_mill();
  const Move arc = xy_arc({0, 0, 0}, 2.0, 0.0, std::numbers::pi / 2.0, 20.0);
  IdealPlannerOptions o;
  o.chord_tolerance_mm = 0.002;
  o.arcs_as_chords = true;
  const IdealPlan p = ideal_planner_time({arc}, c, o);
  const double step = 2.0 * std::acos(1.0 - 0.002 / 2.0);
  EXPECT_EQ(p.segments, static_cast<std::uint64_t>(std::ceil(arc.sweep / step)));
  const double chord = 2.0 * 2.0 * std::sin(arc.sweep / static_cast<double>(p.segments) / 2.0);
  EXPECT_NEAR(p.length_mm, chord * static_cast<double>(p.segments), 1e-9);
  EXPECT_GT(p.time_s, p.length_mm / 20.0);
  EXPECT_LT(p.time_s, p.length_mm / 20.0 + 20.0 / 2000.0 * 1.5) << "at F through the chords' junctions";
}

TEST(IdealPlanner, ItsSpeedOnAFinelyDrawnCircleAsksMoreThanTheAxesGive) {
  // a circle of radius 1 mm in 3600 G1 moves at F100: each junction turns 0.1°, so the ideal
  // passes it at F, where v²/r = 10,000 mm/s², five times the XY axes' 2000
  const MachineConfig c = ideal_mill();
  std::vector<Move> circle;
  const int n = 3600;
  for (int i = 0; i < n; ++i) {
    const double a0 = 2.0 * std::numbers::pi * i / n, a1 = 2.0 * std::numbers::pi * (i + 1) / n;
    circle.push_back(line({std::cos(a0), std::sin(a0), 0}, {std::cos(a1), std::sin(a1), 0}, 100.0));
  }
  const IdealPlan p = ideal_planner_time(circle, c);
  EXPECT_EQ(p.bends, static_cast<std::uint64_t>(n - 1));
  EXPECT_GT(p.bends_over_limit, static_cast<std::uint64_t>(n / 2));
  // along the change of direction (the inward normal) the axes give between 2000 and 2000·√2
  EXPECT_GT(p.bend_accel_max, 10000.0 / (2000.0 * std::sqrt(2.0)) * 0.99);
  EXPECT_LT(p.bend_accel_max, 10000.0 / 2000.0 * 1.01);
  EXPECT_GT(p.bend_accel_median, 3.0);

  // the floor of a planner that keeps the limits holds each bend to sqrt(a·rho): slower, and
  // within the axes' acceleration on the circle
  IdealPlannerOptions keep;
  keep.keep_bend_limits = true;
  const IdealPlan k = ideal_planner_time(circle, c, keep);
  EXPECT_LE(k.bend_accel_max, 1.0 + 1e-9);
  EXPECT_EQ(k.bends_over_limit, 0u);
  EXPECT_GT(k.time_s, 2.0 * std::numbers::pi / std::sqrt(2000.0 * std::sqrt(2.0)));
  EXPECT_GT(k.time_s, 1.2 * p.time_s);
}

}  // namespace
}  // namespace pcnc
