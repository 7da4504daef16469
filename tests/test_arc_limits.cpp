// test_arc_limits.cpp — how an arc shares its plane axes' acceleration (shared/geometry/
// arc_limits.hpp): an arc's plane holds the least and most share of the radius direction each
// axis sees over the sweep (against a dense sampling); the centripetal limit along the sweep is never below the whole plane's rule
// and is that rule on a sweep through both axes' normals; the tangential acceleration it leaves
// keeps every plane axis within its own limit at every angle of the sweep, for any centripetal
// part up to the cap's share, and is never below the whole plane's rule where that one holds.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

#include "geometry/arc_limits.hpp"

using namespace pcnc;

namespace {

// A random arc's plane: limits 500-2500 mm/s², any start, sweeps up to ±0.75 rad, and every
// `long_every`-th one up to two turns.
struct RandomArc {
  double a1, a2, start, sweep;
};
RandomArc random_arc(std::mt19937_64& rng, int n, int long_every) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  RandomArc r{};
  r.a1 = 500.0 + 2000.0 * unit(rng);
  r.a2 = 500.0 + 2000.0 * unit(rng);
  r.start = 2.0 * std::numbers::pi * (unit(rng) - 0.5);
  r.sweep = (unit(rng) - 0.5) * (n % long_every == 0 ? 4.0 * std::numbers::pi : 1.5);
  return r;
}

}  // namespace

TEST(ArcLimits, CentripetalLimitAlongTheSweepIsAtLeastThePlanesAndThePlanesOverAHalfTurn) {
  std::mt19937_64 rng(5);
  int above = 0;
  for (int n = 0; n < 5000; ++n) {
    const auto [a1, a2, start, sweep] = random_arc(rng, n, 4);
    const ArcPlane p = arc_plane(a1, a2, start, sweep);
    const double lim = arc_centripetal_limit(p);
    ASSERT_GE(lim, std::min(a1, a2) * (1.0 - 1e-12));
    // the radius direction's share of each axis, sampled: within the plane's ranges, which the
    // samples reach, and the centripetal part at `lim` keeps both axes
    double c_lo = 1.0, c_hi = 0.0, s_lo = 1.0, s_hi = 0.0;
    for (int i = 0; i <= 4000; ++i) {
      const double th = start + sweep * i / 4000.0, c = std::abs(std::cos(th)), s = std::abs(std::sin(th));
      c_lo = std::min(c_lo, c), c_hi = std::max(c_hi, c), s_lo = std::min(s_lo, s), s_hi = std::max(s_hi, s);
      ASSERT_LE(lim * c, a1 * (1.0 + 1e-9)) << n;
      ASSERT_LE(lim * s, a2 * (1.0 + 1e-9)) << n;
    }
    ASSERT_LE(p.n1_lo, c_lo + 1e-12) << n;
    ASSERT_GE(p.n1_hi, c_hi - 1e-12) << n;
    ASSERT_LE(p.n2_lo, s_lo + 1e-12) << n;
    ASSERT_GE(p.n2_hi, s_hi - 1e-12) << n;
    ASSERT_NEAR(p.n1_lo, c_lo, 2e-3) << n;  // 4000 samples come within a few thousandths
    ASSERT_NEAR(p.n1_hi, c_hi, 2e-3) << n;
    ASSERT_NEAR(p.n2_lo, s_lo, 2e-3) << n;
    ASSERT_NEAR(p.n2_hi, s_hi, 2e-3) << n;
    if (std::abs(sweep) >= std::numbers::pi) {
      EXPECT_NEAR(lim, std::min(a1, a2), 1e-9 * lim);  // both axes' normals lie on the sweep
    }
    above += lim > 1.05 * std::min(a1, a2);
  }
  EXPECT_GT(above, 1000);  // short sweeps away from the slower axis gain
}

TEST(ArcLimits, TangentialAccelerationKeepsEveryAxisWithinItsLimitAtEveryAngle) {
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int by_axis = 0;
  for (int n = 0; n < 3000; ++n) {
    const auto [a1, a2, start, sweep] = random_arc(rng, n, 3);
    const ArcPlane p = arc_plane(a1, a2, start, sweep);
    const double an = kArcCentripetalShare * arc_centripetal_limit(p) * unit(rng);
    const double at = arc_plane_tangential_accel(p, an);
    ASSERT_GT(at, 0.0) << n;
    const double a_plane = std::min(a1, a2);
    if (an < a_plane) {
      ASSERT_GE(at, std::sqrt(a_plane * a_plane - an * an) * (1.0 - 1e-12)) << n;  // the plane's rule at least
    }
    by_axis += an < a_plane && at > 1.01 * std::sqrt(a_plane * a_plane - an * an);
    for (int i = 0; i <= 400; ++i) {
      const double th = start + sweep * i / 400.0;
      // in-plane acceleration: a_t along the tangent (−sin, cos) (either sense) plus an toward the centre
      for (const double sense : {1.0, -1.0}) {
        const double x = -sense * at * std::sin(th) - an * std::cos(th);
        const double y = sense * at * std::cos(th) - an * std::sin(th);
        ASSERT_LE(std::abs(x), a1 * (1.0 + 1e-9)) << "n " << n << " at " << th;
        ASSERT_LE(std::abs(y), a2 * (1.0 + 1e-9)) << "n " << n << " at " << th;
      }
    }
  }
  EXPECT_GT(by_axis, 300);  // each axis's own share gives more than the plane's rule often
}
