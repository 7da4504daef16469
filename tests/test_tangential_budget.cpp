// test_tangential_budget.cpp — the tangential acceleration the axes leave after the normal part
// (shared/geometry/tangential_budget): the range against a brute-force scan of accelerations
// that keep every axis within its limit, its symmetric part, the closed-form ramp bound
// against bisection, and the curve frame against finite differences of the curve.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "geometry/nurbs.hpp"
#include "geometry/tangential_budget.hpp"

namespace pcnc {
namespace {

bool within_all_axes(const Vec3& t, const Vec3& k, double v2, double a_t, const AxisLimits& A) {
  for (int i = 0; i < kAxes; ++i) {
    if (std::abs(t[i] * a_t + k[i] * v2) > A[i]) return false;
  }
  return true;
}

// A random unit tangent and a curvature vector normal to it.
void random_frame(std::mt19937& rng, Vec3& t, Vec3& k) {
  std::normal_distribution<double> n(0.0, 1.0);
  t = normalized(Vec3{n(rng), n(rng), n(rng)});
  Vec3 r{n(rng), n(rng), n(rng)};
  r = r - dot(r, t) * t;
  std::uniform_real_distribution<double> curv(0.0, 3.0);
  k = curv(rng) * normalized(r);
}

TEST(TangentialBudget, RangeIsExactlyTheAccelerationsEveryAxisAllows) {
  std::mt19937 rng(7);
  const AxisLimits A{2000.0, 1500.0, 3000.0};
  std::uniform_real_distribution<double> speed(0.0, 30.0);  // |range| stays within the scan
  int nonempty = 0;
  for (int trial = 0; trial < 300; ++trial) {
    Vec3 t, k;
    random_frame(rng, t, k);
    const double v2 = speed(rng) * speed(rng);
    const AccelRange r = tangential_accel_range(t, k, v2, A);
    // brute force over a grid of accelerations: inside the range <=> every axis within its limit
    double lo = 1e300, hi = -1e300;
    for (int j = -24000; j <= 24000; ++j) {
      const double a = 0.5 * j;
      if (within_all_axes(t, k, v2, a, A)) {
        lo = std::min(lo, a);
        hi = std::max(hi, a);
      }
    }
    if (lo > hi) {
      EXPECT_GT(r.lo, r.hi - 0.5) << "trial " << trial << ": the scan found no acceleration";
      continue;
    }
    ++nonempty;
    EXPECT_NEAR(r.lo, lo, 0.5) << "trial " << trial;
    EXPECT_NEAR(r.hi, hi, 0.5) << "trial " << trial;
    // the symmetric part: the largest b such that both +b and -b keep every axis within its limit
    const double b = tangential_budget(t, k, v2, A);
    EXPECT_NEAR(b, std::min(r.hi, -r.lo), 1e-9 * (1.0 + std::abs(b)));
    if (b > 0.0) {
      EXPECT_TRUE(within_all_axes(t, k, v2, 0.999999 * b, A));
      EXPECT_TRUE(within_all_axes(t, k, v2, -0.999999 * b, A));
      EXPECT_FALSE(within_all_axes(t, k, v2, 1.001 * b, A) && within_all_axes(t, k, v2, -1.001 * b, A));
    }
  }
  EXPECT_GT(nonempty, 200);
}

TEST(TangentialBudget, AnApexAlongAnAxisGivesEachAxisItsOwnPart) {
  // Tangent along X, normal along Y (the apex of a bend drawn along the axes): X takes the whole
  // tangential part, Y the whole centripetal part; they do not share.
  const AxisLimits A{2000.0, 2000.0, 2000.0};
  const Vec3 t{1.0, 0.0, 0.0}, k{0.0, 2.0, 0.0};  // radius 0.5 mm
  EXPECT_DOUBLE_EQ(tangential_budget(t, k, 999.0, A), 2000.0);
  const AccelRange r = tangential_accel_range(t, k, 999.0, A);
  EXPECT_DOUBLE_EQ(r.lo, -2000.0);
  EXPECT_DOUBLE_EQ(r.hi, 2000.0);
  EXPECT_GT(tangential_accel_range(t, k, 1001.0, A).lo, tangential_accel_range(t, k, 1001.0, A).hi)
      << "v^2 k_y above A_y: no tangential acceleration helps";
  // At 45 degrees both axes share: |a_t|/sqrt2 + v^2 |k|/sqrt2 <= A.
  const double s = std::sqrt(0.5);
  EXPECT_NEAR(tangential_budget({s, s, 0.0}, {-s * 2.0, s * 2.0, 0.0}, 500.0, A), (2000.0 - 2.0 * s * 500.0) / s, 1e-9);
}

TEST(TangentialBudget, ReachableV2IsTheLargestSpeedTheRampAllows) {
  std::mt19937 rng(11);
  const AxisLimits A{2000.0, 2000.0, 1000.0};
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  for (int trial = 0; trial < 200; ++trial) {
    Vec3 t, k;
    random_frame(rng, t, k);
    const double from = 400.0 * u01(rng), ds = 0.001 + 0.05 * u01(rng), share = 0.5 + 0.5 * u01(rng);
    // bisection on f(x) = from + 2 ds share budget(x) - x, falling in x
    auto f = [&](double x) { return from + 2.0 * ds * share * tangential_budget(t, k, x, A) - x; };
    double lo = 0.0, hi = 1e7;
    for (int it = 0; it < 200; ++it) {
      const double mid = 0.5 * (lo + hi);
      (f(mid) >= 0.0 ? lo : hi) = mid;
    }
    const double x = reachable_v2(from, ds, t, k, A, share);
    EXPECT_NEAR(x, lo, 1e-9 * (1.0 + lo)) << "trial " << trial;
    EXPECT_GE(f(x), -1e-9 * (1.0 + x));
  }
  EXPECT_TRUE(std::isinf(reachable_v2(1.0, 0.1, {0.0, 0.0, 0.0}, {0.0, 0.0, 0.0}, A, 1.0)));
}

TEST(TangentialBudget, CurveFrameMatchesFiniteDifferences) {
  // A cubic through a bend in 3D, non-uniform weights: t and k against finite differences of
  // the curve's points (second order, in u).
  const NurbsCurve c = make_nurbs({{0, 0, 0}, {1, 0.2, 0}, {2, 1.5, 0.3}, {2.5, 3, 0.1}, {4, 3.5, 0}},
                                  {1.0, 1.5, 0.8, 1.2, 1.0}, 4);
  const NurbsView v = c.view();
  for (double f : {0.1, 0.27, 0.5, 0.73, 0.9}) {
    const double u = v.u_min() + f * (v.u_max() - v.u_min());
    const double h = 1e-4;
    const Vec3 pm = nurbs_point(v, u - h), p0 = nurbs_point(v, u), pp = nurbs_point(v, u + h);
    const Vec3 d1 = (1.0 / (2.0 * h)) * (pp - pm);
    const Vec3 d2 = (1.0 / (h * h)) * (pp - 2.0 * p0 + pm);
    const Vec3 t = normalized(d1);
    const Vec3 k = (1.0 / dot(d1, d1)) * (d2 - dot(d2, t) * t);
    const CurveFrame fr = nurbs_frame(v, u);
    ASSERT_TRUE(fr.ok);
    EXPECT_LT(norm(fr.t - t), 1e-7) << "u=" << u;
    EXPECT_LT(norm(fr.k - k), 1e-4 * (1.0 + norm(k))) << "u=" << u;
  }
  // A doubled first control point: C'(0) = 0; the frame is taken just beside it.
  const NurbsCurve d = make_nurbs({{0, 0, 0}, {0, 0, 0}, {1, 0, 0}, {2, 1, 0}}, {1, 1, 1, 1}, 4);
  const CurveFrame f0 = nurbs_frame(d.view(), d.view().u_min());
  ASSERT_TRUE(f0.ok);
  EXPECT_NEAR(f0.t[0], 1.0, 1e-3);
}

TEST(TangentialBudget, CurveFrameWithASpanHintIsTheSameFrame) {
  // Any hint (the span, a neighbour, out of range) gives the frame without one, bit for bit, and
  // leaves the span of u (find_span) behind; also where C' vanishes (the doubled point).
  const NurbsCurve c = make_nurbs({{0, 0, 0}, {0, 0, 0}, {1, 0.2, 0}, {2, 1.5, 0.3}, {2.5, 3, 0.1}, {4, 3.5, 0}, {5, 3, 1}},
                                  {1.0, 1.0, 1.5, 0.8, 1.2, 1.0, 0.7}, 4);
  const NurbsView v = c.view();
  int frames = 0;
  for (int i = 0; i <= 200; ++i) {
    const double u = v.u_min() + (v.u_max() - v.u_min()) * i / 200.0;
    const CurveFrame ref = nurbs_frame(v, u);
    for (int hint = -1; hint <= v.count + 1; ++hint) {
      int h = hint;
      const CurveFrame f = nurbs_frame(v, u, h);
      EXPECT_EQ(f.ok, ref.ok);
      EXPECT_EQ(f.p, ref.p) << "u=" << u << " hint " << hint;
      EXPECT_EQ(f.t, ref.t) << "u=" << u << " hint " << hint;
      EXPECT_EQ(f.k, ref.k) << "u=" << u << " hint " << hint;
      EXPECT_EQ(h, find_span(v, u));
      frames += f.ok ? 1 : 0;
    }
  }
  EXPECT_EQ(frames, 201 * (v.count + 3));
}

}  // namespace
}  // namespace pcnc
