// test_preprocessor.cpp — the kinematic plan of one move (pure functions, no files, no process):
// projected speed and acceleration, driving axis, deceleration start, tangents, arc geometry.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstring>

#include "config/config.hpp"
#include "gcode/preprocessor.hpp"
#include "test_constants.hpp"

namespace pcnc {
namespace {


MachineConfig limits() {
  MachineConfig c;
  c.axes[0].max_velocity_mm_s = 100;
  c.axes[0].max_accel_mm_s2 = 2000;
  c.axes[1].max_velocity_mm_s = 80;
  c.axes[1].max_accel_mm_s2 = 1500;
  c.axes[2].max_velocity_mm_s = 50;
  c.axes[2].max_accel_mm_s2 = 1000;
  c.motion.rapid_speed_mm_s = 0;
  return c;
}

Move line_at_feed(Vec3 a, Vec3 b, double feed) {
  Move m;
  m.kind = MoveKind::kLine;
  m.start = a;
  m.end = b;
  m.feed_mm_s = feed;
  m.line = 4;
  return m;
}

TEST(Preprocessor, SingleAxisLine) {
  const Block b = make_block(line_at_feed({0, 0, 0}, {0, -10, 0}, 20), limits());
  EXPECT_EQ(b.kind, BlockKind::kLine);
  EXPECT_EQ(b.line, 4u);
  EXPECT_EQ(b.motion_class, MotionClass::kSingleAxis);
  EXPECT_DOUBLE_EQ(b.length, 10);
  EXPECT_DOUBLE_EQ(b.speed, 20);
  EXPECT_DOUBLE_EQ(b.accel, 1500);
  EXPECT_EQ(b.driving_axis, 1);
  EXPECT_EQ(b.driving_dir, -1);
  EXPECT_DOUBLE_EQ(b.driving_speed, 20);
  EXPECT_DOUBLE_EQ(b.driving_accel, 1500);
  // stop from 20 mm/s at 1500 mm/s^2 takes 400/3000 mm; it ends at y = -10
  EXPECT_NEAR(b.decel_start, -10 + 400.0 / 3000.0, 1e-12);
  EXPECT_DOUBLE_EQ(b.dir_start[1], -1);
  EXPECT_DOUBLE_EQ(b.dir_end[1], -1);
}

TEST(Preprocessor, FeedProjectedSoNoAxisExceedsItsLimit) {
  // 3-4-0 direction: u = (0.6, 0.8, 0). F = 1000 mm/s is far too fast.
  const Block b = make_block(line_at_feed({0, 0, 0}, {30, 40, 0}, 1000), limits());
  EXPECT_EQ(b.motion_class, MotionClass::kPlane);
  EXPECT_NEAR(b.speed, std::min(100 / 0.6, 80 / 0.8), 1e-9);  // Y limits: 100 mm/s
  EXPECT_NEAR(b.accel, std::min(2000 / 0.6, 1500 / 0.8), 1e-9);
  EXPECT_EQ(b.driving_axis, 1);
  EXPECT_NEAR(b.driving_speed, 80, 1e-9);
  EXPECT_NEAR(b.driving_accel, 1500, 1e-9);
  for (int i = 0; i < 3; ++i) {
    EXPECT_LE(b.speed * std::fabs(b.dir_start[static_cast<std::size_t>(i)]),
              limits().axes[static_cast<std::size_t>(i)].max_velocity_mm_s + 1e-9);
  }
}

TEST(Preprocessor, SpaceLineAndTriangularProfile) {
  // Short move: cannot reach 100 mm/s and stop again; deceleration starts at the midpoint.
  const Block b = make_block(line_at_feed({0, 0, 0}, {1, 1, 1}, 100), limits());
  EXPECT_EQ(b.motion_class, MotionClass::kSpace);
  const double u = 1 / std::sqrt(3.0);
  EXPECT_NEAR(b.speed, 50 / u, 1e-9);      // Z limit
  EXPECT_NEAR(b.decel_start, 0.5, 1e-12);  // X is the driving axis (first of the equal ones)
  EXPECT_EQ(b.driving_axis, 0);
}

TEST(Preprocessor, DecelStartDistance) {
  EXPECT_DOUBLE_EQ(decel_start_distance(10, 10, 100), 10 - 0.5);
  EXPECT_DOUBLE_EQ(decel_start_distance(0.5, 10, 100), 0.25);
  EXPECT_DOUBLE_EQ(decel_start_distance(10, 0, 100), 10);
}

TEST(Preprocessor, RapidUsesAxisMaximaOrTheConfiguredRapid) {
  Move m = line_at_feed({0, 0, 0}, {10, 0, 0}, 0);
  m.kind = MoveKind::kRapid;
  MachineConfig c = limits();
  EXPECT_DOUBLE_EQ(make_block(m, c).speed, 100);
  c.motion.rapid_speed_mm_s = 40;
  EXPECT_DOUBLE_EQ(make_block(m, c).speed, 40);
  EXPECT_EQ(make_block(m, c).kind, BlockKind::kRapid);
}

Move arc(Vec3 start, Vec3 end, Vec3 center, double r, double sweep, int normal, double feed) {
  Move m;
  m.kind = MoveKind::kArc;
  m.start = start;
  m.end = end;
  m.center = center;
  m.radius = r;
  m.sweep = sweep;
  m.normal_axis = normal;
  m.feed_mm_s = feed;
  return m;
}

TEST(Preprocessor, QuarterArcGeometryAndTangents) {
  const Block b = make_block(arc({10, 0, 0}, {0, 10, 0}, {0, 0, 0}, 10, kPi / 2, 2, 20), limits());
  EXPECT_EQ(b.kind, BlockKind::kArc);
  EXPECT_EQ(b.motion_class, MotionClass::kPlane);
  EXPECT_NEAR(b.length, 5 * kPi, 1e-12);
  EXPECT_NEAR(b.arc.start_angle, 0, 1e-12);
  EXPECT_NEAR(b.arc.angular_speed, 2, 1e-12);  // 20 mm/s on r = 10
  EXPECT_NEAR(b.dir_start[1], 1, 1e-12);
  EXPECT_NEAR(b.dir_end[0], -1, 1e-12);
  // tangential acceleration: what the smaller in-plane limit (1500) leaves beside the
  // centripetal v²/r at the top speed, twice the feed (the largest override): 40²/10
  EXPECT_NEAR(b.accel, std::sqrt(1500.0 * 1500.0 - 160.0 * 160.0), 1e-9);
  EXPECT_NEAR(b.arc.angular_accel, b.accel / 10, 1e-12);
  const double stop = 2.0 * 2.0 / (2 * b.arc.angular_accel);
  EXPECT_NEAR(b.arc.decel_start_angle, kPi / 2 - stop, 1e-12);
}

TEST(Preprocessor, ArcSpeedLimitedByCentripetalAcceleration) {
  // r = 1 mm at 1000 mm/s: v^2/r must stay within 0.95 of 1500 mm/s^2 -> v = sqrt(1425).
  const Block b = make_block(arc({1, 0, 0}, {-1, 0, 0}, {0, 0, 0}, 1, kPi, 2, 1000), limits());
  EXPECT_NEAR(b.speed, std::sqrt(1425.0), 1e-9);
  EXPECT_LE(b.speed * b.speed / 1.0, kArcCentripetalShare * 1500 + 1e-9);
  // at that top speed the tangential part gets what the centripetal part leaves
  EXPECT_NEAR(b.accel, std::sqrt(1 - kArcCentripetalShare * kArcCentripetalShare) * 1500, 1e-9);
}

// Arcs take kArcCentripetalShare (0.95) of the smaller plane axis's acceleration for the
// centripetal part at their top speed: at every speed the block may run at (up to twice its
// speed, the largest override, and never above the axes' cap) and at every point of the full
// circle, the in-plane acceleration a_t·T + (v²/r)·N keeps each plane axis within its own limit.
TEST(Preprocessor, ArcsAtThePlaneShareKeepEveryAxisWithinItsLimit) {
  const MachineConfig c = limits();  // X 2000, Y 1500 mm/s^2
  int at_cap = 0;
  for (double r : {0.2, 1.0, 1.09, 5.0, 50.0}) {
    for (double feed : {5.0, 20.0, 40.0, 1000.0}) {
      const Block b = make_block(arc({r, 0, 0}, {-r, 0, 0}, {0, 0, 0}, r, kPi, 2, feed), limits());
      const double cap = std::sqrt(kArcCentripetalShare * 1500.0 * r);
      EXPECT_LE(b.speed, cap * (1 + 1e-12)) << "r " << r << " F " << feed;
      if (b.speed > cap * (1 - 1e-9)) ++at_cap;
      // the block's top speed: what the axes allow (the centripetal cap, Y's 80 mm/s on a half
      // circle), at most twice its speed
      const double v_top = std::min({cap, 80.0, 2.0 * b.speed});
      for (int k = 0; k <= 20; ++k) {
        const double v = v_top * k / 20.0;
        const double an = v * v / r;
        for (int j = 0; j < 360; ++j) {
          const double th = j * kPi / 180.0;
          // T = (-sin, cos), N = (-cos, -sin); braking or speeding up (a_t of either sign)
          for (double sign : {1.0, -1.0}) {
            const double ax = std::fabs(-sign * b.accel * std::sin(th) - an * std::cos(th));
            const double ay = std::fabs(sign * b.accel * std::cos(th) - an * std::sin(th));
            EXPECT_LE(ax, c.axes[0].max_accel_mm_s2 * (1 + 1e-9)) << "r " << r << " F " << feed << " v " << v;
            EXPECT_LE(ay, c.axes[1].max_accel_mm_s2 * (1 + 1e-9)) << "r " << r << " F " << feed << " v " << v;
          }
        }
      }
    }
  }
  EXPECT_GE(at_cap, 5) << "some arcs run at the centripetal cap";
}

TEST(Preprocessor, ArcSpeedLimitedByTheAxisThatPeaks) {
  // A quarter arc from angle 0 to 90 deg in XY: X velocity peaks (|sin| = 1) at 90 deg, Y at 0.
  // Large radius so the centripetal bound does not bind. Y (80 mm/s) is the limit.
  const Block b = make_block(arc({1000, 0, 0}, {0, 1000, 0}, {0, 0, 0}, 1000, kPi / 2, 2, 500), limits());
  EXPECT_NEAR(b.speed, 80, 1e-9);
  // A small arc around angle 0 only: Y moves at full speed, X hardly at all -> still 80.
  // Around angle 90 deg: X moves at full speed -> 100.
  const double a = 0.1;
  const Block c =
      make_block(arc({1000 * std::cos(kPi / 2 - a), 1000 * std::sin(kPi / 2 - a), 0},
                     {1000 * std::cos(kPi / 2 + a), 1000 * std::sin(kPi / 2 + a), 0}, {0, 0, 0}, 1000, 2 * a, 2, 500),
                 limits());
  EXPECT_NEAR(c.speed, 100, 1e-9);
}

TEST(Preprocessor, HelixSpeedAlongThePath) {
  // r = 5, helix -2 over a full turn: angular speed = v / sqrt(r^2 + (h/sweep)^2).
  const double h = -2, sweep = -2 * kPi;
  const Block b = make_block(arc({5, 0, 0}, {5, 0, h}, {0, 0, 0}, 5, sweep, 2, 10), limits());
  const double rho = std::sqrt(25 + std::pow(h / sweep, 2));
  EXPECT_EQ(b.motion_class, MotionClass::kSpace);
  EXPECT_NEAR(b.length, rho * 2 * kPi, 1e-12);
  EXPECT_NEAR(b.arc.helix, h, 1e-12);
  EXPECT_NEAR(b.arc.angular_speed, 10 / rho, 1e-12);
  EXPECT_EQ(b.driving_axis, 2);
  EXPECT_EQ(b.driving_dir, -1);
  EXPECT_NEAR(b.driving_speed, 10 * std::fabs(h) / b.length, 1e-12);
  EXPECT_NEAR(norm(b.dir_start), 1, 1e-12);
  EXPECT_LT(b.dir_start[2], 0);  // going down
  EXPECT_LT(b.dir_start[1], 0);  // clockwise from angle 0: toward -Y
}

TEST(Preprocessor, ArcInG18PlaneUsesZAndX) {
  // normal Y; angles from Z toward X. Start on +Z of the center, quarter turn to +X.
  const Block b = make_block(arc({0, 0, 10}, {10, 0, 0}, {0, 0, 0}, 10, kPi / 2, 1, 10), limits());
  EXPECT_EQ(b.arc.normal_axis, 1);
  EXPECT_NEAR(b.arc.start_angle, 0, 1e-12);
  EXPECT_NEAR(b.dir_start[0], 1, 1e-12);  // moving toward +X first
  EXPECT_NEAR(b.dir_end[2], -1, 1e-12);   // then down in Z
  // in-plane axes are Z (1000) and X (2000): tangential accel from the smaller one, beside
  // the centripetal (2·10)²/10 at the top speed
  EXPECT_NEAR(b.accel, std::sqrt(1000.0 * 1000.0 - 40.0 * 40.0), 1e-9);
}

TEST(Preprocessor, MaxAbsTrigOverSweptAngles) {
  EXPECT_DOUBLE_EQ(max_abs_sin(0, kPi), 1);
  EXPECT_NEAR(max_abs_sin(0, 0.1), std::sin(0.1), 1e-15);
  EXPECT_NEAR(max_abs_sin(0.2, -0.1), std::sin(0.2), 1e-15);
  EXPECT_DOUBLE_EQ(max_abs_cos(-0.1, 0.2), 1);
  EXPECT_NEAR(max_abs_cos(1.0, 0.2), std::cos(1.0), 1e-15);
  EXPECT_DOUBLE_EQ(max_abs_cos(3.0, 0.3), 1);  // crosses pi
}

TEST(Preprocessor, DwellPauseEnd) {
  Move d;
  d.kind = MoveKind::kDwell;
  d.dwell_s = 2.5;
  d.start = d.end = {1, 2, 3};
  Block b = make_block(d, limits());
  EXPECT_EQ(b.kind, BlockKind::kDwell);
  EXPECT_DOUBLE_EQ(b.dwell_s, 2.5);
  EXPECT_DOUBLE_EQ(b.end[2], 3);
  EXPECT_DOUBLE_EQ(norm(b.dir_start), 0);
  Move p = d;
  p.kind = MoveKind::kPause;
  p.optional_stop = true;
  b = make_block(p, limits());
  EXPECT_EQ(b.kind, BlockKind::kPause);
  EXPECT_EQ(b.optional_stop, 1);
  p.kind = MoveKind::kEnd;
  EXPECT_EQ(make_block(p, limits()).kind, BlockKind::kEnd);
}

TEST(Preprocessor, InPlaceVariantSetsEveryFieldButTheNurbsArrays) {
  const Move moves[] = {line_at_feed({0, 0, 0}, {3, 4, 0}, 10), arc({10, 0, 0}, {0, 10, 1}, {0, 0, 0}, 10, kPi / 2, 2, 20)};
  for (const Move& m : moves) {
    Block dirty;
    std::memset(static_cast<void*>(&dirty), 0xAB, sizeof dirty);
    make_block_into(m, limits(), dirty);
    const Block clean = make_block(m, limits());
    EXPECT_EQ(std::memcmp(&dirty, &clean, offsetof(Block, nurbs)), 0);
    EXPECT_EQ(dirty.nurbs.point_count, 0);
    EXPECT_EQ(dirty.nurbs.knot_count, 0);
    EXPECT_EQ(dirty.nurbs.schedule_count, 0);
  }
}

TEST(Preprocessor, ContouringFlagCarried) {
  Move m = line_at_feed({0, 0, 0}, {1, 0, 0}, 10);
  m.contouring = true;
  EXPECT_EQ(make_block(m, limits()).contouring, 1);
  m.contouring = false;
  EXPECT_EQ(make_block(m, limits()).contouring, 0);
}

}  // namespace
}  // namespace pcnc
