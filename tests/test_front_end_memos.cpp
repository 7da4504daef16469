// test_front_end_memos.cpp — the NURBS plans and the smoothing fits kept between the front end's
// passes (gcode/nurbs_plan_memo.hpp, gcode/spline_fit_memo.hpp): a second request for the same curve and limits is a hit whose
// blocks are byte for byte those planning makes; any difference in the curve or the limits is
// a miss; an entry is handed out once; and a whole program checked twice in one process (what
// pcnc-host does: the check, then the stream) gives the same blocks both times, the second
// time from the memo. The same for fit_polyline's fits.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "gcode/nurbs_plan_memo.hpp"
#include "gcode/spline_fit_memo.hpp"
#include "gcode_test_util.hpp"
#include "nurbs_circles.hpp"

namespace pcnc::test {
namespace {

std::string bytes_of(const std::vector<Block>& blocks) {
  std::string s;
  for (const Block& b : blocks) s.append(reinterpret_cast<const char*>(&b), sizeof(Block));
  return s;
}

NurbsLimits limits(double feed) {
  NurbsLimits l = nurbs_limits(mill_config(), feed);
  l.samples_per_span = 64;
  return l;
}

TEST(NurbsPlanMemo, SecondRequestIsAnExactHitOnce) {
  nurbs_plan_memo_clear();
  const NurbsCurve c = quarter_circle(3.0, Vec3{10, 10, 5});
  const NurbsBlocks fresh = plan_nurbs_blocks(c, limits(20.0));
  ASSERT_TRUE(fresh.error.empty()) << fresh.error;
  ASSERT_FALSE(fresh.blocks.empty());

  const NurbsBlocks first = plan_nurbs_blocks_memo(c, limits(20.0));
  EXPECT_EQ(nurbs_plan_memo_stats().misses, 1u);
  EXPECT_EQ(nurbs_plan_memo_stats().entries, 1u);
  EXPECT_GE(nurbs_plan_memo_stats().bytes, fresh.blocks.size() * sizeof(Block));
  const NurbsBlocks second = plan_nurbs_blocks_memo(c, limits(20.0));
  EXPECT_EQ(nurbs_plan_memo_stats().hits, 1u);
  EXPECT_EQ(nurbs_plan_memo_stats().entries, 0u);  // handed out once
  EXPECT_EQ(nurbs_plan_memo_stats().bytes, 0u);
  EXPECT_EQ(bytes_of(first.blocks), bytes_of(fresh.blocks));
  EXPECT_EQ(bytes_of(second.blocks), bytes_of(fresh.blocks));
  EXPECT_EQ(second.corner_after, fresh.corner_after);
  // the third request plans again
  (void)plan_nurbs_blocks_memo(c, limits(20.0));
  EXPECT_EQ(nurbs_plan_memo_stats().misses, 2u);
}

TEST(NurbsPlanMemo, AnyDifferenceIsAMiss) {
  nurbs_plan_memo_clear();
  const NurbsCurve c = quarter_circle(3.0, Vec3{10, 10, 5});
  (void)plan_nurbs_blocks_memo(c, limits(20.0));
  NurbsCurve moved = c;
  moved.points[1][2] += 1e-12;  // one control point, by a picometre
  const NurbsBlocks a = plan_nurbs_blocks_memo(moved, limits(20.0));
  EXPECT_EQ(bytes_of(a.blocks), bytes_of(plan_nurbs_blocks(moved, limits(20.0)).blocks));
  NurbsLimits l = limits(20.0);
  l.axis_accel_mm_s2[2] *= 0.5;  // one limit the hash does not see
  const NurbsBlocks b = plan_nurbs_blocks_memo(c, l);
  EXPECT_EQ(bytes_of(b.blocks), bytes_of(plan_nurbs_blocks(c, l).blocks));
  EXPECT_EQ(nurbs_plan_memo_stats().hits, 0u);
  EXPECT_EQ(nurbs_plan_memo_stats().misses, 3u);
}

TEST(NurbsPlanMemo, AProgramCheckedTwiceGivesTheSameBlocks) {
  nurbs_plan_memo_clear();
  spline_fit_memo_clear();
  // a run of short G1 moves on a gentle arc: smoothed into a curve at the mill's tolerance
  std::string text = "G21 G90 M21 G64 P0.005\nG0 X0 Y0 Z0\nG1 X0.05 Y0 F1200\n";
  for (int i = 2; i <= 60; ++i) {
    const double a = i * 0.01;
    text += "G1 X" + std::to_string(5.0 * std::sin(a)) + " Y" + std::to_string(5.0 * (1.0 - std::cos(a))) + "\n";
  }
  text += "M30\n";
  const MachineConfig c = wide_config();
  JobOptions o;
  o.start_position = Vec3{0, 0, 0};
  const CheckResult r1 = check_program_text(text, "t.ngc", c, o);
  ASSERT_TRUE(r1.ok);
  ASSERT_GT(r1.smoothed_curves, 0u);
  const std::size_t misses = nurbs_plan_memo_stats().misses;
  const CheckResult r2 = check_program_text(text, "t.ngc", c, o);
  ASSERT_TRUE(r2.ok);
  EXPECT_GT(nurbs_plan_memo_stats().hits, 0u);
  EXPECT_EQ(nurbs_plan_memo_stats().misses, misses);  // nothing planned again
  EXPECT_GT(spline_fit_memo_stats().hits, 0u);           // nor fitted again
  EXPECT_EQ(spline_fit_memo_stats().hits, spline_fit_memo_stats().misses);
  EXPECT_EQ(r1.max_path_deviation_mm, r2.max_path_deviation_mm);
  EXPECT_EQ(r1.smoothed_blocks, r2.smoothed_blocks);
  EXPECT_EQ(r1.planned_time_s, r2.planned_time_s);
}

TEST(SplineFitMemo, SecondRequestIsAnExactHitOnceAndAnyDifferenceAMiss) {
  spline_fit_memo_clear();
  std::vector<Vec3> pts;
  for (int i = 0; i <= 30; ++i) pts.push_back(Vec3{0.05 * i, 0.3 * std::sin(0.05 * i), 0.0});
  const SplineFit fresh = fit_polyline(pts, 0.005);
  ASSERT_TRUE(fresh.ok);
  auto same = [](const SplineFit& a, const SplineFit& b) {
    return a.curve.degree == b.curve.degree && a.curve.points == b.curve.points && a.curve.weights == b.curve.weights &&
           a.curve.knots == b.curve.knots && a.deviation == b.deviation && a.ok == b.ok && a.worst_point == b.worst_point;
  };
  EXPECT_TRUE(same(fit_polyline_memo(pts, 0.005), fresh));
  EXPECT_EQ(spline_fit_memo_stats().entries, 1u);
  EXPECT_TRUE(same(fit_polyline_memo(pts, 0.005), fresh));
  EXPECT_EQ(spline_fit_memo_stats().hits, 1u);
  EXPECT_EQ(spline_fit_memo_stats().entries, 0u);  // handed out once
  // a different tolerance, or one point moved by a picometre: fitted anew
  (void)fit_polyline_memo(pts, 0.005);
  EXPECT_TRUE(same(fit_polyline_memo(pts, 0.004), fit_polyline(pts, 0.004)));
  std::vector<Vec3> moved = pts;
  moved[7][1] += 1e-12;
  EXPECT_TRUE(same(fit_polyline_memo(moved, 0.005), fit_polyline(moved, 0.005)));
  EXPECT_EQ(spline_fit_memo_stats().hits, 1u);
  EXPECT_EQ(spline_fit_memo_stats().misses, 4u);
}

}  // namespace
}  // namespace pcnc::test
