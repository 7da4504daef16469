// test_nurbs.cpp — the NURBS value type against exact geometry: circles and lines made of
// rational quadratics, an independent Cox–de Boor reference, derivatives against finite
// differences, knot vectors (LinuxCNC G5.2 and the seed's chord length), knot insertion,
// splitting into block-sized pieces, block storage and validation messages.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "geometry/nurbs.hpp"
#include "geometry/tangential_budget.hpp"
#include "ipc/block_nurbs.hpp"
#include "nurbs_circles.hpp"
#include "gcode/nurbs_reader.hpp"
#include "gcode/nurbs_rough.hpp"
#include "nurbs_tool.hpp"
#include "test_paths.hpp"

namespace pcnc {
namespace {

const double kS = test::kCircleWeight;
using test::full_circle;
using test::quarter_circle;

// The control points of ../shared/gcode/nurbs/g5.2/nurbs-xy.ngc (start at X0 Y0, order 3).
NurbsCurve nurbs_xy() {
  return make_nurbs({{0, 0, 0}, {0, 1, 0}, {2, 2, 0}, {2, 0, 0}, {0, 0, 0}}, {1, 1, 1, 1, 2}, 3);
}

NurbsCurve random_curve(int count, int degree, unsigned seed, KnotRule rule = KnotRule::kOpenUniform) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> coord(0.0, 20.0);
  std::uniform_real_distribution<double> weight(0.3, 3.0);
  std::vector<Vec3> pts;
  std::vector<double> w;
  for (int i = 0; i < count; ++i) {
    pts.push_back({coord(rng), coord(rng), coord(rng) * 0.2});
    w.push_back(weight(rng));
  }
  return make_nurbs(pts, w, degree + 1, rule);
}

// Independent reference: the textbook recursive definition, evaluated directly.
double basis_ref(const std::vector<double>& t, int i, int p, double u, bool last_span) {
  if (p == 0) {
    if (last_span) return (t[i] < u && u <= t[i + 1]) ? 1.0 : 0.0;
    return (t[i] <= u && u < t[i + 1]) ? 1.0 : 0.0;
  }
  double v = 0.0;
  if (t[i + p] != t[i]) v += (u - t[i]) / (t[i + p] - t[i]) * basis_ref(t, i, p - 1, u, last_span);
  if (t[i + p + 1] != t[i + 1])
    v += (t[i + p + 1] - u) / (t[i + p + 1] - t[i + 1]) * basis_ref(t, i + 1, p - 1, u, last_span);
  return v;
}

Vec3 point_ref(const NurbsCurve& c, double u) {
  const bool last = u >= c.u_max();
  Vec3 a{0, 0, 0};
  double w = 0;
  for (std::size_t i = 0; i < c.points.size(); ++i) {
    const double n = basis_ref(c.knots, static_cast<int>(i), c.degree, u, last) * c.weights[i];
    a = a + n * c.points[i];
    w += n;
  }
  return (1.0 / w) * a;
}

TEST(NurbsKnots, OpenUniformAsLinuxCncBuildsIt) {
  // n+1 = 5 control points, order 3: 0 0 0 1 2 3 3 3 (domain 0..count-order+1).
  EXPECT_EQ(open_uniform_knots(5, 2), (std::vector<double>{0, 0, 0, 1, 2, 3, 3, 3}));
  // 7 points, order 4 (trident programs): 0 0 0 0 1 2 3 4 4 4 4.
  EXPECT_EQ(open_uniform_knots(7, 3), (std::vector<double>{0, 0, 0, 0, 1, 2, 3, 4, 4, 4, 4}));
  // As many points as the order: a Bezier curve on [0, 1].
  EXPECT_EQ(open_uniform_knots(4, 3), (std::vector<double>{0, 0, 0, 0, 1, 1, 1, 1}));
}

TEST(NurbsKnots, ChordLengthFollowsSeedEquation4) {
  // Chords 2, 1, 1 (total 4), order 3, m = n-k+2 = 2: x = ((1/2)*1 + 2) / 4 * 2 = 1.25.
  const std::vector<Vec3> pts = {{0, 0, 0}, {2, 0, 0}, {2, 1, 0}, {2, 2, 0}};
  const std::vector<double> k = chord_length_knots(pts, 2);
  ASSERT_EQ(k.size(), 7u);
  EXPECT_EQ(k[0], 0.0);
  EXPECT_EQ(k[2], 0.0);
  EXPECT_DOUBLE_EQ(k[3], 1.25);
  EXPECT_EQ(k[4], 2.0);
  EXPECT_EQ(k[6], 2.0);
  // Always clamped, increasing, valid, same domain as the open uniform vector.
  for (unsigned seed = 1; seed < 20; ++seed) {
    const NurbsCurve c = random_curve(12, 1 + static_cast<int>(seed % 5), seed, KnotRule::kChordLength);
    EXPECT_EQ(validate(c), "") << seed;
    EXPECT_DOUBLE_EQ(c.u_max(), open_uniform_knots(12, c.degree)[12]) << seed;
    for (std::size_t i = 1; i < c.knots.size(); ++i) EXPECT_LE(c.knots[i - 1], c.knots[i]);
  }
}

TEST(NurbsEval, QuarterCircleIsExact) {
  const double r = 10.0;
  const NurbsCurve c = quarter_circle(r);
  ASSERT_EQ(validate(c), "");
  for (int i = 0; i <= 1000; ++i) {
    const double u = i / 1000.0;
    const NurbsEval e = nurbs_eval(c.view(), u);
    EXPECT_NEAR(norm(e.p), r, 1e-11) << u;
    EXPECT_NEAR(dot(e.p, e.d1), 0.0, 1e-9) << u;  // tangent perpendicular to the radius
    EXPECT_NEAR(nurbs_curvature(e), 1.0 / r, 1e-10) << u;
  }
  EXPECT_NEAR(nurbs_arc_length(c.view(), 0, 1), M_PI * r / 2, 1e-9);
}

TEST(NurbsEval, FullCircleIsExactAcrossDoubleKnots) {
  const double r = 7.5;
  const Vec3 center{12.5, 12.5, 3.0};
  const NurbsCurve c = full_circle(r, center);
  ASSERT_EQ(validate(c), "");
  for (int i = 0; i <= 4000; ++i) {
    const double u = 4.0 * i / 4000.0;
    const NurbsEval e = nurbs_eval(c.view(), u);
    EXPECT_NEAR(norm(e.p - center), r, 1e-11) << u;
    EXPECT_NEAR(e.p[2], 3.0, 1e-12);
    EXPECT_NEAR(nurbs_curvature(e), 1.0 / r, 1e-10) << u;
  }
  EXPECT_NEAR(nurbs_arc_length(c.view(), 0, 4), 2 * M_PI * r, 1e-9);
  // The double knots are not corners: the circle is tangent continuous.
  EXPECT_TRUE(corner_knots(c).empty());
}

TEST(NurbsEval, LineStaysOnLine) {
  // Collinear control points with uneven weights: every point is on the line.
  const Vec3 a{1, 2, 3}, b{11, 7, -2};
  std::vector<Vec3> pts;
  for (double s : {0.0, 0.1, 0.5, 0.55, 0.9, 1.0}) pts.push_back(a + s * (b - a));
  const NurbsCurve c = make_nurbs(pts, {1, 0.5, 2, 1, 3, 1}, 4);
  ASSERT_EQ(validate(c), "");
  const Vec3 dir = normalized(b - a);
  for (int i = 0; i <= 500; ++i) {
    const double u = c.u_max() * i / 500.0;
    const Vec3 p = nurbs_point(c.view(), u);
    const Vec3 off = p - a;
    EXPECT_NEAR(norm(off - dot(off, dir) * dir), 0.0, 1e-12) << u;
  }
}

TEST(NurbsEval, MatchesIndependentReferenceAndEndsAtControlPoints) {
  const NurbsCurve xy = nurbs_xy();
  ASSERT_EQ(validate(xy), "");
  EXPECT_EQ(xy.u_max(), 3.0);
  for (const NurbsCurve& c : {xy, random_curve(17, 3, 5), random_curve(9, 5, 6), random_curve(6, 1, 7),
                              random_curve(20, 4, 8, KnotRule::kChordLength)}) {
    for (int i = 0; i <= 777; ++i) {
      const double u = c.u_min() + (c.u_max() - c.u_min()) * i / 777.0;
      const Vec3 got = nurbs_point(c.view(), u);
      const Vec3 ref = point_ref(c, u);
      EXPECT_NEAR(norm(got - ref), 0.0, 1e-10) << "u=" << u;
      EXPECT_NEAR(norm(nurbs_eval(c.view(), u).p - got), 0.0, 1e-12);
    }
    EXPECT_NEAR(norm(nurbs_point(c.view(), c.u_min()) - c.points.front()), 0.0, 1e-12);
    EXPECT_NEAR(norm(nurbs_point(c.view(), c.u_max()) - c.points.back()), 0.0, 1e-12);
  }
}

// The generic Cox–de Boor loops nurbs_eval ran before it was unrolled per degree (the same
// operations in the same order): the unrolled evaluation must give the same bits.
inline double sdiv(double a, double b) { return b != 0.0 ? a / b : 0.0; }

// table[d][j] = N_{span-d+j, d}(u) by the generic Cox–de Boor loops, u clamped to the domain;
// returns the span.
int generic_table(const NurbsView& v, double& u, double (&table)[6][6]) {
  u = std::clamp(u, v.u_min(), v.u_max());
  const int p = v.degree;
  const int span = find_span(v, u);
  const double* t = v.knots;
  table[0][0] = 1.0;
  for (int d = 1; d <= p; ++d) {
    for (int j = 0; j <= d; ++j) {
      const int i = span - d + j;
      double value = 0.0;
      if (j >= 1) value += sdiv(u - t[i], t[i + d] - t[i]) * table[d - 1][j - 1];
      if (j <= d - 1) value += sdiv(t[i + d + 1] - u, t[i + d + 1] - t[i + 1]) * table[d - 1][j];
      table[d][j] = value;
    }
  }
  return span;
}

NurbsEval generic_eval(const NurbsCurve& c, double u) {
  const NurbsView v = c.view();
  const int p = v.degree;
  const double* t = v.knots;
  double table[6][6] = {};
  const int span = generic_table(v, u, table);
  auto derive = [&](int d, const double* lower, double* out) {
    for (int j = 0; j <= d; ++j) {
      const int i = span - d + j;
      double value = 0.0;
      if (j >= 1) value += sdiv(lower[j - 1], t[i + d] - t[i]);
      if (j <= d - 1) value -= sdiv(lower[j], t[i + d + 1] - t[i + 1]);
      out[j] = d * value;
    }
  };
  double d1[6] = {}, d2[6] = {}, lower_d1[6] = {};
  derive(p, table[p - 1], d1);
  if (p >= 2) {
    derive(p - 1, table[p - 2], lower_d1);
    derive(p, lower_d1, d2);
  }
  Vec3 a0{}, a1{}, a2{};
  double w0 = 0.0, w1 = 0.0, w2 = 0.0;
  for (int j = 0; j <= p; ++j) {
    const int i = span - p + j;
    const double w = v.weights[i];
    const Vec3 wp = w * v.points[i];
    a0 = a0 + table[p][j] * wp;
    a1 = a1 + d1[j] * wp;
    a2 = a2 + d2[j] * wp;
    w0 += table[p][j] * w;
    w1 += d1[j] * w;
    w2 += d2[j] * w;
  }
  NurbsEval e;
  const double inv = 1.0 / w0;
  e.p = inv * a0;
  e.d1 = inv * (a1 - w1 * e.p);
  e.d2 = inv * (a2 - 2.0 * w1 * e.d1 - w2 * e.p);
  return e;
}

// nurbs_point's generic loop before the unrolling (its own sums: N·w, then the points).
Vec3 generic_point(const NurbsCurve& c, double u) {
  const NurbsView v = c.view();
  const int p = v.degree;
  double table[6][6] = {};
  const int span = generic_table(v, u, table);
  Vec3 a{0.0, 0.0, 0.0};
  double w = 0.0;
  for (int j = 0; j <= p; ++j) {
    const int i = span - p + j;
    const double nw = table[p][j] * v.weights[i];
    a = a + nw * v.points[i];
    w += nw;
  }
  return (1.0 / w) * a;
}

// Parameters that probe every case: the ends, every knot (and the doubles just beside it),
// and random values.
std::vector<double> probe_params(const NurbsCurve& c, unsigned seed) {
  std::vector<double> us{c.u_min(), c.u_max()};
  for (const double k : c.knots) {
    us.push_back(k);
    us.push_back(std::nextafter(k, -1e300));
    us.push_back(std::nextafter(k, 1e300));
  }
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> at(c.u_min(), c.u_max());
  for (int i = 0; i < 300; ++i) us.push_back(at(rng));
  return us;
}

TEST(NurbsEval, UnrolledEvaluationAndSpanHintsGiveTheGenericLoopsBits) {
  // every degree, rational, with a doubled interior knot (a corner) on the quadratic circle
  std::vector<NurbsCurve> curves{full_circle(5.0), nurbs_xy()};
  for (int degree = 1; degree <= kMaxNurbsDegree; ++degree) {
    curves.push_back(random_curve(degree + 8, degree, 40u + static_cast<unsigned>(degree)));
    curves.push_back(random_curve(degree + 12, degree, 50u + static_cast<unsigned>(degree), KnotRule::kChordLength));
  }
  std::size_t checked = 0;
  for (std::size_t n = 0; n < curves.size(); ++n) {
    const NurbsCurve& c = curves[n];
    ASSERT_EQ(validate(c), "");
    const NurbsView v = c.view();
    for (const double u : probe_params(c, 7u + static_cast<unsigned>(n))) {
      const NurbsEval ref = generic_eval(c, u);
      const NurbsEval got = nurbs_eval(v, u);
      EXPECT_EQ(got.p, ref.p) << "curve " << n << " u=" << u;
      EXPECT_EQ(got.d1, ref.d1) << "curve " << n << " u=" << u;
      EXPECT_EQ(got.d2, ref.d2) << "curve " << n << " u=" << u;
      EXPECT_EQ(nurbs_derivative(v, u), ref.d1);
      EXPECT_EQ(nurbs_point(v, u), generic_point(c, u)) << "curve " << n << " u=" << u;
      const double uc = std::clamp(u, v.u_min(), v.u_max());
      // every hint, right or wrong, in range or not: the same span and the same bits
      for (int hint = -2; hint <= v.count + 2; ++hint) {
        ASSERT_EQ(find_span(v, uc, hint), find_span(v, uc)) << "curve " << n << " u=" << u << " hint " << hint;
        int h1 = hint, h2 = hint;
        const NurbsEval e = nurbs_eval(v, u, h1);
        EXPECT_EQ(h1, find_span(v, uc));
        EXPECT_EQ(e.p, ref.p);
        EXPECT_EQ(e.d1, ref.d1);
        EXPECT_EQ(e.d2, ref.d2);
        EXPECT_EQ(nurbs_derivative(v, u, h2), ref.d1);
        EXPECT_EQ(h2, h1);
        ++checked;
      }
    }
  }
  EXPECT_GT(checked, 10000u);
}

TEST(NurbsEval, PairsGiveTheSingleCallsBits) {
  // two parameters of one span (the two SIMD lanes), of two spans (two single calls), beyond
  // the ends (clamped), every degree, rational, with a doubled interior knot
  std::vector<NurbsCurve> curves{full_circle(5.0), nurbs_xy()};
  for (int degree = 1; degree <= kMaxNurbsDegree; ++degree) {
    curves.push_back(random_curve(degree + 8, degree, 60u + static_cast<unsigned>(degree)));
    curves.push_back(random_curve(degree + 12, degree, 70u + static_cast<unsigned>(degree), KnotRule::kChordLength));
  }
  std::size_t same_span = 0, checked = 0;
  for (std::size_t n = 0; n < curves.size(); ++n) {
    const NurbsView v = curves[n].view();
    const std::vector<double> us = probe_params(curves[n], 17u + static_cast<unsigned>(n));
    std::mt19937 rng(5u + static_cast<unsigned>(n));
    std::uniform_real_distribution<double> near(-1e-3, 1e-3);
    for (std::size_t k = 0; k < us.size(); ++k) {
      const double ua = us[k];
      for (const double ub : {us[(k + 1) % us.size()], ua + near(rng) * (v.u_max() - v.u_min()), ua, v.u_max() + 1.0}) {
        const NurbsEval ra = nurbs_eval(v, ua), rb = nurbs_eval(v, ub);
        if (find_span(v, std::clamp(ua, v.u_min(), v.u_max())) == find_span(v, std::clamp(ub, v.u_min(), v.u_max())))
          ++same_span;
        for (int hint = -1; hint <= v.count; hint += 3) {
          int h = hint;
          NurbsEval ea, eb;
          nurbs_eval_pair(v, ua, ub, h, ea, eb);
          EXPECT_EQ(ea.p, ra.p) << "curve " << n << " ua=" << ua << " ub=" << ub;
          EXPECT_EQ(ea.d1, ra.d1);
          EXPECT_EQ(ea.d2, ra.d2);
          EXPECT_EQ(eb.p, rb.p) << "curve " << n << " ua=" << ua << " ub=" << ub;
          EXPECT_EQ(eb.d1, rb.d1);
          EXPECT_EQ(eb.d2, rb.d2);
          EXPECT_EQ(h, find_span(v, std::clamp(ub, v.u_min(), v.u_max())));
          nurbs_eval_pair(v, ua, ub, h, ea, eb, false);  // without C'': p and d1 all the same
          EXPECT_EQ(ea.p, ra.p);
          EXPECT_EQ(ea.d1, ra.d1);
          EXPECT_EQ(ea.d2, Vec3{});
          EXPECT_EQ(eb.p, rb.p);
          EXPECT_EQ(eb.d1, rb.d1);
          Vec3 da, db, pa, pb;
          nurbs_derivative_pair(v, ua, ub, h, da, db);
          EXPECT_EQ(da, nurbs_derivative(v, ua));
          EXPECT_EQ(db, nurbs_derivative(v, ub));
          nurbs_point_pair(v, ua, ub, h, pa, pb);
          EXPECT_EQ(pa, nurbs_point(v, ua));
          EXPECT_EQ(pb, nurbs_point(v, ub));
          CurveFrame fa, fb;
          nurbs_frame_pair(v, ua, ub, h, fa, fb);
          const CurveFrame ga = nurbs_frame(v, ua), gb = nurbs_frame(v, ub);
          EXPECT_EQ(fa.ok, ga.ok);
          EXPECT_EQ(fa.p, ga.p);
          EXPECT_EQ(fa.t, ga.t);
          EXPECT_EQ(fa.k, ga.k);
          EXPECT_EQ(fb.ok, gb.ok);
          EXPECT_EQ(fb.p, gb.p);
          EXPECT_EQ(fb.t, gb.t);
          EXPECT_EQ(fb.k, gb.k);
          ++checked;
        }
      }
    }
  }
  EXPECT_GT(same_span, 2000u);  // the lanes themselves were exercised, not only the fallback
  EXPECT_GT(checked, 20000u);
}

TEST(NurbsEval, DerivativesMatchFiniteDifferences) {
  for (const NurbsCurve& c : {nurbs_xy(), random_curve(15, 3, 11), random_curve(12, 5, 12), quarter_circle(3)}) {
    const NurbsView v = c.view();
    const double h = 1e-5;
    for (int i = 1; i < 200; ++i) {
      double u = v.u_min() + (v.u_max() - v.u_min()) * (i + 0.37) / 201.0;
      // Stay inside one span so the difference quotients see a polynomial piece.
      const int span = find_span(v, u);
      if (u - h < c.knots[span] || u + h >= c.knots[span + 1]) continue;
      const NurbsEval e = nurbs_eval(v, u);
      const Vec3 fp = nurbs_point(v, u + h), fm = nurbs_point(v, u - h), f0 = nurbs_point(v, u);
      const Vec3 d1 = (1.0 / (2 * h)) * (fp - fm);
      const Vec3 d2 = (1.0 / (h * h)) * (fp - 2.0 * f0 + fm);
      const double scale1 = 1.0 + norm(e.d1);
      const double scale2 = 1.0 + norm(e.d2);
      EXPECT_NEAR(norm(e.d1 - d1) / scale1, 0.0, 1e-7) << u;
      EXPECT_NEAR(norm(e.d2 - d2) / scale2, 0.0, 1e-3) << u;
    }
  }
}

TEST(NurbsEval, DoubledStartPointStillHasATangent) {
  // trident-xy.ngc starts at X10 Y0 and repeats it as the first listed point: C'(0) = 0.
  const NurbsCurve c = make_nurbs(
      {{10, 0, 0}, {10, 0, 0}, {20, 20, 0}, {12, 8, 0}, {10, 20, 0}, {8, 8, 0}, {0, 20, 0}, {10, 0, 0}},
      std::vector<double>(8, 1.0), 4);
  ASSERT_EQ(validate(c), "");
  EXPECT_NEAR(norm(nurbs_eval(c.view(), 0.0).d1), 0.0, 1e-12);
  const Vec3 t = nurbs_tangent(c.view(), 0.0, true);
  const Vec3 toward = normalized(Vec3{20, 20, 0} - Vec3{10, 0, 0});
  EXPECT_NEAR(dot(t, toward), 1.0, 1e-12);
  const Vec3 probe = normalized(nurbs_point(c.view(), 1e-4) - nurbs_point(c.view(), 0.0));
  EXPECT_NEAR(dot(t, probe), 1.0, 1e-6);
}

double max_deviation(const NurbsCurve& a, const NurbsCurve& b, double u0, double u1, int samples = 2000) {
  double worst = 0.0;
  for (int i = 0; i <= samples; ++i) {
    const double u = u0 + (u1 - u0) * i / samples;
    worst = std::max(worst, norm(nurbs_point(a.view(), u) - nurbs_point(b.view(), u)));
  }
  return worst;
}

TEST(NurbsKnotInsertion, LeavesCurveUnchanged) {
  for (const NurbsCurve& c : {nurbs_xy(), random_curve(14, 3, 21), random_curve(10, 5, 22), full_circle(5)}) {
    NurbsCurve d = insert_knot(c, c.u_min() + 0.37 * (c.u_max() - c.u_min()));
    d = insert_knot(d, c.u_min() + 0.81 * (c.u_max() - c.u_min()), 2);
    // An existing knot, raised by one (still at most the degree, so still valid).
    const double existing = c.knots[static_cast<std::size_t>(c.degree + 1)];
    d = insert_knot(d, existing);
    EXPECT_EQ(d.points.size(), c.points.size() + 4);
    if (std::count(c.knots.begin(), c.knots.end(), existing) < c.degree) {
      EXPECT_EQ(validate(d), "");
    }
    EXPECT_LT(max_deviation(c, d, c.u_min(), c.u_max()), 1e-9);
  }
}

TEST(NurbsSplit, PiecesFitABlockAndReproduceTheCurve) {
  for (int degree = 1; degree <= 5; ++degree) {
    const NurbsCurve c = random_curve(100, degree, 30 + static_cast<unsigned>(degree));
    const std::vector<NurbsCurve> pieces = split_for_blocks(c);
    ASSERT_GT(pieces.size(), 1u);
    double u = c.u_min();
    for (std::size_t i = 0; i < pieces.size(); ++i) {
      const NurbsCurve& q = pieces[i];
      EXPECT_EQ(validate(q), "") << i;
      EXPECT_LE(q.points.size(), static_cast<std::size_t>(kMaxNurbsPoints));
      EXPECT_EQ(q.u_min(), u);  // consecutive, no gap
      u = q.u_max();
      EXPECT_LT(max_deviation(c, q, q.u_min(), q.u_max(), 500), 1e-9) << "degree " << degree << " piece " << i;
      if (i + 1 < pieces.size() && degree >= 2) {
        // Pieces join with the curve's continuity: same point, same first derivative.
        const NurbsEval end = nurbs_eval(q.view(), q.u_max());
        const NurbsEval start = nurbs_eval(pieces[i + 1].view(), q.u_max());
        EXPECT_LT(norm(end.p - start.p), 1e-9);
        EXPECT_LT(norm(end.d1 - start.d1), 1e-9 * (1 + norm(end.d1)));
        if (degree >= 3) {
          EXPECT_LT(norm(end.d2 - start.d2), 1e-7 * (1 + norm(end.d2)));
        }
      }
    }
    EXPECT_EQ(u, c.u_max());
  }
}

TEST(NurbsSplit, CurveThatFitsStaysWholeAndCornersAreCut) {
  const NurbsCurve xy = nurbs_xy();
  EXPECT_EQ(split_for_blocks(xy).size(), 1u);
  // Degree 1: a polyline; every interior knot is a corner.
  const NurbsCurve poly = make_nurbs({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {2, 1, 0}}, {1, 1, 1, 1}, 2);
  const auto lines = split_for_blocks(poly);
  ASSERT_EQ(lines.size(), 3u);
  for (const auto& l : lines) EXPECT_EQ(l.points.size(), 2u);
  // Degree 2 with a double knot at a real corner.
  NurbsCurve kink;
  kink.degree = 2;
  kink.points = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {2, 1, 0}, {2, 2, 0}};
  kink.weights = {1, 1, 1, 1, 1};
  kink.knots = {0, 0, 0, 1, 1, 2, 2, 2};
  ASSERT_EQ(validate(kink), "");
  EXPECT_EQ(corner_knots(kink), (std::vector<double>{1.0}));
  EXPECT_EQ(split_for_blocks(kink).size(), 2u);
  // The full circle has double knots but no corner: one piece.
  EXPECT_EQ(split_for_blocks(full_circle(4)).size(), 1u);
}

TEST(NurbsGeometry, RoundTripThroughBlock) {
  const NurbsCurve c = random_curve(32, 3, 40);
  Block b;
  ASSERT_EQ(to_geometry(c, b.nurbs), "");
  EXPECT_EQ(b.nurbs.point_count, 32);
  EXPECT_EQ(b.nurbs.knot_count, 36);
  const NurbsCurve back = from_geometry(b.nurbs);
  EXPECT_EQ(back.points, c.points);
  EXPECT_EQ(back.knots, c.knots);
  EXPECT_EQ(back.weights, c.weights);
  for (double u : {0.0, 1.3, 17.9, 29.0}) {
    EXPECT_EQ(nurbs_point(view_of(b.nurbs), u), nurbs_point(c.view(), u));
  }
  EXPECT_NE(to_geometry(random_curve(33, 3, 41), b.nurbs).find("at most 32"), std::string::npos);
}

TEST(NurbsValidate, NamesEachError) {
  auto expect_error = [](const NurbsCurve& c, const std::string& words) {
    const std::string err = validate(c);
    EXPECT_NE(err.find(words), std::string::npos) << "got: '" << err << "', wanted '" << words << "'";
  };
  const NurbsCurve good = nurbs_xy();
  ASSERT_EQ(validate(good), "");

  NurbsCurve c = good;
  c.degree = 0;
  expect_error(c, "order 1 out of range");
  c.degree = 6;
  expect_error(c, "order 7 out of range");

  c = make_nurbs({{0, 0, 0}, {1, 0, 0}, {2, 1, 0}}, {1, 1, 1}, 4);
  expect_error(c, "needs at least 4 control points, got 3");

  c = good;
  c.weights[2] = 0.0;
  expect_error(c, "weight of control point 3 is 0");
  c.weights[2] = -1.5;
  expect_error(c, "weights must be > 0");
  c = good;
  c.weights.pop_back();
  expect_error(c, "4 weights for 5 control points");

  c = good;
  c.knots.pop_back();
  expect_error(c, "needs 8 knots");
  c = good;
  c.knots = {0, 0, 0, 2, 1, 3, 3, 3};
  expect_error(c, "must not decrease");
  c = good;
  c.knots = {0, 0, 0, 0, 0, 0, 0, 0};
  expect_error(c, "empty parameter range");
  c = good;
  c.knots = {0, 0, 1, 1, 2, 3, 3, 3};
  expect_error(c, "clamped");
  c = make_nurbs({{0, 0, 0}, {1, 0, 0}, {2, 1, 0}, {3, 1, 0}, {4, 0, 0}, {5, 0, 0}}, std::vector<double>(6, 1), 3);
  c.knots = {0, 0, 0, 1, 1, 1, 2, 2, 2};
  expect_error(c, "repeats 3 times");
  c = good;
  c.points[1][0] = NAN;
  expect_error(c, "control point 2 is not a finite number");
}

// ---- the seed's rough interpolation and the offline tool --------------------------------

TEST(NurbsRough, QuarterCircleWithinToleranceWithFewSegments) {
  const double r = 10.0, tol = 0.001;
  const NurbsCurve c = quarter_circle(r);
  // Feed steps of 0.5 mm: every chord error is within the tolerance, measured densely.
  const RoughPolyline rough = rough_interpolate(c, 0.5, tol);
  EXPECT_LE(rough.max_deviation_mm, tol);
  EXPECT_EQ(rough.segments + 1, rough.points.size());
  for (std::size_t i = 0; i < rough.points.size(); ++i) EXPECT_NEAR(norm(rough.points[i]), r, 1e-11);
  EXPECT_EQ(rough.params.back(), 1.0);
  // Bisection alone: between the fewest possible chords and twice that many.
  const double max_angle = 2.0 * std::acos(1.0 - tol / r);
  const auto fewest = static_cast<std::size_t>(std::ceil((M_PI / 2) / max_angle));
  const RoughPolyline cam = rough_interpolate(c, 100.0, tol);
  EXPECT_LE(cam.max_deviation_mm, tol);
  EXPECT_GE(cam.segments, fewest);
  EXPECT_LE(cam.segments, 2 * fewest);
  // The measured deviation is real: a coarse polyline is reported above the tolerance.
  EXPECT_GT(polyline_deviation(c, {0.0, 1.0}, {c.points.front(), c.points.back()}), r * (1 - kS) - 1e-9);
}

TEST(NurbsReader, ReadsLinuxCncG52Programs) {
  const std::string dir = test::shared_dir() + "/gcode/nurbs/g5.2/";
  const NurbsProgram xy = read_nurbs_program(dir + "nurbs-xy.ngc");
  ASSERT_EQ(xy.error, "");
  ASSERT_EQ(xy.curves.size(), 1u);
  const NurbsCurve& c = xy.curves[0].curve;
  EXPECT_EQ(c.degree, 2);
  EXPECT_EQ(c.points, (std::vector<Vec3>{{0, 0, 0}, {0, 1, 0}, {2, 2, 0}, {2, 0, 0}, {0, 0, 0}}));
  EXPECT_EQ(c.weights, (std::vector<double>{1, 1, 1, 1, 2}));
  EXPECT_EQ(c.knots, open_uniform_knots(5, 2));
  EXPECT_NEAR(xy.curves[0].feed_mm_s, 100.0 / 60.0, 1e-12);

  // Three planes: XY (G17), YZ (G19) and ZX (G18, first axis Z), order 4, doubled start.
  const NurbsProgram tri = read_nurbs_program(dir + "trident-xy-yz-zx.ngc");
  ASSERT_EQ(tri.error, "");
  ASSERT_EQ(tri.curves.size(), 3u);
  for (const ProgramCurve& pc : tri.curves) {
    EXPECT_EQ(pc.curve.degree, 3);
    EXPECT_EQ(pc.curve.points.size(), 8u);
    EXPECT_EQ(pc.curve.points[0], pc.curve.points[1]);
  }
  EXPECT_EQ(tri.curves[0].curve.points[2], (Vec3{20, 20, 0}));
  EXPECT_EQ(tri.curves[1].curve.points[2], (Vec3{0, 20, 20}));  // Y20 Z20 at X0
  EXPECT_EQ(tri.curves[2].curve.points[2], (Vec3{20, 0, 20}));  // Z20 X20 at Y0
  EXPECT_EQ(tri.curves[2].curve.points[3], (Vec3{8, 0, 12}));   // Z12 X8

  EXPECT_NE(parse_nurbs_program("G0 X0 Y0\nF60\nG5.2 L3\nX1 Y1\nG5.3\n").error.find("line 4: control point without its weight P"),
            std::string::npos);
  EXPECT_NE(parse_nurbs_program("G5.3\n").error.find("G5.3 without an open G5.2"), std::string::npos);
  EXPECT_NE(parse_nurbs_program("G5.2 L7\nX1 Y0 P1\nX2 Y0 P1\nG5.3\n").error.find("order 7 out of range"),
            std::string::npos);
  EXPECT_NE(parse_nurbs_program("G5.2 L4\nX1 Y0 P1\nX2 Y0 P1\nG5.3\n").error.find("at least 4 control points"),
            std::string::npos);
  EXPECT_NE(parse_nurbs_program("G5.2\nX1 Y0 P-1\nX2 Y0 P1\nG5.3\n").error.find("weights must be > 0"),
            std::string::npos);
  EXPECT_NE(parse_nurbs_program("G5.2\nX1 Y0 Z3 P1\nG5.3\n").error.find("not in the NURBS plane"), std::string::npos);
}

TEST(NurbsTool, PrintsTheRoughInterpolationOfEachCurve) {
  NurbsToolOptions o;
  o.file = test::shared_dir() + "/gcode/nurbs/g5.2/leto-xy.ngc";
  o.config_path = test::default_config();
  o.tolerance_mm = 0.001;
  std::ostringstream out, err;
  ASSERT_EQ(run_nurbs_rough(o, out, err), 0) << err.str();
  const std::string text = out.str();
  EXPECT_NE(text.find("curve 1 (line 14): order 3, 12 control points"), std::string::npos) << text;
  EXPECT_NE(text.find("rough interpolation: "), std::string::npos);
  EXPECT_NE(text.find("direct NURBS: 1 G5.2 block (1 ring block)"), std::string::npos);
  // The max deviation printed is within the tolerance.
  const std::size_t at = text.find("max deviation ");
  ASSERT_NE(at, std::string::npos);
  EXPECT_LE(std::stod(text.substr(at + 14)), 0.001);

  o.file = test::shared_dir() + "/gcode/nurbs/g5.2/does-not-exist.ngc";
  std::ostringstream out2, err2;
  EXPECT_EQ(run_nurbs_rough(o, out2, err2), 2) << "a program that cannot be read: bad input";
  EXPECT_NE(err2.str().find("cannot read"), std::string::npos);
}

}  // namespace
}  // namespace pcnc
