// test_probe_calibration.cpp — r_eff(d) on a reference sphere (geometry/probe_calibration):
// touches synthesised from a lobed pre-travel (axial, lateral and three-lobed, the kinematic
// probe's pattern, written here independently of the library) are calibrated back: with the
// sphere's centre known within the piecewise-linear interpolation bound in θ (h²/8·max|f''|),
// with the centre fitted up to the constant-offset term (c_fit − c)·d the model says it cannot
// see; too few azimuths are refused.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "geometry/probe_calibration.hpp"

namespace pcnc {
namespace {

constexpr double kBall = 1.0, kSphere = 6.0;
constexpr double kAxial = 0.010, kLateral = 0.020, kLobe = 0.005;
const Vec3 kCentre{12.0, 8.0, 3.0};

// The true effective radius for a probe moving along (θ, ψ): ball radius minus pre-travel.
double true_reff(double polar, double azimuth) {
  const double c = std::cos(polar), s = std::sin(polar);
  return kBall - (kAxial * c * c + (kLateral + kLobe * std::cos(3.0 * azimuth)) * s * s);
}

// Touch along d: the ball came toward the centre, latched at R_s + r_eff from it.
ProbeTouch touch(const Vec3& centre, const Vec3& d, double noise = 0.0) {
  const ApproachAngles a = approach_angles(d);
  return {centre - (kSphere + true_reff(a.polar, a.azimuth) + noise) * d, d};
}

std::vector<ProbeTouch> touches(const CalibrationLayout& layout, int per_ring) {
  std::vector<ProbeTouch> t;
  for (const Vec3& d : calibration_directions(layout, per_ring)) t.push_back(touch(kCentre, d));
  return t;
}

// Bound of linear interpolation in θ over steps h: h²/8 · max |∂²r/∂θ²| ≤ h²/8 · 2(axial +
// lateral + lobe) (r'' = 2 cos 2θ (lateral + lobe cos 3ψ − axial)).
double theta_bound(double h) { return h * h / 8.0 * 2.0 * (kAxial + kLateral + kLobe); }

TEST(ProbeCalibration, AnglesRoundTrip) {
  for (double th : {0.1, 0.7, 1.5, 2.5})
    for (double ps : {-3.0, -1.0, 0.0, 2.0}) {
      const ApproachAngles a = approach_angles(approach_direction(th, ps));
      EXPECT_NEAR(a.polar, th, 1e-12);
      EXPECT_NEAR(a.azimuth, ps, 1e-12);
    }
  EXPECT_NEAR(approach_angles({0, 0, -5}).polar, 0.0, 1e-15);   // straight down
  EXPECT_NEAR(approach_angles({1, 0, 0}).polar, std::numbers::pi / 2, 1e-15);
}

TEST(ProbeCalibration, ConstantCalibrationIsTheRadiusEverywhere) {
  const ProbeCalibration c = constant_calibration(0.9876);
  for (const Vec3& d : {Vec3{0, 0, -1}, Vec3{1, 1, 0}, Vec3{0.2, -0.5, -0.3}, Vec3{0, 0, 1}})
    EXPECT_DOUBLE_EQ(effective_radius(c, d), 0.9876);
}

TEST(ProbeCalibration, ValidateAndOutOfRangeTables) {
  EXPECT_EQ(validate(constant_calibration(1.0)), "");
  ProbeCalibration c = constant_calibration(1.0);
  c.harmonics = kMaxHarmonic + 1;
  EXPECT_EQ(validate(c).rfind("harmonics:", 0), 0u);
  EXPECT_EQ(effective_radius(c, {0, 0, -1}), 0.0);  // never reads past the arrays
  c = constant_calibration(1.0);
  c.polar_nodes = kMaxPolarNodes + 1;
  EXPECT_EQ(validate(c).rfind("polar_nodes:", 0), 0u);
  EXPECT_EQ(effective_radius(c, {0, 0, -1}), 0.0);
  c = constant_calibration(1.0);
  c.coeff[1][0] = std::nan("");
  EXPECT_EQ(validate(c).rfind("coeff:", 0), 0u);
}

TEST(ProbeCalibration, KnownCentreRecoversTheLobedPretravel) {
  const CalibrationLayout layout;  // 7 polar nodes (15°), order 4
  const ProbeCalibrationResult r = calibrate_probe(touches(layout, 12), kSphere, layout, &kCentre);
  ASSERT_TRUE(r.ok()) << r.error;
  EXPECT_FALSE(r.centre_fitted);
  EXPECT_LT(r.max_abs, 1e-12);  // the touches lie on the nodes: interpolated exactly
  // elsewhere: within the interpolation bound (the ψ series holds cos 3ψ exactly)
  const double bound = theta_bound(layout.polar_max_rad / (layout.polar_nodes - 1));
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> th(0.0, std::numbers::pi / 2), ps(-std::numbers::pi, std::numbers::pi);
  double worst = 0.0;
  for (int i = 0; i < 2000; ++i) {
    const double a = th(rng), b = ps(rng);
    worst = std::max(worst, std::abs(effective_radius(r.cal, approach_direction(a, b)) - true_reff(a, b)));
  }
  EXPECT_LT(worst, bound);
  EXPECT_GT(worst, 0.05 * bound);  // the bound is not vacuous: interpolation does err between nodes
  // straight down and horizontal along a lobe's crest, exactly
  EXPECT_NEAR(effective_radius(r.cal, {0, 0, -1}), kBall - kAxial, 1e-12);
  EXPECT_NEAR(effective_radius(r.cal, {1, 0, 0}), kBall - kLateral - kLobe, 1e-12);
}

TEST(ProbeCalibration, FittedCentreRecoversUpToTheConstantOffsetTerm) {
  const CalibrationLayout layout{7, std::numbers::pi / 2, 4};
  const std::vector<ProbeTouch> t = touches(layout, 12);
  const ProbeCalibrationResult r = calibrate_probe(t, kSphere, layout);
  ASSERT_TRUE(r.ok()) << r.error;
  EXPECT_TRUE(r.centre_fitted);
  // the upper-hemisphere touches with an axial/lateral difference pull the centre along Z
  const Vec3 dc = r.sphere_centre - kCentre;
  EXPECT_GT(std::abs(dc[2]), 1e-4);
  // r_cal(d) = r_true(d) + (c_fit − c)·d + O(|dc|²/R_s), at the touches and between them
  const double bound = theta_bound(std::numbers::pi / 12) + 2.0 * dot(dc, dc) / kSphere;
  for (double a = 0.0; a <= std::numbers::pi / 2; a += 0.1)
    for (double b = -3.0; b < 3.2; b += 0.25) {
      const Vec3 d = approach_direction(a, b);
      EXPECT_NEAR(effective_radius(r.cal, d), true_reff(a, b) + dot(dc, d), bound) << a << " " << b;
    }
}

TEST(ProbeCalibration, RepeatabilityNoiseAveragesOut) {
  const CalibrationLayout layout{7, std::numbers::pi / 2, 3};
  std::mt19937_64 rng(5);
  const double sigma = 0.5e-3;
  std::normal_distribution<double> noise(0.0, sigma);
  std::vector<ProbeTouch> t;
  for (int rep = 0; rep < 4; ++rep)
    for (const Vec3& d : calibration_directions(layout, 16)) t.push_back(touch(kCentre, d, noise(rng)));
  const ProbeCalibrationResult r = calibrate_probe(t, kSphere, layout, &kCentre);
  ASSERT_TRUE(r.ok()) << r.error;
  EXPECT_NEAR(r.rms, sigma, 0.25 * sigma);  // residuals are the noise
  // each ring's 7 coefficients from 64 touches: the value at a node errs by about σ·sqrt(7/64)
  for (int k = 1; k < 7; ++k)
    for (double b : {0.0, 1.0, 2.0}) {
      const double a = k * std::numbers::pi / 12;
      EXPECT_NEAR(effective_radius(r.cal, approach_direction(a, b)), true_reff(a, b), 4.0 * sigma * std::sqrt(7.0 / 64.0));
    }
}

TEST(ProbeCalibration, RefusesTablesTheTouchesDoNotDetermine) {
  const CalibrationLayout layout{7, std::numbers::pi / 2, 4};
  // 8 azimuths per ring for 9 coefficients a ring: enough touches in all, too few per ring
  std::vector<ProbeTouch> t = touches(layout, 8);
  for (int i = 0; i < 10; ++i) t.push_back(t[static_cast<std::size_t>(i)]);
  const ProbeCalibrationResult r = calibrate_probe(t, kSphere, layout, &kCentre);
  EXPECT_FALSE(r.ok());
  EXPECT_NE(r.error.find("azimuths"), std::string::npos) << r.error;
  EXPECT_FALSE(calibrate_probe(touches(layout, 12), kSphere, CalibrationLayout{1, 1.0, 2}, &kCentre).ok());
  EXPECT_FALSE(calibrate_probe(touches(layout, 12), kSphere, CalibrationLayout{7, 1.5, 9}, &kCentre).ok());
  EXPECT_FALSE(calibrate_probe({}, kSphere, layout, &kCentre).ok());
}

}  // namespace
}  // namespace pcnc
