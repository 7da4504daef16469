// test_axis_slerp.cpp — the tool-axis orientation interpolation (issue 16, item 3): unit length,
// the ends, a constant angular rate (equal angles between evenly spaced samples, measured
// independently with atan2), the midpoint equal to the normalised sum of the ends, the
// derivatives against central differences, and the degenerate cases (equal, opposite and
// nearly opposite axes).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "geometry/axis_slerp.hpp"
#include "test_constants.hpp"

namespace pcnc {
namespace {


double angle_between(const Vec3& a, const Vec3& b) { return std::atan2(norm(cross(a, b)), dot(a, b)); }

Vec3 random_unit(std::mt19937_64& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  for (;;) {
    const Vec3 v{n(rng), n(rng), n(rng)};
    if (norm(v) > 1e-3) return normalized(v);
  }
}

void expect_near(const Vec3& a, const Vec3& b, double tol) {
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(a[i], b[i], tol) << "component " << i;
}

TEST(AxisSlerp, UnitLengthEndsAndConstantAngularRate) {
  std::mt19937_64 rng(21);
  for (int i = 0; i < 2000; ++i) {
    const Vec3 a = random_unit(rng), b = random_unit(rng);
    const AxisSlerp s = make_axis_slerp(3.0 * a, 0.5 * b);  // lengths do not matter
    const double total = angle_between(a, b);
    EXPECT_NEAR(s.angle, total, 1e-12);
    expect_near(slerp_axis(s, 0.0), a, 1e-12);
    expect_near(slerp_axis(s, 1.0), b, 1e-12);
    const int n = 64;
    for (int k = 0; k <= n; ++k) {
      const Vec3 v = slerp_axis(s, static_cast<double>(k) / n);
      ASSERT_NEAR(norm(v), 1.0, 1e-14);
      // on the great circle: in the plane of a and b
      ASSERT_NEAR(dot(v, normalized(cross(a, b))), 0.0, 1e-12);
      if (k > 0) {
        const Vec3 before = slerp_axis(s, static_cast<double>(k - 1) / n);
        ASSERT_NEAR(angle_between(before, v), total / n, 1e-12) << "step " << k;
      }
      ASSERT_NEAR(norm(slerp_axis_d1(s, static_cast<double>(k) / n)), total, 1e-12);
    }
    if (total < kPi - 1e-3) expect_near(slerp_axis(s, 0.5), normalized(a + b), 1e-12);
  }
}

TEST(AxisSlerp, NotTheAnglesLinearly) {
  // From +Z to +X: halfway the axis is at 45° in the X-Z plane.
  const AxisSlerp s = make_axis_slerp({0, 0, 1}, {1, 0, 0});
  expect_near(slerp_axis(s, 0.5), {std::sqrt(0.5), 0, std::sqrt(0.5)}, 1e-15);
  expect_near(slerp_axis(s, 1.0 / 3), {0.5, 0, std::sqrt(3.0) / 2}, 1e-15);
}

TEST(AxisSlerp, DerivativesMatchCentralDifferences) {
  std::mt19937_64 rng(22);
  const double h = 1e-5;
  for (int i = 0; i < 500; ++i) {
    const AxisSlerp s = make_axis_slerp(random_unit(rng), random_unit(rng));
    for (double t : {0.0, 0.17, 0.5, 0.93, 1.0}) {
      const Vec3 fd1 = (1.0 / (2 * h)) * (slerp_axis(s, t + h) - slerp_axis(s, t - h));
      const Vec3 fd2 = (1.0 / (h * h)) * (slerp_axis(s, t + h) - 2.0 * slerp_axis(s, t) + slerp_axis(s, t - h));
      expect_near(slerp_axis_d1(s, t), fd1, 1e-8);
      expect_near(slerp_axis_d2(s, t), fd2, 1e-4);
    }
  }
}

TEST(AxisSlerp, EqualAxesStayPut) {
  const Vec3 a = normalized(Vec3{0.2, -0.3, 0.9});
  const AxisSlerp s = make_axis_slerp(a, a);
  EXPECT_EQ(s.angle, 0.0);
  for (double t : {0.0, 0.3, 1.0}) {
    expect_near(slerp_axis(s, t), a, 1e-15);
    expect_near(slerp_axis_d1(s, t), {0, 0, 0}, 0.0);
  }
}

TEST(AxisSlerp, OppositeAxesTurnThroughAFixedPerpendicular) {
  for (const Vec3& a : {Vec3{0, 0, 1}, Vec3{0, 0, -1}, normalized(Vec3{0.3, -0.5, 0.8}), Vec3{1, 0, 0}}) {
    const Vec3 b = -1.0 * a;
    const AxisSlerp s = make_axis_slerp(a, b);
    EXPECT_NEAR(s.angle, kPi, 0);
    expect_near(slerp_axis(s, 0.0), a, 1e-15);
    expect_near(slerp_axis(s, 1.0), b, 1e-15);
    const Vec3 mid = slerp_axis(s, 0.5);
    EXPECT_NEAR(dot(mid, a), 0.0, 1e-15);
    EXPECT_NEAR(norm(mid), 1.0, 1e-15);
    for (int k = 1; k <= 10; ++k)
      EXPECT_NEAR(angle_between(slerp_axis(s, (k - 1) / 10.0), slerp_axis(s, k / 10.0)), kPi / 10, 1e-12);
  }
  // +Z to −Z turns through +X (the coordinate axis least aligned with Z, X on ties)
  expect_near(slerp_axis(make_axis_slerp({0, 0, 1}, {0, 0, -1}), 0.5), {1, 0, 0}, 1e-15);
}

TEST(AxisSlerp, NearlyOppositeAxesAreStillExact) {
  const Vec3 a{0, 0, 1};
  const Vec3 b = normalized(Vec3{1e-7, 0, -1});
  const AxisSlerp s = make_axis_slerp(a, b);
  EXPECT_NEAR(s.angle, kPi - 1e-7, 1e-15);
  expect_near(slerp_axis(s, 1.0), b, 1e-15);
  expect_near(slerp_axis(s, 0.5), {1, 0, 0}, 1e-7);  // the short way round, through +X
}

}  // namespace
}  // namespace pcnc
