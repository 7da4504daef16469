// test_sphere_fit.cpp — the least-squares sphere and plane (geometry/sphere_fit): exact points
// give the sphere back, seeded noise gives it within the statistical error of least squares
// (σ·sqrt(3/n) per centre coordinate, σ/sqrt(n) for the radius, on a full sphere), residuals
// are the geometric distances, degenerate sets are refused.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "geometry/sphere_fit.hpp"

namespace pcnc {
namespace {

// A point on the unit sphere from two uniforms (area-uniform).
Vec3 unit_from(double u1, double u2) {
  const double z = 2.0 * u1 - 1.0, phi = 2.0 * std::numbers::pi * u2;
  const double s = std::sqrt(1.0 - z * z);
  return {s * std::cos(phi), s * std::sin(phi), z};
}

TEST(SphereFit, ExactPointsOnAHemisphereGiveTheSphere) {
  const Vec3 c{12.5, 7.0, -3.25};
  const double r = 6.35;
  std::vector<Vec3> pts;
  for (int k = 0; k < 5; ++k)      // polar 0..72°: only the upper cap is probed
    for (int i = 0; i < 8; ++i) {
      const double th = k * 0.3, ps = i * std::numbers::pi / 4;
      pts.push_back(c + r * Vec3{std::sin(th) * std::cos(ps), std::sin(th) * std::sin(ps), std::cos(th)});
    }
  const SphereFit f = fit_sphere(pts);
  ASSERT_TRUE(f.ok()) << f.error;
  EXPECT_NEAR(f.centre[0], c[0], 1e-9);
  EXPECT_NEAR(f.centre[1], c[1], 1e-9);
  EXPECT_NEAR(f.centre[2], c[2], 1e-9);
  EXPECT_NEAR(f.radius, r, 1e-9);
  EXPECT_LT(f.max_abs, 1e-9);
}

TEST(SphereFit, NoisyPointsWithinTheLeastSquaresError) {
  const Vec3 c{3.0, -2.0, 10.0};
  const double r = 12.5, sigma = 0.002;
  const int n = 400;
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  std::normal_distribution<double> noise(0.0, sigma);
  std::vector<Vec3> pts;
  for (int i = 0; i < n; ++i) {
    const double a = uni(rng), b = uni(rng);
    pts.push_back(c + (r + noise(rng)) * unit_from(a, b));
  }
  const SphereFit f = fit_sphere(pts);
  ASSERT_TRUE(f.ok()) << f.error;
  const double centre_sd = sigma * std::sqrt(3.0 / n), radius_sd = sigma / std::sqrt(static_cast<double>(n));
  for (int i = 0; i < 3; ++i) EXPECT_LT(std::abs(f.centre[static_cast<std::size_t>(i)] - c[static_cast<std::size_t>(i)]), 4.0 * centre_sd);
  EXPECT_LT(std::abs(f.radius - r), 4.0 * radius_sd);
  // the residual RMS estimates sigma (n − 4 degrees of freedom)
  EXPECT_NEAR(f.rms, sigma, 0.15 * sigma);
  // residuals are the geometric distances to the fitted sphere, in order
  ASSERT_EQ(f.residuals.size(), pts.size());
  for (std::size_t i = 0; i < pts.size(); i += 37) {
    const Vec3 d = pts[i] - f.centre;
    EXPECT_NEAR(f.residuals[i], std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) - f.radius, 1e-12);
  }
}

TEST(SphereFit, GaussNewtonLowersTheGeometricErrorOfTheAlgebraicStart) {
  // noise on a small cap biases the algebraic fit; the geometric fit's sum of squares must be
  // no larger than that of any nearby sphere (a local minimum): probe ±1 µm in each parameter
  std::mt19937_64 rng(7);
  std::normal_distribution<double> noise(0.0, 0.005);
  std::vector<Vec3> pts;
  for (int k = 0; k < 30; ++k) {
    const double th = 0.5 * k / 29.0, ps = 2.4 * k;
    pts.push_back((5.0 + noise(rng)) * Vec3{std::sin(th) * std::cos(ps), std::sin(th) * std::sin(ps), std::cos(th)});
  }
  const SphereFit f = fit_sphere(pts);
  ASSERT_TRUE(f.ok()) << f.error;
  auto ss = [&](const Vec3& c, double r) {
    double s = 0.0;
    for (const Vec3& p : pts) s += std::pow(norm(p - c) - r, 2);
    return s;
  };
  const double best = ss(f.centre, f.radius);
  for (int i = 0; i < 4; ++i)
    for (double h : {-1e-3, 1e-3}) {
      Vec3 c = f.centre;
      double r = f.radius;
      if (i < 3) c[static_cast<std::size_t>(i)] += h; else r += h;
      EXPECT_GE(ss(c, r), best);
    }
}

TEST(SphereFit, RefusesTooFewOrCoplanarPoints) {
  EXPECT_FALSE(fit_sphere({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}).ok());
  std::vector<Vec3> flat;
  for (int i = 0; i < 10; ++i) flat.push_back({std::cos(i * 0.6), std::sin(i * 0.6), 2.0});
  const SphereFit f = fit_sphere(flat);
  EXPECT_FALSE(f.ok());
  EXPECT_NE(f.error.find("plane"), std::string::npos);
}

TEST(PlaneFit, RecoversATiltedPlaneAndItsResiduals) {
  // z = 1 + 0.3x − 0.2y: normal (−0.3, 0.2, 1)/|.|
  std::mt19937_64 rng(3);
  std::normal_distribution<double> noise(0.0, 1e-4);
  std::vector<Vec3> pts;
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 5; ++j) pts.push_back({i * 2.0, j * 3.0, 1.0 + 0.3 * i * 2.0 - 0.2 * j * 3.0 + noise(rng)});
  const PlaneFit p = fit_plane(pts);
  ASSERT_TRUE(p.ok()) << p.error;
  const Vec3 n = normalized(Vec3{-0.3, 0.2, 1.0});
  EXPECT_GT(dot(p.normal, n), std::cos(1e-4));
  EXPECT_NEAR(p.rms, 1e-4 * std::sqrt(1.0 / (1.0 + 0.13)), 3e-5);  // vertical noise seen along n
  for (std::size_t i = 0; i < pts.size(); ++i) EXPECT_NEAR(p.residuals[i], dot(pts[i] - p.point, p.normal), 1e-15);
  EXPECT_FALSE(fit_plane({{0, 0, 0}, {1, 1, 1}, {2, 2, 2}, {3, 3, 3}}).ok());
}

}  // namespace
}  // namespace pcnc
