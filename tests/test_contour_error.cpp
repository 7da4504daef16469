// test_contour_error.cpp — distance_to_path against closed-form distances to lines, arcs
// and helices, from points off the path in every direction and from poor starting guesses.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "config/config.hpp"
#include "motion/contour_error.hpp"
#include "test_paths.hpp"

namespace pcnc {
namespace {

Block line_block(Vec3 a, Vec3 b) {
  Block blk;
  blk.kind = BlockKind::kLine;
  blk.start = a;
  blk.end = b;
  blk.length = norm(b - a);
  blk.speed = 10.0;
  blk.accel = 100.0;
  blk.dir_start = blk.dir_end = normalized(b - a);
  return blk;
}

// Counter-clockwise XY arc around c, radius r, from angle a0 over sweep, rising by dz.
Block arc_block(Vec3 c, double r, double a0, double sweep, double dz) {
  Block blk;
  blk.kind = BlockKind::kArc;
  blk.start = {c[0] + r * std::cos(a0), c[1] + r * std::sin(a0), c[2]};
  blk.end = {c[0] + r * std::cos(a0 + sweep), c[1] + r * std::sin(a0 + sweep), c[2] + dz};
  blk.length = std::hypot(r * std::abs(sweep), dz);
  blk.speed = 10.0;
  blk.accel = 100.0;
  blk.arc.center = c;
  blk.arc.radius = r;
  blk.arc.start_angle = a0;
  blk.arc.sweep = sweep;
  blk.arc.helix = dz;
  blk.arc.normal_axis = 2;
  const double s = sweep > 0 ? 1.0 : -1.0;
  blk.dir_start = normalized(Vec3{-std::sin(a0) * s * r * std::abs(sweep), std::cos(a0) * s * r * std::abs(sweep), dz});
  blk.dir_end = normalized(
      Vec3{-std::sin(a0 + sweep) * s * r * std::abs(sweep), std::cos(a0 + sweep) * s * r * std::abs(sweep), dz});
  return blk;
}

TEST(ContourError, LineDistanceIsThePerpendicularOrTheNearestEnd) {
  const MachineConfig cfg = load_config(test::default_config());
  const PreparedBlock b = prepare_block(line_block({1, 1, 1}, {11, 1, 1}), cfg);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> off(-0.05, 0.05), along(-2.0, 12.0);
  for (int i = 0; i < 500; ++i) {
    const Vec3 p{along(rng), 1.0 + off(rng), 1.0 + off(rng)};
    const double x = std::clamp(p[0], 1.0, 11.0);
    const double expected = norm(p - Vec3{x, 1.0, 1.0});
    for (double guess : {0.0, 5.0, 10.0}) {
      EXPECT_NEAR(distance_to_path(b, p, guess).distance, expected, 1e-9) << "point " << p[0] << " guess " << guess;
    }
  }
}

TEST(ContourError, ArcDistanceIsTheRadialErrorInsideTheSweep) {
  const MachineConfig cfg = load_config(test::default_config());
  const Vec3 c{12.5, 12.5, 5.0};
  const PreparedBlock b = prepare_block(arc_block(c, 5.0, 0.0, std::numbers::pi, 0.0), cfg);  // upper half circle
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> ang(0.05, std::numbers::pi - 0.05), dr(-0.01, 0.01);
  for (int i = 0; i < 500; ++i) {
    const double a = ang(rng), e = dr(rng);
    const Vec3 p{c[0] + (5.0 + e) * std::cos(a), c[1] + (5.0 + e) * std::sin(a), c[2]};
    // guess from a setpoint somewhat ahead on the path, as the machine lags behind
    const double guess = std::min(b.length, 5.0 * a + 0.3);
    const PathDistance d = distance_to_path(b, p, guess);
    EXPECT_NEAR(d.distance, std::abs(e), 1e-9);
    EXPECT_NEAR(d.s, 5.0 * a, 1e-6);
  }
  // below the start of the half circle the nearest point is the start point
  const Vec3 below{c[0] + 5.0, c[1] - 1.0, c[2]};
  EXPECT_NEAR(distance_to_path(b, below, 3.0).distance, 1.0, 1e-9);
}

// Planar arcs take the closed form: clockwise and counter-clockwise, short and almost full
// sweeps, true circles and the slight spirals of CAM arcs (end radius 3 µm off), points
// inside and outside the circle, off the plane, and beyond the ends, against a dense
// search along the curve.
TEST(ContourError, PlanarArcDistanceMatchesADenseSearch) {
  const MachineConfig cfg = load_config(test::default_config());
  const Vec3 c{12.5, 12.5, 5.0};
  std::mt19937 rng(21);
  std::uniform_real_distribution<double> frac(0.0, 1.0), off(-0.5, 0.5);
  for (const double sweep : {0.3, -0.3, 2.0, -2.0, 4.5, -4.5, 6.2, -6.2})
  for (const double end_dr : {0.0, 0.003}) {
    Block blk = arc_block(c, 4.0, 1.1, sweep, 0.0);
    blk.end = {c[0] + (4.0 + end_dr) * std::cos(1.1 + sweep), c[1] + (4.0 + end_dr) * std::sin(1.1 + sweep), c[2]};
    const PreparedBlock b = prepare_block(blk, cfg);
    for (int i = 0; i < 60; ++i) {
      // anywhere around the circle, also beyond the sweep, within half a millimetre of it
      const double a = 1.1 + frac(rng) * 2.0 * std::numbers::pi;
      const double r = 4.0 + off(rng);
      const Vec3 p{c[0] + r * std::cos(a), c[1] + r * std::sin(a), c[2] + 0.2 * off(rng)};
      double best = 1e9, best_s = 0.0;
      for (int k = 0; k <= 20000; ++k) {
        const double s = b.length * k / 20000.0;
        const double d = norm(evaluate(b, s).p - p);
        if (d < best) {
          best = d;
          best_s = s;
        }
      }
      const PathDistance d = distance_to_path(b, p, frac(rng) * b.length);
      // never farther than any sampled point (on a spiral, the radial ray is off by
      // k²·|ρ − r|/(2ρr), k = dr/dθ: here under 1e-5·distance), and no nearer than the
      // sampling step allows
      EXPECT_LE(d.distance, best + 1e-12 + 1e-5 * best) << "sweep " << sweep << " angle " << a;
      EXPECT_GT(d.distance, best - 1e-5) << "sweep " << sweep << " angle " << a;
      EXPECT_NEAR(norm(evaluate(b, d.s).p - p), d.distance, 1e-9) << "s must name the nearest point";
      if (best > 1e-3) {
        EXPECT_NEAR(d.s, best_s, 2e-3 * b.length) << "sweep " << sweep;
      }
    }
  }
}

TEST(ContourError, HelixDistanceMatchesADenseSearch) {
  const MachineConfig cfg = load_config(test::default_config());
  const PreparedBlock b = prepare_block(arc_block({12.5, 12.5, 5.0}, 3.0, 0.3, 2.5 * std::numbers::pi, 2.0), cfg);
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> frac(0.0, 1.0), off(-0.02, 0.02);
  for (int i = 0; i < 200; ++i) {
    const double s0 = frac(rng) * b.length;
    const Vec3 p = evaluate(b, s0).p + Vec3{off(rng), off(rng), off(rng)};
    double best = 1e9;
    for (int k = 0; k <= 200000; ++k) best = std::min(best, norm(evaluate(b, b.length * k / 200000.0).p - p));
    EXPECT_NEAR(distance_to_path(b, p, std::min(b.length, s0 + 0.2)).distance, best, 1e-6);
  }
}

}  // namespace
}  // namespace pcnc
