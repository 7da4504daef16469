// test_nurbs_arc_samples.cpp — arc lengths at many parameters at once (the feed schedule's
// dense samples, geometry/nurbs_arc_samples.hpp) against one adaptive nurbs_arc_length per
// interval: on a rational circle with double knots (known length), on a random cubic, on a
// cubic whose C' vanishes inside a span (|C'| has a kink there: the 4-point sums must not be
// trusted), with parameters that cross knots and repeat; and nurbs_derivative is nurbs_eval's
// first derivative bit for bit.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "geometry/nurbs.hpp"
#include "geometry/nurbs_arc_samples.hpp"
#include "nurbs_circles.hpp"

namespace pcnc::test {
namespace {

// us: per_span samples in every span of the curve, and u_max (as the feed schedule samples).
std::vector<double> span_samples(const NurbsCurve& c, int per_span) {
  const NurbsView v = c.view();
  std::vector<double> us;
  for (int i = v.degree; i < v.count; ++i) {
    const double a = v.knots[i], b = v.knots[i + 1];
    if (!(b > a)) continue;
    for (int k = 0; k < per_span; ++k) us.push_back(a + (b - a) * k / per_span);
  }
  us.push_back(v.u_max());
  return us;
}

// the reference: one adaptive length per interval, summed
std::vector<double> one_by_one(const NurbsView& v, const std::vector<double>& us) {
  std::vector<double> s(us.size(), 0.0);
  for (std::size_t j = 1; j < us.size(); ++j) s[j] = s[j - 1] + nurbs_arc_length(v, us[j - 1], us[j]);
  return s;
}

void expect_same_lengths(const NurbsCurve& c, const std::vector<double>& us, double rel) {
  const std::vector<double> got = nurbs_arc_lengths_at(c.view(), us);
  const std::vector<double> want = one_by_one(c.view(), us);
  ASSERT_EQ(got.size(), us.size());
  EXPECT_EQ(got[0], 0.0);
  for (std::size_t j = 0; j < us.size(); ++j) {
    EXPECT_NEAR(got[j], want[j], rel * want.back() + 1e-15) << j << " u " << us[j];
    if (j > 0) {
      EXPECT_GE(got[j], got[j - 1]) << j;
      // never shorter than the chord
      const double chord = norm(nurbs_point(c.view(), us[j]) - nurbs_point(c.view(), us[j - 1]));
      EXPECT_GE(got[j] - got[j - 1], chord * (1.0 - 1e-9) - 1e-15) << j;
    }
  }
}

NurbsCurve random_cubic(unsigned seed, int count) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> d(0.0, 5.0);
  std::vector<Vec3> pts;
  for (int i = 0; i < count; ++i) pts.push_back(Vec3{d(rng), d(rng), d(rng)});
  return make_nurbs(pts, std::vector<double>(pts.size(), 1.0), 4, KnotRule::kChordLength);
}

TEST(NurbsArcSamples, DerivativeIsNurbsEvalsFirstDerivativeExactly) {
  const NurbsCurve c = random_cubic(7, 12);
  const NurbsCurve q = quarter_circle(3.0);
  for (int i = 0; i <= 500; ++i) {
    const double u = c.u_min() + (c.u_max() - c.u_min()) * i / 500.0;
    const Vec3 d = nurbs_derivative(c.view(), u), e = nurbs_eval(c.view(), u).d1;
    for (int a = 0; a < 3; ++a) EXPECT_EQ(d[static_cast<std::size_t>(a)], e[static_cast<std::size_t>(a)]) << u;
    const double w = i / 500.0;
    const Vec3 dq = nurbs_derivative(q.view(), w), eq = nurbs_eval(q.view(), w).d1;
    for (int a = 0; a < 3; ++a) EXPECT_EQ(dq[static_cast<std::size_t>(a)], eq[static_cast<std::size_t>(a)]) << w;
  }
}

TEST(NurbsArcSamples, CircleAcrossDoubleKnotsHasItsLength) {
  const double r = 7.5;
  const NurbsCurve c = full_circle(r, Vec3{12.5, 12.5, 3.0});
  const std::vector<double> us = span_samples(c, 128);
  const std::vector<double> s = nurbs_arc_lengths_at(c.view(), us);
  EXPECT_NEAR(s.back(), 2 * M_PI * r, 1e-9);
  // every sample: the arc of a circle is r times the angle swept
  for (std::size_t j = 0; j < us.size(); ++j) {
    const Vec3 p = nurbs_point(c.view(), us[j]) - Vec3{12.5, 12.5, 3.0};
    double angle = std::atan2(p[1], p[0]) - std::atan2(nurbs_point(c.view(), 0.0)[1] - 12.5, nurbs_point(c.view(), 0.0)[0] - 12.5);
    while (angle < -1e-9) angle += 2 * M_PI;
    if (j + 1 == us.size()) angle = 2 * M_PI;
    EXPECT_NEAR(s[j], r * angle, 1e-9) << j;
  }
  expect_same_lengths(c, us, 1e-11);
}

TEST(NurbsArcSamples, RandomCubicsAgreeWithTheAdaptiveLength) {
  for (unsigned seed = 1; seed <= 20; ++seed) {
    const NurbsCurve c = random_cubic(seed, 6 + static_cast<int>(seed % 7));
    expect_same_lengths(c, span_samples(c, 32), 1e-11);
    expect_same_lengths(c, span_samples(c, 3), 1e-11);
  }
}

TEST(NurbsArcSamples, VanishingDerivativeAndKnotCrossingIntervals) {
  // a cubic Bézier whose C' vanishes at u = 0.5 (a cusp: |C'| has a kink there)
  const NurbsCurve cusp = make_nurbs({Vec3{0, 0, 0}, Vec3{2, 1, 0}, Vec3{0, 1, 0}, Vec3{2, 0, 0}}, {1, 1, 1, 1}, 4,
                                     KnotRule::kOpenUniform);
  EXPECT_NEAR(norm(nurbs_eval(cusp.view(), 0.5).d1), 0.0, 1e-12);
  std::vector<double> us;
  for (int k = 0; k <= 7; ++k) us.push_back(k / 7.0);  // 0.5 falls inside an interval
  expect_same_lengths(cusp, us, 1e-12);
  // parameters crossing several knots, repeated ones, and both ends
  const NurbsCurve c = random_cubic(3, 10);
  const double lo = c.u_min(), hi = c.u_max();
  us = {lo, lo + 0.01 * (hi - lo), lo + 0.37 * (hi - lo), lo + 0.37 * (hi - lo), lo + 0.38 * (hi - lo), lo + 0.9 * (hi - lo), hi};
  expect_same_lengths(c, us, 1e-11);
  EXPECT_NEAR(nurbs_arc_lengths_at(c.view(), us).back(), nurbs_arc_length(c.view(), lo, hi), 1e-11 * nurbs_arc_length(c.view(), lo, hi));
}

}  // namespace
}  // namespace pcnc::test
