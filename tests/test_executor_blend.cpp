// test_executor_blend.cpp — corner blending in the block executor (docs/rt-executor.md, "Corner
// blending"): a two-block corner passed at the junction-deviation speed runs a blended path within
// the blend's share of the tolerance, with no velocity step; at a feed within the plan's corner
// speed every axis's acceleration stays within its limit cycle by cycle; a feed hold inside the
// window stops on the blended path and resumes along it; a block shorter than the windows is
// spanned by both corners' windows; a block that arrives too late for the window, a tolerance of
// 0 and M22 keep today's sharp corner.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "geometry/spline_fit.hpp"
#include "motion/executor.hpp"
#include "machine_runner.hpp"
#include "make_blocks.hpp"

namespace pcnc {
namespace {

using test::ProgramBuilder;

constexpr double kTol = 0.005;

MachineConfig mill(double tolerance = kTol) {
  MachineConfig c = test::default_machine_config();
  c.motion.path_tolerance_mm = tolerance;
  return c;
}

struct Cycle {
  Vec3 p, v, a;
  bool blending;
};

// Runs the blocks (the ring kept full; with `late` > 0 the second block is held back until the
// machine is within `late` of the first one's end), one sample per cycle. With `hold_in_window`,
// a feed hold from the first cycle inside a blend's window, for `hold_cycles` cycles.
std::vector<Cycle> run(const MachineConfig& c, const std::vector<Block>& blocks, double late = 0.0, bool hold_in_window = false,
                       int hold_cycles = 0) {
  Executor ex(c);
  ex.set_position(blocks.front().start);
  MotionRing ring;
  std::size_t next = 0;
  std::vector<Cycle> out;
  int held = -1;
  for (int i = 0; i < 200000; ++i) {
    while (next < blocks.size()) {
      if (late > 0.0 && next == 1) {
        const PreparedBlock* cur = ex.current_motion();
        if (!cur || cur->length - ex.progress() >= late) break;
      }
      if (!ring.try_push(blocks[next])) break;
      ++next;
    }
    ExecInput in;
    if (hold_in_window && held < 0 && ex.blending()) held = 0;
    if (held >= 0 && held < hold_cycles) {
      in.hold = true;
      ++held;
    }
    ExecResult r;
    ex.step(ring, in, r);
    EXPECT_EQ(r.fault, FaultCode::kNone) << r.reason;
    if (r.fault != FaultCode::kNone) break;
    out.push_back({ex.position(), ex.velocity(), ex.acceleration(), ex.blending()});
    if (r.program_end) break;
  }
  return out;
}

double polyline_distance(const Vec3& p, const std::vector<Vec3>& pts) {
  double d = 1e300;
  for (std::size_t i = 0; i + 1 < pts.size(); ++i) d = std::min(d, point_segment_distance(p, pts[i], pts[i + 1]));
  return d;
}

// The same distance for points that walk along the polyline: the segments near the last nearest
// one (`hint`) first; the whole polyline when none of them is within `near` (so the result is
// the true distance whenever it exceeds `near`).
double polyline_distance_along(const Vec3& p, const std::vector<Vec3>& pts, std::size_t& hint, double near) {
  const std::size_t lo = hint > 100 ? hint - 100 : 0;
  const std::size_t hi = std::min(pts.size() > 0 ? pts.size() - 1 : 0, hint + 2000);
  double d = 1e300;
  std::size_t best = hint;
  for (std::size_t i = lo; i < hi; ++i) {
    const double di = point_segment_distance(p, pts[i], pts[i + 1]);
    if (di < d) d = di, best = i;
  }
  if (d > near) {
    for (std::size_t i = 0; i + 1 < pts.size(); ++i) {
      const double di = point_segment_distance(p, pts[i], pts[i + 1]);
      if (di < d) d = di, best = i;
    }
  }
  hint = best;
  return d;
}

// A 24° turn in XZ (the weakest axis, Z, takes the turn), as at LHchips4's line 4954.
std::vector<Vec3> corner_points() {
  const double e = 12.0 * std::numbers::pi / 180.0;
  const Vec3 a{4.0, 12.5, 15.0};
  const Vec3 p = a + 6.0 * Vec3{std::cos(e), 0.0, -std::sin(e)};
  return {a, p, p + 6.0 * Vec3{std::cos(e), 0.0, std::sin(e)}};
}

std::vector<Block> corner_program(const MachineConfig& c, double feed, bool contouring = true) {
  const auto pts = corner_points();
  ProgramBuilder b(c, pts[0]);
  b.contouring(contouring);
  b.line(pts[1], feed).line(pts[2], feed).end();
  return b.blocks();
}

// The largest per-cycle velocity change of an axis, as a ratio to its acceleration limit (the
// setpoints' second difference / dt²), over the cycles where `pick` holds.
template <class Pick>
double worst_accel_ratio(const MachineConfig& c, const std::vector<Cycle>& cy, Pick pick) {
  const double dt = c.cycle_period_s();
  double worst = 0.0;
  for (std::size_t k = 1; k + 1 < cy.size(); ++k) {
    if (!pick(k)) continue;
    for (int i = 0; i < kAxes; ++i) {
      const double acc = (cy[k + 1].p[i] - 2.0 * cy[k].p[i] + cy[k - 1].p[i]) / (dt * dt);
      worst = std::max(worst, std::abs(acc) / c.axes[i].max_accel_mm_s2);
    }
  }
  return worst;
}

TEST(ExecutorBlend, CornerAtTheJunctionSpeedIsBlendedWithinItsShareOfTheTolerance) {
  const MachineConfig c = mill();
  const auto cy = run(c, corner_program(c, 50.0));
  const auto pts = corner_points();
  int blending = 0;
  double worst = 0.0;
  for (const Cycle& k : cy) {
    blending += k.blending;
    worst = std::max(worst, polyline_distance(k.p, pts));
  }
  EXPECT_GT(blending, 5);
  EXPECT_LE(worst, kBlendToleranceShare * kTol * (1.0 + 1e-9));
  EXPECT_GT(worst, 0.5 * kBlendToleranceShare * kTol);  // the corner is cut, not passed sharp
  EXPECT_EQ(cy.back().p, pts[2]);
  // the sharp corner steps Z's velocity by v·|Δt_z| in one cycle; the blend spreads it: the worst
  // per-cycle change of any axis is well under that step's
  const double dt = c.cycle_period_s();
  const double v_j = junction_deviation_speed(normalized(pts[1] - pts[0]), normalized(pts[2] - pts[1]),
                                              {2000.0, 2000.0, 1000.0}, kTol);
  const double step_ratio = v_j * 2.0 * std::sin(12.0 * std::numbers::pi / 180.0) / dt / 1000.0;
  const double ratio = worst_accel_ratio(c, cy, [](std::size_t) { return true; });
  EXPECT_LT(ratio, 0.35 * step_ratio);
  std::cout << "[ figures  ] 24 deg XZ corner at " << v_j << " mm/s: blended " << worst * 1000.0
            << " um from the corner's lines, worst axis acceleration " << ratio << " of its limit (a sharp corner: "
            << step_ratio << ")\n";
}

TEST(ExecutorBlend, WithinThePlansCornerSpeedEveryAxisStaysWithinItsLimitCycleByCycle) {
  // At a feed under the plan's corner speed (corner_blend_plan: share 0.5 of each axis for the
  // blend), the whole window runs at that feed: every axis's acceleration within its limit in every
  // cycle, and no velocity step (the sharp corner would step Z by 2.08 mm/s at 5 mm/s: 4.2 times
  // its limit in one cycle).
  const MachineConfig c = mill();
  const auto pts = corner_points();
  CornerBlendInput in;
  in.corner = pts[1];
  in.t_in = normalized(pts[1] - pts[0]);
  in.t_out = normalized(pts[2] - pts[1]);
  in.len_in = in.len_out = 6.0;
  in.deviation = kBlendToleranceShare * kTol;
  in.accel_in = in.accel_out = 2000.0;
  in.axis_accel = {2000.0, 2000.0, 1000.0};
  in.axis_velocity = {100.0, 100.0, 50.0};
  const CornerBlend plan = corner_blend_plan(in);
  ASSERT_TRUE(plan.on);
  const double feed = std::min(5.0, plan.v_corner);
  const auto cy = run(c, corner_program(c, feed));
  int blending = 0;
  for (const Cycle& k : cy) blending += k.blending;
  EXPECT_GT(blending, 10);
  const double ratio = worst_accel_ratio(c, cy, [&](std::size_t k) { return cy[k].blending || cy[k - 1].blending || cy[k + 1].blending; });
  EXPECT_LE(ratio, 1.0);
  EXPECT_GT(ratio, 0.05);  // the blend does turn the path there
  // and the executor's own acceleration output agrees with the setpoints' second differences
  for (std::size_t k = 1; k + 1 < cy.size(); ++k) {
    if (!cy[k].blending) continue;
    EXPECT_LE(std::abs(cy[k].a[2]), c.axes[2].max_accel_mm_s2 * 1.001);
  }
}

TEST(ExecutorBlend, FeedHoldInsideTheWindowStopsOnTheBlendedPathAndResumesAlongIt) {
  const MachineConfig c = mill();
  // the blended path does not depend on the feed: run slowly (0.5 µm a cycle), it is the reference
  const auto free_run = run(c, corner_program(c, 1.0));
  // at 5 mm/s the hold stops within 7 µm, well inside the window (52 µm)
  const auto held = run(c, corner_program(c, 5.0), 0.0, true, 400);
  // every setpoint of the held run lies on the reference path, so the stop and the resume kept
  // the blended path
  std::vector<Vec3> path;
  for (const Cycle& k : free_run) path.push_back(k.p);
  int stopped = 0;
  double worst = 0.0;
  std::size_t hint = 0;
  for (std::size_t k = 0; k < held.size(); ++k) {
    if (k > 0 && held[k].p == held[k - 1].p && held[k].blending) ++stopped;
    worst = std::max(worst, polyline_distance_along(held[k].p, path, hint, 1e-6));
  }
  EXPECT_GT(stopped, 100);  // it came to rest inside the window and stood there
  EXPECT_LT(worst, 1e-5);   // on the blended path (the reference's samples are chords of it)
  EXPECT_EQ(held.back().p, corner_points()[2]);
}

TEST(ExecutorBlend, ABlockShorterThanTheWindowsIsSpannedByBothCorners) {
  // curve-like corner pair of LHchips4: a 20° turn, a 2 µm line, another 20° turn
  const MachineConfig c = mill();
  const double e = 20.0 * std::numbers::pi / 180.0;
  const Vec3 a{4.0, 12.5, 15.0}, p1 = a + 5.0 * Vec3{1.0, 0.0, 0.0};
  const Vec3 p2 = p1 + 0.002 * Vec3{std::cos(e), 0.0, std::sin(e)};
  const Vec3 p3 = p2 + 5.0 * Vec3{std::cos(2 * e), 0.0, std::sin(2 * e)};
  ProgramBuilder b(c, a);
  b.contouring(true);
  b.line(p1, 50.0).line(p2, 50.0).line(p3, 50.0).end();
  const auto cy = run(c, b.blocks());
  const std::vector<Vec3> pts{a, p1, p2, p3};
  double worst = 0.0, worst_dv = 0.0;
  for (std::size_t k = 0; k < cy.size(); ++k) {
    worst = std::max(worst, polyline_distance(cy[k].p, pts));
    if (k > 0) worst_dv = std::max(worst_dv, std::abs(cy[k].v[2] - cy[k - 1].v[2]));
  }
  EXPECT_LE(worst, kBlendToleranceShare * kTol * (1.0 + 1e-9));
  EXPECT_GT(worst, 0.3 * kBlendToleranceShare * kTol);
  // the two steps of Z's velocity (v·sin 20° and v·(sin 40° − sin 20°) at the corners' speed,
  // 2 µm apart: one cycle today) are spread over the group's window (31 µm: 3 cycles at this speed)
  const double v_j = junction_deviation_speed({1, 0, 0}, {std::cos(e), 0, std::sin(e)}, {2000.0, 2000.0, 1000.0}, kTol);
  EXPECT_LT(worst_dv, 0.6 * v_j * std::sin(2 * e));
  std::cout << "[ figures  ] two 20 deg turns 2 um apart at " << v_j << " mm/s: " << worst * 1000.0
            << " um from the polyline, Z velocity change per cycle at most " << worst_dv << " mm/s (sharp: "
            << v_j * std::sin(2 * e) << ")\n";
  EXPECT_EQ(cy.back().p, p3);
}

TEST(ExecutorBlend, ArcIntoLineIsBlendedWithinTheBudget) {
  // a quarter arc of r 1 mm in XY, then a line turning 60° away from its end tangent
  const MachineConfig c = mill();
  const Vec3 centre{12.5, 12.5, 15.0}, s{13.5, 12.5, 15.0}, e{12.5, 13.5, 15.0};
  const Vec3 out = e + 3.0 * Vec3{-0.5, -std::sqrt(3.0) / 2.0, 0.0};
  ProgramBuilder b(c, s);
  b.contouring(true);
  b.arc(e, centre, 2, false, 30.0).line(out, 30.0).end();
  const auto cy = run(c, b.blocks());
  int blending = 0;
  double worst = 0.0;
  for (const Cycle& k : cy) {
    blending += k.blending;
    double d = point_segment_distance(k.p, e, out);
    const Vec3 r = k.p - centre;
    const double ang = std::atan2(r[1], r[0]);
    if (ang >= -1e-9 && ang <= std::numbers::pi / 2 + 1e-9) d = std::min(d, std::abs(std::hypot(r[0], r[1]) - 1.0));
    worst = std::max(worst, d);
  }
  EXPECT_GT(blending, 3);
  EXPECT_LE(worst, kBlendToleranceShare * kTol * 1.01);
  EXPECT_EQ(cy.back().p, out);
}

TEST(ExecutorBlend, SharpCornerWhereTheBlendCannotBeginOrIsNotAsked) {
  const auto pts = corner_points();
  auto worst_of = [&](const std::vector<Cycle>& cy, int* blending) {
    double worst = 0.0;
    *blending = 0;
    for (const Cycle& k : cy) {
      *blending += k.blending;
      worst = std::max(worst, polyline_distance(k.p, pts));
    }
    return worst;
  };
  int n = 0;
  // the next block reaches the ring only when the machine is 1 µm from the corner: the window
  // never begins behind the machine, it is at most what is left (h <= 1 µm), and no setpoint jumps
  const MachineConfig c = mill();
  const auto late = run(c, corner_program(c, 50.0), 0.001);
  EXPECT_LT(worst_of(late, &n), kBlendDeviation * 0.001 * std::sin(24.0 * std::numbers::pi / 180.0) + 1e-12);
  for (std::size_t k = 1; k < late.size(); ++k) EXPECT_LT(norm(late[k].p - late[k - 1].p), 50.0 * c.cycle_period_s() * 1.001);
  EXPECT_EQ(late.back().p, pts[2]);
  // tolerance 0 (the seed's rule) and M22: no blend
  const MachineConfig seed = mill(0.0);
  EXPECT_LT(worst_of(run(seed, corner_program(seed, 50.0)), &n), 1e-12);
  EXPECT_EQ(n, 0);
  EXPECT_LT(worst_of(run(c, corner_program(c, 50.0, false)), &n), 1e-12);
  EXPECT_EQ(n, 0);
}

}  // namespace
}  // namespace pcnc
