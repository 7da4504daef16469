// test_spline_fit.cpp — the smoothing fit (shared/geometry/spline_fit.hpp): the tolerance is
// measured here independently (dense curve samples against every programmed segment, every
// programmed point and segment against a dense curve polyline, no windows), the run's end
// points are exact, the curve is C2, and a corner the fit cannot follow is reported.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "geometry/spline_fit.hpp"

namespace pcnc {
namespace {

// Brute force: every one of `n` curve samples against every segment, and every programmed
// point and segment sample against every chord of a dense curve polyline.
double brute_deviation(const NurbsCurve& c, const std::vector<Vec3>& pts, int n = 20000) {
  const NurbsView v = c.view();
  std::vector<Vec3> s;
  for (int i = 0; i <= n; ++i) s.push_back(nurbs_point(v, v.u_min() + (v.u_max() - v.u_min()) * i / n));
  double worst = 0.0;
  for (const Vec3& p : s) {
    double d = 1e300;
    for (std::size_t j = 0; j + 1 < pts.size(); ++j) d = std::min(d, point_segment_distance(p, pts[j], pts[j + 1]));
    worst = std::max(worst, d);
  }
  for (std::size_t j = 0; j < pts.size(); ++j) {
    for (int q = 0; q < (j + 1 < pts.size() ? 8 : 1); ++q) {
      const Vec3 p = q == 0 ? pts[j] : pts[j] + (q / 8.0) * (pts[j + 1] - pts[j]);
      double d = 1e300;
      for (std::size_t k = 0; k + 1 < s.size(); ++k) d = std::min(d, point_segment_distance(p, s[k], s[k + 1]));
      worst = std::max(worst, d);
    }
  }
  return worst;
}

// A CAM-like run: a 3D curve (helix-ish wave) sampled into short chords, coordinates rounded
// to `decimals` as a post-processor writes them.
std::vector<Vec3> wave(int n, double step, int decimals) {
  std::vector<Vec3> pts;
  const double q = std::pow(10.0, decimals);
  for (int i = 0; i <= n; ++i) {
    const double s = i * step;
    Vec3 p{5.0 + 4.0 * std::cos(s / 4.0), 5.0 + 3.0 * std::sin(s / 3.0), 2.0 + 0.8 * std::sin(s)};
    for (double& x : p) x = std::round(x * q) / q;
    pts.push_back(p);
  }
  return pts;
}

void expect_c2(const NurbsCurve& c) {
  const NurbsView v = c.view();
  for (int i = c.degree + 1; i < v.count; ++i) {
    const double u = v.knots[i];
    if (!(u > v.u_min() && u < v.u_max())) continue;
    const double h = 1e-7;
    const NurbsEval a = nurbs_eval(v, u - h), b = nurbs_eval(v, u + h);
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(a.p[k], b.p[k], 1e-6);
      EXPECT_NEAR(a.d1[k], b.d1[k], 1e-5 * (1.0 + std::abs(a.d1[k])));
      EXPECT_NEAR(a.d2[k], b.d2[k], 1e-3 * (1.0 + std::abs(a.d2[k])));
    }
  }
}

TEST(SplineFit, CamWaveFitsWithinTheToleranceMeasuredIndependently) {
  for (double tol : {0.001, 0.005, 0.02}) {
    const std::vector<Vec3> pts = wave(400, 0.08, 3);
    const SplineFit f = fit_polyline(pts, tol);
    ASSERT_TRUE(f.ok) << tol << " " << f.deviation;
    EXPECT_EQ(validate(f.curve), "");
    const double brute = brute_deviation(f.curve, pts);
    EXPECT_LE(brute, tol * 1.0001) << "tolerance " << tol;
    // the fit's own figure is measured too: never below the true distance, and close to it
    EXPECT_LE(brute, 1.02 * f.deviation);
    EXPECT_GE(brute, 0.9 * f.deviation);
    // compression: far fewer control points than programmed points
    EXPECT_LT(f.curve.points.size(), pts.size() / 2) << tol;
    // end points exact
    EXPECT_EQ(f.curve.points.front(), pts.front());
    EXPECT_EQ(f.curve.points.back(), pts.back());
    EXPECT_EQ(nurbs_point(f.curve.view(), f.curve.u_max()), pts.back());
    expect_c2(f.curve);
  }
}

TEST(SplineFit, NoisyPointsStillFit) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> jitter(-0.002, 0.002);
  std::vector<Vec3> pts = wave(300, 0.05, 4);
  for (std::size_t i = 1; i + 1 < pts.size(); ++i)
    for (double& x : pts[i]) x += jitter(rng);
  const SplineFit f = fit_polyline(pts, 0.005);
  ASSERT_TRUE(f.ok) << f.deviation;
  EXPECT_LE(brute_deviation(f.curve, pts), 0.005 * 1.0001);
  expect_c2(f.curve);
}

TEST(SplineFit, TwoPointsAreTheSegment) {
  const std::vector<Vec3> pts{{1, 2, 3}, {4, 6, 3}};
  const SplineFit f = fit_polyline(pts, 0.005);
  ASSERT_TRUE(f.ok);
  EXPECT_LE(brute_deviation(f.curve, pts), 1e-9);
}

// A sharp corner in the middle of a run: no C2 curve stays within 1 µm of it with knots
// no closer than the fit allows; the fit says so and points at the corner.
TEST(SplineFit, ASharpCornerIsReportedWhereItIs) {
  std::vector<Vec3> pts;
  for (int i = 0; i <= 20; ++i) pts.push_back({0.1 * i, 0.0, 0.0});
  for (int i = 1; i <= 20; ++i) pts.push_back({2.0, 0.1 * i, 0.0});
  const SplineFit f = fit_polyline(pts, 0.0001);
  EXPECT_FALSE(f.ok) << f.deviation;
  EXPECT_NEAR(f.worst_point, 20, 2);
  EXPECT_GE(brute_deviation(f.curve, pts), 0.0001);
}

// A few very long moves (a fuzzer found 64 points over 7.7 m): the first knots are 2 mm apart
// only up to what refinement may reach, about two per programmed point, not thousands.
TEST(SplineFit, AFewVeryLongMovesCostFewKnots) {
  std::vector<Vec3> pts;
  for (int i = 0; i <= 8; ++i) pts.push_back({1000.0 * i, 30.0 * std::sin(0.3 * i), 0.0});
  const SplineFit f = fit_polyline(pts, 0.005);
  EXPECT_LE(f.curve.points.size(), 2 * pts.size() + 8 + 4);
  EXPECT_EQ(f.curve.points.front(), pts.front());
  EXPECT_EQ(f.curve.points.back(), pts.back());
  if (f.ok) {
    EXPECT_LE(brute_deviation(f.curve, pts), 0.005 * 1.05);
  }
}

// The per-point figure names where the deviation is.
TEST(SplineFit, PolylineDeviationOfTheSegmentItself) {
  const std::vector<Vec3> pts{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}};
  NurbsCurve straight = make_nurbs({{0, 0, 0}, {1.0 / 3, 0, 0}, {2.0 / 3, 0, 0}, {1, 0, 0}}, {1, 1, 1, 1}, 4);
  std::vector<double> per_point;
  const double d = polyline_deviation(straight, pts, 16, &per_point);
  EXPECT_GT(d, 0.9);  // the second segment is far from a curve that stops at (1, 0, 0)
  EXPECT_GT(per_point[2], 0.9);
}

}  // namespace
}  // namespace pcnc
