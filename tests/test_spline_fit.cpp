// test_spline_fit.cpp — the smoothing fit (shared/geometry/spline_fit.hpp): the tolerance is
// measured here independently (dense curve samples against every programmed segment, every
// programmed point and segment against a dense curve polyline, no windows), the run's end
// points are exact, the curve is C2, and a corner the fit cannot follow is reported.
#include <gtest/gtest.h>

#include <algorithm>
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

// polyline_deviation as it was before its segments were skipped by bounding balls: every
// segment of each window scanned with point_segment_distance. The measure must give the same
// distances bit for bit (the fits, and so the blocks, depend on them).
std::vector<double> full_scan_per_point(const NurbsCurve& curve, const std::vector<Vec3>& pts, int per_span,
                                        double& worst) {
  std::vector<double> t(pts.size(), 0.0);
  for (std::size_t i = 1; i < pts.size(); ++i) t[i] = t[i - 1] + norm(pts[i] - pts[i - 1]);
  auto window = [](const std::vector<double>& x, double u, std::size_t min_count, double min_width) {
    const std::size_t n = x.size();
    std::size_t j = static_cast<std::size_t>(std::upper_bound(x.begin(), x.end(), u) - x.begin());
    j = j > 0 ? j - 1 : 0;
    std::size_t lo = j, hi = std::min(j + 1, n - 1);
    while (lo > 0 && (j - lo < min_count || u - x[lo] < min_width)) --lo;
    while (hi + 1 < n && (hi - j < min_count || x[hi] - u < min_width)) ++hi;
    return std::pair<std::size_t, std::size_t>{lo, hi};
  };
  auto to_polyline = [](const Vec3& p, const std::vector<Vec3>& q, std::size_t lo, std::size_t hi) {
    double best = norm(p - q[lo]);
    for (std::size_t i = lo; i < hi; ++i) best = std::min(best, point_segment_distance(p, q[i], q[i + 1]));
    return best;
  };
  const NurbsView v = curve.view();
  std::vector<double> su;
  std::vector<Vec3> sp;
  for (int i = curve.degree; i < v.count; ++i) {
    const double a = v.knots[i], b = v.knots[i + 1];
    if (!(b > a)) continue;
    for (int j = 0; j < per_span; ++j) su.push_back(a + (b - a) * j / per_span);
  }
  su.push_back(v.u_max());
  for (double u : su) sp.push_back(nurbs_point(v, u));
  const double span = t.back() / static_cast<double>(std::max<std::size_t>(1, su.size() - 1)) * per_span;
  const double width = 0.05 + 2.0 * span / per_span;
  std::vector<std::pair<double, double>> devs;  // (u, distance)
  for (std::size_t k = 0; k < su.size(); ++k) {
    const auto [lo, hi] = window(t, su[k], 4, width);
    devs.push_back({su[k], to_polyline(sp[k], pts, lo, hi)});
  }
  for (std::size_t i = 0; i < pts.size(); ++i) {
    for (int q = 0; q < (i + 1 < pts.size() ? 4 : 1); ++q) {
      const double f = q / 4.0;
      const Vec3 p = q == 0 ? pts[i] : pts[i] + f * (pts[i + 1] - pts[i]);
      const double u = q == 0 ? t[i] : t[i] + f * (t[i + 1] - t[i]);
      const auto [lo, hi] = window(su, u, static_cast<std::size_t>(2 * per_span), width);
      devs.push_back({u, to_polyline(p, sp, lo, hi)});
    }
  }
  worst = 0.0;
  std::vector<double> per_point(pts.size(), 0.0);
  for (const auto& [u, d] : devs) {
    worst = std::max(worst, d);
    std::size_t j = static_cast<std::size_t>(std::lower_bound(t.begin(), t.end(), u) - t.begin());
    if (j >= t.size() || (j > 0 && u - t[j - 1] < t[j] - u)) j = j > 0 ? j - 1 : 0;
    per_point[j] = std::max(per_point[j], d);
  }
  return per_point;
}

TEST(SplineFit, PolylineDeviationIsTheFullScansBitForBit) {
  // fitted curves (close to their polylines: most segments skipped), the same curves against
  // a shifted polyline (far: few skipped), and a run that comes back on itself (a closed loop,
  // where a window's far end is near its start)
  std::vector<std::pair<NurbsCurve, std::vector<Vec3>>> cases;
  for (const auto& [n, step] : {std::pair{120, 0.05}, std::pair{400, 0.02}, std::pair{60, 0.4}}) {
    const std::vector<Vec3> pts = wave(n, step, 4);
    const SplineFit fit = fit_polyline(pts, 0.005);  // ok or not: a valid curve near the points
    ASSERT_EQ(validate(fit.curve), "");
    cases.push_back({fit.curve, pts});
    std::vector<Vec3> shifted = pts;
    for (Vec3& p : shifted) p[2] += 0.01;
    cases.push_back({fit.curve, shifted});
  }
  std::vector<Vec3> loop;
  for (int i = 0; i <= 200; ++i) {
    const double a = 2.0 * std::numbers::pi * i / 200.0;
    loop.push_back({std::cos(a), std::sin(a), 0.0});
  }
  cases.push_back({fit_polyline(loop, 0.005).curve, loop});
  for (std::size_t c = 0; c < cases.size(); ++c) {
    for (int per_span : {16, 5}) {
      double worst_ref = 0.0;
      const std::vector<double> ref = full_scan_per_point(cases[c].first, cases[c].second, per_span, worst_ref);
      std::vector<double> got;
      EXPECT_EQ(polyline_deviation(cases[c].first, cases[c].second, per_span, &got), worst_ref) << "case " << c;
      ASSERT_EQ(got.size(), ref.size());
      for (std::size_t i = 0; i < ref.size(); ++i) EXPECT_EQ(got[i], ref[i]) << "case " << c << " point " << i;
    }
  }
}

}  // namespace
}  // namespace pcnc
