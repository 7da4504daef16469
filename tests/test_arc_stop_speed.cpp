// test_arc_stop_speed.cpp — the arc's stop rule (rt/motion/path.hpp arc_stop_speed) finds the
// largest speed its rule allows by regula falsi (Illinois) in a few evaluations: its answer must
// be safe (the rule at that speed allows it) and the plain 24-step bisection's to 1e-7 of the
// cap, on every kind of arc (flat ones in each plane, helices, tight and wide radii, spirals) and
// every kind of question (far from the end and at its last cycles, exits above and below the
// rule's turning point k·dt·v_exit = distance, the exact rule and the one with the margin, finite
// and infinite caps).
// The acceleration it counts on over the rest of the arc, each axis carrying its own share
// (arc_sweep_accel), must be at most what the per-axis rule the executor brakes by gives at
// every point of that rest (a lower bound, spirals and helices included), and on circles the
// least of it (no slack), larger than the plane rule where the rest runs along the faster axis.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "gcode/preprocessor.hpp"
#include "machine_runner.hpp"
#include "motion/junction.hpp"
#include "geometry/arc_limits.hpp"
#include "motion/path.hpp"

using namespace pcnc;

namespace {

// The bisection as it ran before: every mid evaluated.
double plain_arc_stop_speed(const PreparedBlock& b, const MachineConfig& c, double distance, double v_exit, bool exact,
                            double cap, double dt, double k) {
  const ArcSweep sweep = arc_sweep(b, c, b.length - distance);
  auto rule = [&](double v) { return arc_stop_rule(b, sweep, distance, v_exit, exact, dt, k, v); };
  if (!std::isfinite(cap)) cap = b.v_machine;
  if (rule(cap) >= cap) return cap;
  double lo = 0.0, hi = cap;
  for (int i = 0; i < 24; ++i) {
    const double mid = 0.5 * (lo + hi);
    (rule(mid) >= mid ? lo : hi) = mid;
  }
  return lo;
}

PreparedBlock arc(const MachineConfig& c, double r, double sweep, int normal, double rise, double r_end, double feed) {
  const Vec3 center{12.5, 12.5, 12.5};
  const std::array<int, 2> ax = normal == 2 ? std::array<int, 2>{0, 1} : normal == 1 ? std::array<int, 2>{2, 0}
                                                                                      : std::array<int, 2>{1, 2};
  Move m;
  m.kind = MoveKind::kArc;
  m.start = center;
  m.start[ax[0]] += r;
  m.end = center;
  m.end[ax[0]] += r_end * std::cos(sweep);
  m.end[ax[1]] += r_end * std::sin(sweep);
  m.end[normal] += rise;
  m.center = center;
  m.radius = r;
  m.sweep = sweep;
  m.normal_axis = normal;
  m.feed_mm_s = feed;
  return prepare_block(make_block(m, c), c);
}

}  // namespace

TEST(ArcStopSpeed, TheRootIsSafeAndThePlainBisectionsTo1e7OfTheCap) {
  const MachineConfig c = test::default_machine_config();
  const double dt = c.cycle_period_s();
  std::mt19937_64 rng(29);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int asked = 0, binding = 0, falling = 0;
  for (int n = 0; n < 300; ++n) {
    const double r = std::exp(std::log(0.05) + unit(rng) * std::log(400.0));  // 0.05 .. 20 mm
    const double sweep = (unit(rng) < 0.5 ? -1.0 : 1.0) * (0.05 + unit(rng) * 2.0 * std::numbers::pi);
    const int normal = n % 3;
    const double rise = n % 4 == 0 ? (unit(rng) - 0.5) * 2.0 : 0.0;                 // helices
    const double r_end = n % 5 == 0 ? r * (1.0 + 0.01 * (unit(rng) - 0.5)) : r;     // spirals
    const PreparedBlock b = arc(c, r, sweep, normal, rise, r_end, 5.0 + 200.0 * unit(rng));
    ASSERT_EQ(b.kind, BlockKind::kArc);
    for (int q = 0; q < 40; ++q) {
      // distances from a part of one cycle's travel to the whole block, exits up to the cap
      const double distance = q % 4 == 0 ? b.length * unit(rng) : b.v_machine * dt * 20.0 * unit(rng) * unit(rng);
      const double v_exit = q % 3 == 0 ? 0.0 : b.v_machine * unit(rng);
      const double f = q % 2 == 0 ? 0.1 : 0.5;
      const double k = 1.0 + 2.0 * f;
      const bool exact = q % 5 == 0;
      const double cap = q % 7 == 0 ? std::numeric_limits<double>::infinity() : b.v_machine * (0.2 + unit(rng));
      const double want = plain_arc_stop_speed(b, c, distance, v_exit, exact, cap, dt, k);
      const double got = arc_stop_speed(b, c, distance, v_exit, exact, cap, dt, k);
      const double top = std::isfinite(cap) ? cap : b.v_machine;
      ASSERT_NEAR(got, want, 1e-7 * top)
          << "r " << r << " sweep " << sweep << " normal " << normal << " distance " << distance << " v_exit "
          << v_exit << " exact " << exact << " cap " << cap;
      ASSERT_GE(arc_stop_rule(b, arc_sweep(b, c, b.length - distance), distance, v_exit, exact, dt, k, got), got)
          << "unsafe: r " << r << " distance " << distance;
      ++asked;
      binding += want < (std::isfinite(cap) ? cap : b.v_machine);
      falling += !exact && distance < k * dt * v_exit;
    }
  }
  // the questions reached the bisection itself, on both sides of the rule's turning point
  EXPECT_GT(binding, asked / 4);
  EXPECT_GT(falling, asked / 20);
}

TEST(ArcSweep, PlaneAxisRoomIsTheLeastOfItsRuleOverTheRange) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int n = 0; n < 2000; ++n) {
    const double limit = 500.0 + 2000.0 * unit(rng);
    const double c = limit * 1.3 * unit(rng);
    const double q = 0.3 + 0.7 * unit(rng);
    const double phi = n % 3 == 0 ? 0.0 : 0.05 * unit(rng) * unit(rng);
    double x_lo = unit(rng), x_hi = unit(rng);
    if (x_lo > x_hi) std::swap(x_lo, x_hi);
    if (n % 4 == 0) x_lo = 0.0;
    if (n % 5 == 0) x_hi = 1.0;
    const double got = plane_axis_tangential_room(limit, c, q, phi, x_lo, x_hi);
    double least = std::numeric_limits<double>::infinity();
    bool spent = false;
    for (int i = 0; i <= 20000; ++i) {
      const double x = x_lo + (x_hi - x_lo) * i / 20000.0;
      if (limit - c * x <= 0.0) spent = true;
      const double along = q * (std::sqrt(1.0 - x * x) + phi * x);
      if (along > 1e-12) least = std::min(least, (limit - c * x) / along);
    }
    if (spent) {
      EXPECT_EQ(got, 0.0) << n;
      continue;
    }
    // a lower bound of the sampled rule, and within the sampling's reach of its least value
    ASSERT_LE(got, least * (1.0 + 1e-12)) << "n " << n << " c/limit " << c / limit << " phi " << phi;
    ASSERT_GE(got, least * (1.0 - 1e-3) - 1e-9) << "n " << n << " c/limit " << c / limit << " phi " << phi;
  }
}

TEST(ArcSweep, BoundsThePerAxisRuleOnTheRestOfEveryArcAndIsTightOnCircles) {
  const MachineConfig c = test::default_machine_config();
  std::mt19937_64 rng(31);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int gained = 0, g19 = 0;
  for (int n = 0; n < 240; ++n) {
    const double r = std::exp(std::log(0.05) + unit(rng) * std::log(400.0));
    const double sweep = (unit(rng) < 0.5 ? -1.0 : 1.0) * (0.05 + unit(rng) * 2.0 * std::numbers::pi);
    const int normal = n % 3;
    const bool helix = n % 4 == 1, spiral = n % 5 == 2;
    const double rise = helix ? (unit(rng) - 0.5) * 2.0 : 0.0;
    const double r_end = spiral ? r * (1.0 + 0.01 * (unit(rng) - 0.5)) : r;
    const PreparedBlock b = arc(c, r, sweep, normal, rise, r_end, 5.0 + 200.0 * unit(rng));
    ASSERT_EQ(b.kind, BlockKind::kArc);
    const double f = b.arc_f;
    for (int q = 0; q < 6; ++q) {
      const double from = q == 0 ? 0.0 : b.length * unit(rng);
      const double v = b.v_machine * 1.1 * unit(rng);
      const ArcSweep w = arc_sweep(b, c, from);
      const double bound = arc_sweep_accel(b, w, v);
      double least = std::numeric_limits<double>::infinity();
      for (int i = 0; i <= 4000; ++i) {
        const PathPoint p = evaluate(b, from + (b.length - from) * i / 4000.0);
        least = std::min(least, f * point_tangential_accel(p.tangent, p.curvature, c, v / f));
      }
      ASSERT_LE(bound, least * (1.0 + 1e-9) + 1e-9)
          << "r " << r << " sweep " << sweep << " normal " << normal << " helix " << helix << " spiral " << spiral
          << " from " << from << " v " << v;
      if (!spiral && !helix) {
        // on a circle it is the least value itself (4000 samples reach within 0.5 % of it)
        EXPECT_GE(bound, least * 0.995 - 1e-6) << "r " << r << " sweep " << sweep << " from " << from << " v " << v;
        gained += bound > arc_path_accel(b, v) * 1.05;
        g19 += normal == 0 && bound > arc_path_accel(b, v) * 1.05;
      }
    }
  }
  // it gives more than the plane rule often, G19 arcs (Y 2000, Z 1000 mm/s²) among them
  EXPECT_GT(gained, 20);
  EXPECT_GT(g19, 5);
}
