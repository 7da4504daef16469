// test_nurbs_interp.cpp — real-time NURBS interpolation at T = 0.5 ms against exact
// geometry: setpoints of circles (rational quadratics) on the true circle within 0.01 µm,
// run time of a NURBS circle against the analytic arc's, a line stays a line, the chord
// error of a free-form curve never exceeds delta, the path speed follows the schedule, the
// Taylor step with its correction hits the requested step length, feed hold, end speeds and
// a long curve run through its split pieces without stopping.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include "geometry/nurbs.hpp"
#include "ipc/block_nurbs.hpp"
#include "nurbs_circles.hpp"
#include "motion/nurbs_follower.hpp"
#include "gcode/nurbs_schedule.hpp"

namespace pcnc {
namespace {

const double kInterpScale = test::kCircleWeight;
using test::full_circle;
using test::quarter_circle;
constexpr double kT = 0.0005;

// The desktop mill's limits (configs/desktop-mill.toml) without reading the file.
NurbsLimits limits(double feed, double delta = 0.001) {
  NurbsLimits lim;
  lim.feed_mm_s = feed;
  lim.period_s = kT;
  lim.chord_tolerance_mm = delta;
  lim.axis_velocity_mm_s = {100, 100, 50};
  lim.axis_accel_mm_s2 = {2000, 2000, 1000};
  return lim;
}

// nurbs-xy.ngc (order 3) scaled up to a few mm, and trident-xy.ngc (order 4, doubled start).
NurbsCurve nurbs_xy_curve() {
  return make_nurbs({{0, 0, 0}, {0, 5, 0}, {10, 10, 0}, {10, 0, 0}, {0, 0, 0}}, {1, 1, 1, 1, 2}, 3);
}
NurbsCurve trident_xy() {
  return make_nurbs(
      {{10, 0, 0}, {10, 0, 0}, {20, 20, 0}, {12, 8, 0}, {10, 20, 0}, {8, 8, 0}, {0, 20, 0}, {10, 0, 0}},
      std::vector<double>(8, 1.0), 4);
}

struct NurbsCycle {
  double u0, u1;  // parameter before and after
  Vec3 p;         // setpoint
  double chord;   // |p - previous p|
  double v;       // follower speed after the step
};

struct BlockRun {
  std::vector<NurbsCycle> cycles;
  bool finished = false;
};

// Runs one block from rest to rest (or between given speeds) and records every cycle.
BlockRun run_block(const Block& b, double v_start = 0.0, double v_end = 0.0, int hold_from = -1, int hold_to = -1) {
  BlockRun r;
  NurbsFollower f;
  f.start(b, v_start);
  Vec3 prev = f.at().p;
  for (int k = 0; k < 10'000'000 && !f.done(); ++k) {
    const double u0 = f.u();
    const double scale = (k >= hold_from && k < hold_to) ? 0.0 : 1.0;
    const Vec3 p = f.step(b, kT, v_end, scale);
    r.cycles.push_back({u0, f.u(), p, norm(p - prev), f.speed()});
    prev = p;
  }
  r.finished = f.done();
  return r;
}

Block single_block(const NurbsCurve& c, const NurbsLimits& lim) {
  const NurbsBlocks nb = plan_nurbs_blocks(c, lim);
  EXPECT_EQ(nb.error, "");
  EXPECT_EQ(nb.blocks.size(), 1u);
  return nb.blocks.front();
}

TEST(NurbsStep, TaylorStepWithCorrectionHitsTheStepLength) {
  for (const NurbsCurve& c : {nurbs_xy_curve(), trident_xy(), full_circle(3, {0, 0, 0})}) {
    const NurbsView v = c.view();
    for (double ds : {1e-4, 0.005, 0.05}) {
      double u = v.u_min();
      NurbsEval at = nurbs_eval(v, u);
      int steps = 0;
      while (true) {
        const NurbsStep st = nurbs_parameter_step(v, u, at, ds);
        EXPECT_GT(st.u, u);
        EXPECT_NEAR(norm(st.eval.p - at.p), st.chord, 1e-15);
        if (st.at_end) {
          EXPECT_LE(st.chord, ds * (1 + 1e-12));
          EXPECT_EQ(st.u, v.u_max());
          break;
        }
        EXPECT_NEAR(st.chord, ds, 1e-10 * ds + 1e-13) << "u=" << u;
        u = st.u;
        at = st.eval;
        ++steps;
      }
      EXPECT_GT(steps, 0);
    }
  }
}

// The rt steps with a knot-span hint kept between cycles: the same span, so the same step to
// the last bit (u, the curve's point and derivatives, the chord), also from a stale hint (set
// to the last span midway) and across repeated knots (the circle's).
TEST(NurbsStep, TheSpanHintGivesTheSameStepBitForBit) {
  auto same = [](double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; };
  for (const NurbsCurve& c : {nurbs_xy_curve(), trident_xy(), full_circle(3, {0, 0, 0})}) {
    const NurbsView v = c.view();
    for (double ds : {1e-4, 0.005, 0.05}) {
      int hint = 0, stepped = 0;
      double u = v.u_min();
      NurbsEval at = nurbs_eval(v, u);
      for (int k = 0; k < 100000; ++k) {
        if (k == 50) hint = static_cast<int>(c.points.size()) - 1;  // a stale hint: the last span
        const NurbsStep a = nurbs_parameter_step(v, u, at, ds);
        const NurbsStep b = nurbs_parameter_step(v, u, at, ds, hint);
        ASSERT_TRUE(same(a.u, b.u) && same(a.chord, b.chord) && a.at_end == b.at_end) << "u=" << u;
        for (int i = 0; i < 3; ++i) {
          ASSERT_TRUE(same(a.eval.p[i], b.eval.p[i]) && same(a.eval.d1[i], b.eval.d1[i]) && same(a.eval.d2[i], b.eval.d2[i]));
        }
        ++stepped;
        if (a.at_end) break;
        u = a.u;
        at = a.eval;
      }
      EXPECT_GT(stepped, 2);
    }
  }
}

TEST(NurbsInterp, CircleSetpointsOnTheTrueCircle) {
  const Vec3 center{12.5, 12.5, 20.0};
  for (const auto& [curve, r] : {std::pair{quarter_circle(10.0, center), 10.0}, std::pair{full_circle(8.0, center), 8.0}}) {
    const Block b = single_block(curve, limits(50.0));
    const BlockRun run = run_block(b);
    ASSERT_TRUE(run.finished);
    ASSERT_GT(run.cycles.size(), 100u);
    for (const NurbsCycle& c : run.cycles) {
      EXPECT_NEAR(norm(c.p - center), r, 1e-5) << "u=" << c.u1;  // 0.01 µm
      EXPECT_NEAR(c.p[2], 20.0, 1e-12);
    }
    EXPECT_EQ(run.cycles.back().p, b.end);
  }
}

TEST(NurbsInterp, CircleRunTimeMatchesTheAnalyticArc) {
  // The analytic arc of the same radius at the same feed and acceleration: a trapezoid over
  // its length (2 pi r), L / F + F / a when the feed is reached.
  const double r = 10.0, feed = 50.0;
  const Block b = single_block(full_circle(r, {12.5, 12.5, 0}), limits(feed));
  const double length = 2.0 * M_PI * r;
  EXPECT_NEAR(b.length, length, 1e-9);
  const double t_arc = length / feed + feed / b.accel;
  const BlockRun run = run_block(b);
  const double t_nurbs = static_cast<double>(run.cycles.size()) * kT;
  EXPECT_NEAR(t_nurbs / t_arc, 1.0, 0.01) << "nurbs " << t_nurbs << " s, arc " << t_arc << " s";
}

TEST(NurbsInterp, LineSetpointsOnTheLine) {
  const Vec3 a{2, 3, 20}, e{22, 13, 5};
  std::vector<Vec3> pts;
  for (double s : {0.0, 0.3, 0.35, 0.6, 1.0}) pts.push_back(a + s * (e - a));
  const NurbsCurve c = make_nurbs(pts, {1, 2, 0.5, 1, 1}, 3);
  const Block b = single_block(c, limits(40.0));
  EXPECT_EQ(b.motion_class, MotionClass::kSpace);
  const BlockRun run = run_block(b);
  ASSERT_TRUE(run.finished);
  const Vec3 dir = normalized(e - a);
  double along = 0.0;
  for (const NurbsCycle& cy : run.cycles) {
    const Vec3 off = cy.p - a;
    EXPECT_NEAR(norm(off - dot(off, dir) * dir), 0.0, 1e-11);
    EXPECT_GE(dot(off, dir), along - 1e-12);  // never backwards
    along = dot(off, dir);
  }
  EXPECT_NEAR(along, norm(e - a), 1e-12);
}

// Largest distance of the curve between two parameters from the chord joining its ends.
double chord_error(const NurbsView& v, double u0, double u1) {
  const Vec3 p0 = nurbs_point(v, u0);
  const Vec3 p1 = nurbs_point(v, u1);
  const Vec3 d = p1 - p0;
  const double len = norm(d);
  double worst = 0.0;
  for (int i = 1; i < 16; ++i) {
    const Vec3 q = nurbs_point(v, u0 + (u1 - u0) * i / 16.0) - p0;
    const double along = len > 0.0 ? std::clamp(dot(q, d) / (len * len), 0.0, 1.0) : 0.0;
    worst = std::max(worst, norm(q - along * d));
  }
  return worst;
}

TEST(NurbsInterp, FreeFormChordErrorWithinDeltaAndSpeedFollowsSchedule) {
  for (const double delta : {0.001, 0.0001}) {
    for (const NurbsCurve& curve : {nurbs_xy_curve(), trident_xy()}) {
      const double feed = 80.0;
      const NurbsLimits lim = limits(feed, delta);
      const Block b = single_block(curve, lim);
      const NurbsView v = view_of(b.nurbs);
      const BlockRun run = run_block(b);
      ASSERT_TRUE(run.finished);
      double worst = 0.0;
      int compared = 0;
      int hint = 0;
      for (std::size_t k = 0; k < run.cycles.size(); ++k) {
        const NurbsCycle& c = run.cycles[k];
        worst = std::max(worst, chord_error(v, c.u0, c.u1));
        // Path speed measured from the setpoints against the block's schedule, where no limit
        // binds: the follower is neither accelerating nor capped (constant speed over three
        // cycles) and the schedule is flat at the feed.
        if (k >= 2 && k + 1 < run.cycles.size()) {
          const double sched = block_schedule_speed(b.nurbs, c.u1, hint);
          const bool steady = run.cycles[k - 2].v == c.v && run.cycles[k - 1].v == c.v;
          if (steady && sched == feed) {
            EXPECT_NEAR(c.chord / kT, sched, 1e-3 * sched) << "cycle " << k;
            ++compared;
          }
          // Never above the schedule anywhere (the trapezoid of two speeds each under it).
          EXPECT_LE(c.chord / kT, std::max(sched, block_schedule_speed(b.nurbs, c.u0, hint)) * (1 + 1e-9) + 1e-9);
        }
      }
      EXPECT_LE(worst, delta) << "delta " << delta;
      EXPECT_GT(compared, 100) << "the feed must be reached somewhere";
    }
  }
}

TEST(NurbsInterp, AccelerationLimitAndEndSpeeds) {
  const Block b = single_block(nurbs_xy_curve(), limits(60.0));
  // From rest to rest: speed steps never exceed a T (plus rounding), a the schedule's tangential
  // acceleration where the cycle starts (the smaller of the two points around it), never less
  // than the block's accel (the smallest of the schedule's).
  const BlockRun run = run_block(b);
  double prev_v = 0.0;
  int hint = 0;
  bool above_block_accel = false;
  for (const NurbsCycle& c : run.cycles) {
    const double a = std::max(b.accel, block_schedule_accel(b.nurbs, c.u0, hint));
    EXPECT_LE(std::fabs(c.v - prev_v), a * kT * (1 + 1e-9));
    if (std::fabs(c.v - prev_v) > b.accel * kT * 1.01) above_block_accel = true;
    prev_v = c.v;
  }
  EXPECT_TRUE(above_block_accel) << "where the curve allows more, the speed changes faster";
  EXPECT_LT(run.cycles.back().v, 2.5 * b.accel * kT);  // stopped within the last cycles
  // Joined to a neighbour: ends at the required speed.
  const double v_end = 30.0;
  const BlockRun joined = run_block(b, 0.0, v_end);
  ASSERT_TRUE(joined.finished);
  EXPECT_NEAR(joined.cycles.back().v, v_end, b.accel * kT);
}

TEST(NurbsInterp, FeedHoldStopsOnThePathAndResumes) {
  const Vec3 center{12.5, 12.5, 0};
  const Block b = single_block(full_circle(6.0, center), limits(40.0));
  const BlockRun run = run_block(b, 0.0, 0.0, 400, 1400);
  ASSERT_TRUE(run.finished);
  bool stood_still = false;
  double prev_v = 0.0;
  int hint = 0;
  for (std::size_t k = 0; k < run.cycles.size(); ++k) {
    const NurbsCycle& c = run.cycles[k];
    EXPECT_NEAR(norm(c.p - center), 6.0, 1e-5);
    EXPECT_LE(std::fabs(c.v - prev_v), std::max(b.accel, block_schedule_accel(b.nurbs, c.u0, hint)) * kT * (1 + 1e-9));  // hold decelerates
    prev_v = c.v;
    if (k > 400 && k < 1400 && c.v == 0.0) stood_still = true;
  }
  EXPECT_TRUE(stood_still);
}

TEST(NurbsInterp, LongCurveRunsThroughItsPiecesWithoutStopping) {
  std::mt19937 rng(77);
  std::uniform_real_distribution<double> step(-1.0, 1.0);
  std::vector<Vec3> pts{{2, 2, 2}};
  for (int i = 1; i < 90; ++i) pts.push_back(pts.back() + Vec3{0.25 + 0.1 * step(rng), 0.3 * step(rng), 0.05 * step(rng)});
  const NurbsCurve curve = make_nurbs(pts, std::vector<double>(pts.size(), 1.0), 4, KnotRule::kChordLength);
  const NurbsBlocks nb = plan_nurbs_blocks(curve, limits(30.0));
  ASSERT_EQ(nb.error, "");
  ASSERT_GE(nb.blocks.size(), 3u);
  NurbsFollower f;
  f.start(nb.blocks[0], 0.0);
  Vec3 prev = f.at().p;
  double min_v_at_joins = 1e9;
  std::size_t cycles = 0;
  for (std::size_t i = 0; i < nb.blocks.size(); ++i) {
    const Block& b = nb.blocks[i];
    const bool last = i + 1 == nb.blocks.size();
    // The junction speed: what both schedules allow at the join.
    const double v_end = last ? 0.0
                              : std::min(b.nurbs.schedule_speed[b.nurbs.schedule_count - 1],
                                         nb.blocks[i + 1].nurbs.schedule_speed[0]);
    while (!f.done()) {
      const Vec3 p = f.step(b, kT, v_end, 1.0);
      ++cycles;
      // Every setpoint is on the curve (pieces are the same curve) ...
      const double u = f.u();
      EXPECT_LT(norm(p - nurbs_point(curve.view(), u)), 1e-9);
      prev = p;
    }
    if (!last) {
      min_v_at_joins = std::min(min_v_at_joins, f.speed());
      // Continue into the next piece with the speed reached and carry the overshoot.
      const double v = f.speed();
      const double carry = f.leftover();
      f.start(nb.blocks[i + 1], v);
      EXPECT_LT(norm(f.at().p - prev), 1e-9);
      EXPECT_LT(carry, v * kT + 1e-12);
    }
  }
  EXPECT_GT(min_v_at_joins, 5.0) << "the rt must not stop at the joins";
  EXPECT_EQ(prev, curve.points.back());
  EXPECT_GT(cycles, 100u);
}

}  // namespace
}  // namespace pcnc
