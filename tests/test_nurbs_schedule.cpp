// test_nurbs_schedule.cpp — the NURBS feed schedule: each limit (feed, chord error,
// centripetal, axis velocity) where it should bind and with its formula's value, the
// acceleration passes, the cut into block schedules (never above the dense schedule) and
// whole moves turned into chained ring blocks.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <array>
#include <random>
#include <vector>

#include "config/config.hpp"
#include "geometry/nurbs.hpp"
#include "ipc/block_check.hpp"
#include "ipc/block_nurbs.hpp"
#include "nurbs_circles.hpp"
#include "gcode/nurbs_schedule.hpp"
#include "test_paths.hpp"

namespace pcnc {
namespace {

const double kScheduleScale = test::kCircleWeight;
using test::full_circle;
using test::quarter_circle;

NurbsCurve straight_curve(Vec3 a, Vec3 b) {
  std::vector<Vec3> pts;
  for (double s : {0.0, 0.2, 0.5, 0.8, 1.0}) pts.push_back(a + s * (b - a));
  return make_nurbs(pts, {1, 1, 1, 1, 1}, 4);
}

NurbsCurve random_scheduled_curve(int count, int degree, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> coord(0.0, 20.0);
  std::uniform_real_distribution<double> weight(0.5, 2.0);
  std::vector<Vec3> pts;
  std::vector<double> w;
  for (int i = 0; i < count; ++i) {
    pts.push_back({coord(rng), coord(rng), 0.1 * coord(rng)});
    w.push_back(weight(rng));
  }
  return make_nurbs(pts, w, degree + 1, KnotRule::kChordLength);
}

NurbsLimits desktop_limits(double feed) {
  return nurbs_limits(load_config(test::default_config()), feed);
}

// The ramps use 90 % of each sample's acceleration (a margin for the rt's linear interpolation).
constexpr double kRampShare = 0.9;

// The passes' invariant: between neighbours, v^2 changes by at most 2 a ds, a the ramp share
// of the smaller of the two samples' accelerations.
void expect_accel_consistent(const FeedSchedule& fs) {
  for (std::size_t j = 1; j < fs.samples.size(); ++j) {
    const FeedSample& a = fs.samples[j - 1];
    const FeedSample& b = fs.samples[j];
    const double dv2 = std::fabs(b.speed * b.speed - a.speed * a.speed);
    EXPECT_LE(dv2, 2.0 * kRampShare * std::min(a.accel, b.accel) * (b.s - a.s) * (1 + 1e-9) + 1e-9) << "sample " << j;
    EXPECT_LE(b.speed, b.limit + 1e-12);
    EXPECT_GE(b.accel, fs.accel_mm_s2);
  }
}

// Unit tangent and curvature vector by finite differences of the curve's points (independent
// of the schedule's own evaluation).
void frame_by_differences(const NurbsView& v, double u, Vec3& t, Vec3& k) {
  const double h = 1e-5 * (v.u_max() - v.u_min());
  const double a = std::max(v.u_min(), u - h), b = std::min(v.u_max(), u + h), m = 0.5 * (a + b);
  const double hh = 0.5 * (b - a);
  const Vec3 pm = nurbs_point(v, a), p0 = nurbs_point(v, m), pp = nurbs_point(v, b);
  const Vec3 d1 = (1.0 / (2.0 * hh)) * (pp - pm);
  const Vec3 d2 = (1.0 / (hh * hh)) * (pp - 2.0 * p0 + pm);
  t = normalized(d1);
  k = (1.0 / dot(d1, d1)) * (d2 - dot(d2, t) * t);
}

// Per axis, at speed v and tangential acceleration a: |t_i| a + |k_i| v^2 <= A_i (slack for the
// finite differences). Returns the largest ratio to the limit.
double worst_axis_ratio(const NurbsView& view, double u, double v, double a, const NurbsLimits& lim) {
  Vec3 t, k;
  frame_by_differences(view, u, t, k);
  double worst = 0.0;
  for (std::size_t i = 0; i < 3; ++i) {
    worst = std::max(worst, (std::fabs(t[i]) * a + std::fabs(k[i]) * v * v) / lim.axis_accel_mm_s2[i]);
  }
  return worst;
}

TEST(NurbsSchedule, LimitsComeFromTheConfig) {
  const MachineConfig cfg = load_config(test::default_config());
  const NurbsLimits lim = nurbs_limits(cfg, 25.0);
  EXPECT_EQ(lim.feed_mm_s, 25.0);
  EXPECT_DOUBLE_EQ(lim.period_s, 1.0 / cfg.motion.cycle_hz);
  EXPECT_EQ(lim.chord_tolerance_mm, cfg.gcode.nurbs_chord_tolerance_mm);
  EXPECT_EQ(lim.axis_velocity_mm_s[2], cfg.axes[2].max_velocity_mm_s);
  EXPECT_EQ(lim.axis_accel_mm_s2[0], cfg.axes[0].max_accel_mm_s2);
}

TEST(NurbsSchedule, StraightLineAcceleratesOnceAndDeceleratesOnce) {
  const NurbsLimits lim = desktop_limits(40.0);
  // along X, no curvature: the whole 2000 mm/s² but the 5 % sampling margin is tangential
  const NurbsCurve c = straight_curve({1, 1, 0}, {21, 1, 0});
  const FeedSchedule fs = plan_nurbs_feed(c, lim);
  EXPECT_NEAR(fs.length_mm, 20.0, 1e-9);
  const double a = kTangentialAccelMargin * 2000.0;  // 1900
  EXPECT_DOUBLE_EQ(fs.accel_mm_s2, a);
  for (const FeedSample& f : fs.samples) EXPECT_NEAR(f.accel, a, 1e-9);
  EXPECT_EQ(fs.samples.front().speed, 0.0);
  EXPECT_EQ(fs.samples.back().speed, 0.0);
  expect_accel_consistent(fs);
  bool falling = false;
  for (std::size_t j = 1; j < fs.samples.size(); ++j) {
    const FeedSample& f = fs.samples[j];
    EXPECT_EQ(f.binding, FeedLimit::kFeed);
    // v = min(F, sqrt(2 a s), sqrt(2 a (L - s))) exactly, a the ramp acceleration.
    const double want = std::min({40.0, std::sqrt(2.0 * kRampShare * a * f.s), std::sqrt(2.0 * kRampShare * a * (fs.length_mm - f.s))});
    EXPECT_NEAR(f.speed, want, 1e-9 * 40.0) << "s=" << f.s;
    if (f.speed < fs.samples[j - 1].speed) falling = true;
    if (falling) {
      EXPECT_LE(f.speed, fs.samples[j - 1].speed);  // one rise, one fall
    }
  }
  // Given start and end speeds are kept.
  const FeedSchedule joined = plan_nurbs_feed(c, lim, 40.0, 15.0);
  EXPECT_EQ(joined.samples.front().speed, 40.0);
  EXPECT_EQ(joined.samples.back().speed, 15.0);
  expect_accel_consistent(joined);
}

TEST(NurbsSchedule, AxisVelocityProjectedOnTheTangent) {
  NurbsLimits lim = desktop_limits(500.0);
  const FeedSchedule along_x = plan_nurbs_feed(straight_curve({0, 0, 0}, {20, 0, 0}), lim, 500.0, 500.0);
  const FeedSchedule diagonal = plan_nurbs_feed(straight_curve({0, 0, 0}, {20, 20, 0}), lim, 500.0, 500.0);
  const FeedSchedule steep = plan_nurbs_feed(straight_curve({0, 0, 0}, {10, 0, 10}), lim, 500.0, 500.0);
  const std::size_t mid = along_x.samples.size() / 2;
  EXPECT_NEAR(along_x.samples[mid].speed, 100.0, 1e-9);
  EXPECT_NEAR(diagonal.samples[mid].speed, 100.0 * std::sqrt(2.0), 1e-9);
  EXPECT_NEAR(steep.samples[mid].speed, 50.0 * std::sqrt(2.0), 1e-9);  // Z: 50 mm/s
  EXPECT_EQ(steep.samples[mid].binding, FeedLimit::kAxisVelocity);
}

TEST(NurbsSchedule, CentripetalLimitOnASmallCircle) {
  const NurbsLimits lim = desktop_limits(100.0);
  const double r = 1.0;
  const FeedSchedule fs = plan_nurbs_feed(full_circle(r), lim);
  expect_accel_consistent(fs);
  // Per axis: v^2 kappa |n_i| <= share A_i; the worst point has |n_i| = 1: v = sqrt(share * 2000 * r).
  const double share = lim.normal_accel_share;
  const double worst = std::sqrt(share * 2000.0 * r);
  double lowest_mid = 1e9;
  for (const FeedSample& f : fs.samples) {
    if (f.s > 0.3 * fs.length_mm && f.s < 0.7 * fs.length_mm) lowest_mid = std::min(lowest_mid, f.limit);
    if (f.binding == FeedLimit::kCentripetal) {
      // At an axis-aligned normal the limit is exactly the worst one.
      const double angle = f.s / r;
      const double n_max = std::max(std::fabs(std::cos(angle)), std::fabs(std::sin(angle)));
      EXPECT_NEAR(f.limit, std::sqrt(share * 2000.0 * r / n_max), 1e-6);
    }
  }
  EXPECT_NEAR(lowest_mid, worst, 1e-6);
}

TEST(NurbsSchedule, ChordErrorLimitMatchesItsFormula) {
  NurbsLimits lim = desktop_limits(100.0);
  lim.chord_tolerance_mm = 1e-6;  // 1 nm: the chord error binds before anything else
  const double r = 5.0;
  const FeedSchedule fs = plan_nurbs_feed(full_circle(r), lim);
  const double d = lim.chord_tolerance_mm;
  const double want = 2.0 / lim.period_s * std::sqrt(2.0 * r * d - d * d);
  int binding = 0;
  for (const FeedSample& f : fs.samples) {
    if (f.binding == FeedLimit::kChord) {
      ++binding;
      EXPECT_NEAR(f.limit, want, 1e-9 * want);
    }
  }
  EXPECT_EQ(binding, static_cast<int>(fs.samples.size()));
}

TEST(NurbsSchedule, BlockScheduleNeverExceedsTheDenseOne) {
  const NurbsLimits lim = desktop_limits(80.0);
  const NurbsCurve c = random_scheduled_curve(30, 3, 3);
  const FeedSchedule fs = plan_nurbs_feed(c, lim);
  ASSERT_GT(fs.samples.size(), static_cast<std::size_t>(kMaxFeedSchedule));
  Block b;
  fill_block_schedule(fs, c.u_min(), c.u_max(), b.nurbs);
  const NurbsGeometry& g = b.nurbs;
  ASSERT_EQ(g.schedule_count, kMaxFeedSchedule);
  EXPECT_EQ(g.schedule_u[0], c.u_min());
  EXPECT_EQ(g.schedule_u[kMaxFeedSchedule - 1], c.u_max());
  for (int k = 1; k < g.schedule_count; ++k) EXPECT_LT(g.schedule_u[k - 1], g.schedule_u[k]);
  // Linear interpolation of the block schedule is below the dense schedule at every sample.
  int i = 0;
  for (const FeedSample& f : fs.samples) {
    while (i + 2 < g.schedule_count && f.u > g.schedule_u[i + 1]) ++i;
    const double t = (f.u - g.schedule_u[i]) / (g.schedule_u[i + 1] - g.schedule_u[i]);
    const double v = g.schedule_speed[i] + t * (g.schedule_speed[i + 1] - g.schedule_speed[i]);
    EXPECT_LE(v, f.speed + 1e-9) << "u=" << f.u;
  }
  // And it is not needlessly low (this wiggly 30-point curve has far more speed features than
  // 64 points can follow; 0.867 measured with one acceleration for the whole curve, 0.803 since
  // each sample has its own: the dense schedule is then faster, and each kept point carries the
  // smallest acceleration of the stretch it stands for).
  double dense = 0.0, coarse = 0.0;
  for (int k = 0; k < g.schedule_count; ++k) {
    dense += schedule_speed_at(fs, g.schedule_u[k]);
    coarse += g.schedule_speed[k];
  }
  std::printf("block schedule / dense schedule at the kept points: %.3f\n", coarse / dense);
  EXPECT_GT(coarse, 0.78 * dense);
  // A short part fits as it is.
  Block small;
  fill_block_schedule(fs, c.knots[3], c.knots[4], small.nurbs);
  EXPECT_EQ(small.nurbs.schedule_count, lim.samples_per_span + 1);
  EXPECT_EQ(small.nurbs.schedule_u[0], c.knots[3]);
}

TEST(NurbsSchedule, MoveBecomesChainedBlocks) {
  const NurbsLimits lim = desktop_limits(60.0);
  const NurbsCurve c = random_scheduled_curve(100, 3, 9);
  const NurbsBlocks nb = plan_nurbs_blocks(c, lim);
  ASSERT_EQ(nb.error, "");
  ASSERT_GE(nb.blocks.size(), 4u);
  double total = 0.0;
  for (std::size_t i = 0; i < nb.blocks.size(); ++i) {
    const Block& b = nb.blocks[i];
    EXPECT_EQ(b.kind, BlockKind::kNurbs);
    EXPECT_LE(b.nurbs.point_count, kMaxNurbsPoints);
    EXPECT_GE(b.nurbs.schedule_count, 2);
    EXPECT_LE(b.nurbs.schedule_count, kMaxFeedSchedule);
    EXPECT_EQ(b.motion_class, MotionClass::kSpace);
    EXPECT_GT(b.speed, 0.0);
    EXPECT_LE(b.speed, 60.0);
    // the block brakes at the smallest acceleration of its schedule, never below the curve's
    double amin = 1e300;
    for (int k = 0; k < b.nurbs.schedule_count; ++k) amin = std::min(amin, b.nurbs.schedule_accel[k]);
    EXPECT_EQ(b.accel, amin);
    EXPECT_GE(b.accel, nb.schedule.accel_mm_s2);
    EXPECT_NEAR(norm(b.start - nurbs_point(view_of(b.nurbs), b.nurbs.knots[0])), 0.0, 1e-12);
    total += b.length;
    if (i + 1 < nb.blocks.size()) {
      const Block& next = nb.blocks[i + 1];
      EXPECT_NEAR(norm(b.end - next.start), 0.0, 1e-9);
      EXPECT_NEAR(dot(b.dir_end, next.dir_start), 1.0, 1e-9);  // tangent continuous join
      EXPECT_FALSE(nb.corner_after[i]);
      // The joint speed is the same on both sides (both taken from the dense schedule).
      EXPECT_GT(b.nurbs.schedule_speed[b.nurbs.schedule_count - 1], 0.0);
    }
  }
  EXPECT_NEAR(total, nb.schedule.length_mm, 1e-6);
  EXPECT_EQ(nb.blocks.front().start, c.points.front());
  EXPECT_EQ(nb.blocks.back().end, c.points.back());
  // No start ramp in the block schedules (the rt ramps), only geometric limits.
  EXPECT_GT(nb.blocks.front().nurbs.schedule_speed[0], 0.0);

  NurbsCurve bad = c;
  bad.weights[7] = -1.0;
  const NurbsBlocks rejected = plan_nurbs_blocks(bad, lim);
  EXPECT_NE(rejected.error.find("weight of control point 8"), std::string::npos);
  EXPECT_TRUE(rejected.blocks.empty());
}

TEST(NurbsSchedule, CornerStopsTheSchedule) {
  NurbsCurve kink;
  kink.degree = 2;
  kink.points = {{0, 0, 0}, {5, 0, 0}, {10, 0, 0}, {10, 5, 0}, {10, 10, 0}};
  kink.weights = {1, 1, 1, 1, 1};
  kink.knots = {0, 0, 0, 1, 1, 2, 2, 2};
  const NurbsBlocks nb = plan_nurbs_blocks(kink, desktop_limits(50.0));
  ASSERT_EQ(nb.error, "");
  ASSERT_EQ(nb.blocks.size(), 2u);
  EXPECT_TRUE(nb.corner_after[0]);
  EXPECT_EQ(nb.blocks[0].nurbs.schedule_speed[nb.blocks[0].nurbs.schedule_count - 1], 0.0);
  EXPECT_EQ(nb.blocks[1].nurbs.schedule_speed[0], 0.0);
  EXPECT_EQ(nb.blocks[0].motion_class, MotionClass::kSingleAxis);
  EXPECT_NEAR(dot(nb.blocks[0].dir_end, nb.blocks[1].dir_start), 0.0, 1e-12);
}

// A hairpin in a plane turned 30 degrees about Z and tilted a little into Z: at every sample
// the schedule's tangential acceleration plus the normal part at its speed stays within every
// axis's limit (t and k by finite differences here), and it uses what the axes leave: on the
// straights the whole margin-reduced axis limit goes to the ramps, in the bend the normal part
// takes more than the half the old fixed split allowed.
TEST(NurbsSchedule, TangentialAccelerationIsWhatTheAxesLeaveAtEachSample) {
  const NurbsLimits lim = desktop_limits(100.0);
  const double c30 = std::cos(0.5236), s30 = std::sin(0.5236);
  std::vector<Vec3> pts;
  for (const auto& q : std::vector<std::array<double, 2>>{{0, 0}, {3, 0}, {6, 0}, {8, 0}, {9.5, 0.5}, {9.5, 1.5}, {8, 2}, {6, 2}, {3, 2}, {0, 2}}) {
    pts.push_back({c30 * q[0] - s30 * q[1], s30 * q[0] + c30 * q[1], 0.05 * q[0]});
  }
  const NurbsCurve c = make_nurbs(pts, std::vector<double>(pts.size(), 1.0), 4, KnotRule::kChordLength);
  const FeedSchedule fs = plan_nurbs_feed(c, lim);
  expect_accel_consistent(fs);
  const NurbsView view = c.view();
  double worst = 0.0, most_normal = 0.0, straight_accel = 0.0;
  for (const FeedSample& f : fs.samples) {
    const double r = worst_axis_ratio(view, f.u, f.speed, f.accel, lim);
    worst = std::max(worst, r);
    EXPECT_LE(r, 1.0 + 1e-4) << "u=" << f.u;
    EXPECT_GE(r, kTangentialAccelMargin - 1e-4) << "u=" << f.u << ": the acceleration the axes leave is used";
    Vec3 t, k;
    frame_by_differences(view, f.u, t, k);
    for (std::size_t i = 0; i < 3; ++i) most_normal = std::max(most_normal, std::fabs(k[i]) * f.speed * f.speed / 2000.0);
    if (norm(k) < 1e-6) straight_accel = std::max(straight_accel, f.accel);
  }
  // straight: the margin (0.95) * min_i A_i / |t_i| along the first leg's direction
  const Vec3 t0 = normalized(pts[1] - pts[0]);
  EXPECT_NEAR(straight_accel, kTangentialAccelMargin * 2000.0 / std::max(std::fabs(t0[0]), std::fabs(t0[1])), 1e-3);
  EXPECT_GT(most_normal, 0.6) << "the bend gives the centripetal part more than half an axis";
  EXPECT_LE(most_normal, lim.normal_accel_share + 1e-4);
  std::printf("hairpin: worst axis load %.4f of its limit, largest centripetal share %.3f\n", worst, most_normal);
}

// Every point of every block schedule, and the rt's reading of the schedule between them
// (speed linear in u, the smaller acceleration of the two points around u) at every dense
// sample, keeps each axis within its velocity and acceleration limits.
TEST(NurbsSchedule, BlockSchedulesKeepEveryAxisWithinItsLimits) {
  const NurbsLimits lim = desktop_limits(80.0);
  const NurbsCurve c = random_scheduled_curve(60, 3, 5);
  const NurbsBlocks nb = plan_nurbs_blocks(c, lim);
  ASSERT_EQ(nb.error, "");
  double worst = 0.0;
  std::size_t dense_checked = 0;
  for (const Block& b : nb.blocks) {
    const NurbsGeometry& g = b.nurbs;
    const NurbsView view = view_of(g);
    for (int j = 0; j < g.schedule_count; ++j) {
      EXPECT_GT(g.schedule_accel[j], 0.0);
      worst = std::max(worst, worst_axis_ratio(view, g.schedule_u[j], g.schedule_speed[j], g.schedule_accel[j], lim));
    }
    int i = 0;
    for (const FeedSample& f : nb.schedule.samples) {
      if (f.u < g.schedule_u[0] || f.u > g.schedule_u[g.schedule_count - 1]) continue;
      while (i + 2 < g.schedule_count && f.u > g.schedule_u[i + 1]) ++i;
      const double w = (f.u - g.schedule_u[i]) / (g.schedule_u[i + 1] - g.schedule_u[i]);
      const double v = g.schedule_speed[i] + w * (g.schedule_speed[i + 1] - g.schedule_speed[i]);
      const double a = std::min(g.schedule_accel[i], g.schedule_accel[i + 1]);
      worst = std::max(worst, worst_axis_ratio(view, f.u, v, a, lim));
      Vec3 t, k;
      frame_by_differences(view, f.u, t, k);
      for (std::size_t ax = 0; ax < 3; ++ax) EXPECT_LE(std::fabs(t[ax]) * v, lim.axis_velocity_mm_s[ax] * (1 + 1e-6));
      ++dense_checked;
    }
  }
  EXPECT_GT(dense_checked, 1000u);
  EXPECT_LE(worst, 1.0 + 1e-4);
  std::printf("random 60-point curve: %zu blocks, worst axis load %.4f of its limit\n", nb.blocks.size(), worst);
}

// A quadratic is only C1 at its knots: the curvature jumps there, and a block ending at a knot
// is evaluated from the left while the dense sample there sits on the right. Every block of
// long wavy rational quadratic and cubic curves (bench_nurbs_gcode's program, where a 10,000-
// point quadratic was refused at block 22) passes the rt's block check, which evaluates each
// block's own curve at its schedule points.
TEST(NurbsSchedule, EveryBlockPassesTheRtsCheckAlsoWhereTheCurvatureJumps) {
  const MachineConfig cfg = load_config(test::default_config());
  for (int degree : {2, 3}) {
    std::vector<Vec3> pts;
    std::vector<double> w;
    const int n = 3000;
    for (int i = 0; i < n; ++i) {
      pts.push_back({2.5 + 20.0 * i / (n - 1), 12.5 + 4.0 * std::sin(0.7 * i) * std::cos(0.13 * i), 20.0});
      w.push_back(1.0 + 0.3 * std::sin(1.3 * i));
    }
    const NurbsCurve c = make_nurbs(pts, w, degree + 1);
    const NurbsBlocks nb = plan_nurbs_blocks(c, nurbs_limits(cfg, 20.0));
    ASSERT_EQ(nb.error, "");
    ASSERT_GT(nb.blocks.size(), 10u);
    Vec3 at = nb.blocks.front().start;
    std::uint64_t seq = 1;
    int refused = 0;
    for (Block b : nb.blocks) {
      b.seq = seq;
      const BlockVerdict v = check_block(b, at, seq, cfg);
      if (v.fault != FaultCode::kNone && refused++ < 3) {
        ADD_FAILURE() << "degree " << degree << ", block " << seq << ": " << v.reason << " (axis " << int(v.axis)
                      << ", value " << v.value << ")";
      }
      at = b.end;
      ++seq;
    }
    EXPECT_EQ(refused, 0) << "degree " << degree << " of " << nb.blocks.size() << " blocks";
  }
}

}  // namespace
}  // namespace pcnc
