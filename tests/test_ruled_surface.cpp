// test_ruled_surface.cpp — the ruled-surface library (issue 17, item 1) against independent
// computations: Ferguson segments reproduce a cubic; the NURBS third derivative against
// nurbs_eval and finite differences; the spherical ruling against finite differences of
// eq. (10); every curvature function against its defining property (Frenet-like equations of
// the trihedron, the striction point as the foot of the common perpendicular of neighbouring
// rulings, the distribution parameter as distance over angle) and finite differences; the
// closed forms of a cone, a helicoid, a hyperboloid of one sheet and a cylinder; eq. (21) and
// the seed's angular route (eqs. 23-26) against the per-u route.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <vector>

#include "geometry/cusp.hpp"
#include "geometry/hermite_curve.hpp"
#include "geometry/nurbs.hpp"
#include "geometry/nurbs_jet.hpp"
#include "geometry/ruled_motion.hpp"
#include "geometry/ruled_surface.hpp"
#include "geometry/spherical_curve.hpp"

namespace pcnc {
namespace {

constexpr double kH = 1e-3;  // finite-difference step in u (fourth-order differences below)

// |a - b| <= rel * max(|b|, floor) component-wise in norm.
::testing::AssertionResult Near(const Vec3& a, const Vec3& b, double rel, double floor = 1.0) {
  const double err = norm(a - b), scale = std::max(norm(b), floor);
  if (err <= rel * scale) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "(" << a[0] << ", " << a[1] << ", " << a[2] << ") vs (" << b[0] << ", "
                                       << b[1] << ", " << b[2] << "): error " << err << " > " << rel * scale;
}
::testing::AssertionResult NearS(double a, double b, double rel, double floor = 1.0) {
  return Near({a, 0, 0}, {b, 0, 0}, rel, floor);
}

// Fourth-order central difference of a vector function of u (error O(h^4), about 1e-12).
Vec3 fd(const std::function<Vec3(double)>& f, double u, double h = kH) {
  return (1.0 / (12.0 * h)) * (8.0 * (f(u + h) - f(u - h)) - (f(u + 2 * h) - f(u - 2 * h)));
}
double fds(const std::function<double(double)>& f, double u, double h = kH) {
  return (8.0 * (f(u + h) - f(u - h)) - (f(u + 2 * h) - f(u - 2 * h))) / (12.0 * h);
}

// A general piece: Ferguson directrix and a Ferguson (theta, phi) ruling away from the pole.
const HermiteSegment kDirectrix{{0, 0, 0}, {10, 4, 2}, {12, -3, 5}, {8, 6, -4}};
const HermiteSegment kAngles{{0.3, 0.4, 0}, {1.1, 0.7, 0}, {0.5, 0.2, 0}, {-0.3, 0.4, 0}};

RuledCurves general_piece() {
  RuledCurves r;
  r.directrix = CurveSource::of(HermiteView{&kDirectrix, 1});
  r.ruling = CurveSource::of(HermiteView{&kAngles, 1});
  r.form = RulingForm::kAngles;
  return r;
}

Vec3 sphere(double th, double ph) { return {std::cos(th) * std::sin(ph), std::sin(th) * std::sin(ph), std::cos(ph)}; }

// ---- curves -----------------------------------------------------------------------------

TEST(RuledHermite, ReproducesACubicAndItsDerivatives) {
  // q(u) = a + b u + c u^2 + d u^3, written independently; Hermite data from its ends.
  const Vec3 a{1, -2, 3}, b{0.5, 4, -1}, c{2, -3, 0.5}, d{-1, 1.5, 2};
  auto q = [&](double u) { return a + u * b + (u * u) * c + (u * u * u) * d; };
  auto q1 = [&](double u) { return b + (2 * u) * c + (3 * u * u) * d; };
  const HermiteSegment s{q(0), q(1), q1(0), q1(1)};
  for (double u : {0.0, 0.13, 0.5, 0.87, 1.0}) {
    const CurveJet j = hermite_jet(s, u);
    EXPECT_TRUE(Near(j.p, q(u), 1e-14));
    EXPECT_TRUE(Near(j.d1, q1(u), 1e-14));
    EXPECT_TRUE(Near(j.d2, 2.0 * c + (6 * u) * d, 1e-14));
    EXPECT_TRUE(Near(j.d3, 6.0 * d, 1e-14));
  }
}

TEST(RuledHermite, SplineThroughPointsIsC1AndPiecewise) {
  const std::vector<Vec3> pts{{0, 0, 0}, {1, 2, 0}, {3, 2, 1}, {4, 0, 1}};
  const std::vector<Vec3> tan = catmull_rom_tangents(pts);
  EXPECT_TRUE(Near(tan[1], {1.5, 1, 0.5}, 1e-15));
  const std::vector<HermiteSegment> segs = hermite_through(pts, tan);
  ASSERT_EQ(segs.size(), 3u);
  const HermiteView v{segs.data(), 3};
  for (int i = 0; i < 4; ++i) EXPECT_TRUE(Near(hermite_jet(v, i).p, pts[static_cast<std::size_t>(i)], 1e-14));
  // C1 at the joins: left and right derivatives agree.
  for (int i = 1; i < 3; ++i) {
    const CurveJet left = hermite_jet(segs[static_cast<std::size_t>(i - 1)], 1.0);
    EXPECT_TRUE(Near(left.d1, hermite_jet(v, i).d1, 1e-14));
  }
  EXPECT_THROW(hermite_through(pts, {tan[0]}), std::invalid_argument);
}

NurbsCurve test_nurbs() {
  NurbsCurve c;
  c.degree = 3;
  c.points = {{0, 0, 0}, {2, 5, 1}, {5, 6, -1}, {8, 2, 2}, {10, 4, 0}, {13, 1, 1}};
  c.weights = {1, 0.7, 1.6, 0.9, 1.3, 1};
  c.knots = {0, 0, 0, 0, 0.8, 1.7, 3, 3, 3, 3};
  return c;
}

TEST(RuledNurbsJet, AgreesWithNurbsEvalAndFiniteDifferences) {
  const NurbsCurve c = test_nurbs();
  ASSERT_EQ(validate(c), "");
  const NurbsView v = c.view();
  for (double u : {0.1, 0.5, 1.2, 2.0, 2.9}) {
    const CurveJet j = nurbs_jet(v, u);
    const NurbsEval e = nurbs_eval(v, u);  // the existing evaluator, an independent code path
    EXPECT_TRUE(Near(j.p, e.p, 1e-13));
    EXPECT_TRUE(Near(j.d1, e.d1, 1e-12));
    EXPECT_TRUE(Near(j.d2, e.d2, 1e-12));
    const Vec3 d3 = fd([&](double x) { return nurbs_eval(v, x).d2; }, u);
    EXPECT_TRUE(Near(j.d3, d3, 1e-6));
  }
}

TEST(RuledNurbsJet, PolynomialOfDegreeTwoHasNoThirdDerivative) {
  NurbsCurve c;
  c.degree = 2;
  c.points = {{0, 0, 0}, {1, 2, 0}, {3, 1, 1}, {4, 3, 0}};
  c.weights = {1, 1, 1, 1};
  c.knots = {0, 0, 0, 0.4, 1, 1, 1};
  const CurveJet j = nurbs_jet(c.view(), 0.7);
  EXPECT_LT(norm(j.d3), 1e-12);
  EXPECT_TRUE(Near(j.d2, fd([&](double x) { return nurbs_eval(c.view(), x).d1; }, 0.7), 1e-8));
}

TEST(RuledSphericalCurve, AnglesJetMatchesEq10AndItsDifferences) {
  const HermiteView av{&kAngles, 1};
  auto e_of = [&](double u) {
    const Vec3 a = hermite_jet(av, u).p;
    return sphere(a[0], a[1]);
  };
  for (double u : {0.05, 0.4, 0.75}) {
    const CurveJet e = sphere_point_jet(hermite_jet(av, u));
    EXPECT_NEAR(norm(e.p), 1.0, 1e-15);
    EXPECT_TRUE(Near(e.p, e_of(u), 1e-15));
    EXPECT_TRUE(Near(e.d1, fd(e_of, u), 1e-7));
    EXPECT_TRUE(Near(e.d2, fd([&](double x) { return sphere_point_jet(hermite_jet(av, x)).d1; }, u), 1e-7));
    EXPECT_TRUE(Near(e.d3, fd([&](double x) { return sphere_point_jet(hermite_jet(av, x)).d2; }, u), 1e-7));
    // |e| = 1 differentiated: e.e' = 0.
    EXPECT_NEAR(dot(e.p, e.d1), 0.0, 1e-14);
  }
}

TEST(RuledSphericalCurve, NormalisedVectorJetMatchesDifferences) {
  const NurbsCurve c = test_nurbs();
  auto e_of = [&](double u) { return normalized(nurbs_eval(c.view(), u).p + Vec3{1, 1, 1}); };
  for (double u : {0.3, 1.4, 2.6}) {
    CurveJet r = nurbs_jet(c.view(), u);
    r.p = r.p + Vec3{1, 1, 1};  // keep |r| > 0
    const CurveJet e = unit_vector_jet(r);
    EXPECT_TRUE(Near(e.p, e_of(u), 1e-15));
    EXPECT_TRUE(Near(e.d1, fd(e_of, u), 1e-7));
    auto d1_of = [&](double x) {
      CurveJet q = nurbs_jet(c.view(), x);
      q.p = q.p + Vec3{1, 1, 1};
      return unit_vector_jet(q);
    };
    EXPECT_TRUE(Near(e.d2, fd([&](double x) { return d1_of(x).d1; }, u), 1e-7));
    EXPECT_TRUE(Near(e.d3, fd([&](double x) { return d1_of(x).d2; }, u), 1e-7));
  }
}

TEST(RuledSphericalCurve, AnglesRoundTripAndUnwrap) {
  for (double th : {-2.5, -0.3, 0.0, 1.0, 3.0})
    for (double ph : {0.2, 1.0, 2.9}) {
      const Vec3 a = sphere_angles(sphere(th, ph));
      EXPECT_NEAR(a[0], th, 1e-12);
      EXPECT_NEAR(a[1], ph, 1e-12);
    }
  // Crossing theta = pi: the raw angles jump by 2 pi, the unwrapped ones do not.
  const std::vector<Vec3> ev{sphere(3.0, 0.5), sphere(3.1, 0.5), sphere(-3.1, 0.5), sphere(-3.0, 0.5)};
  const std::vector<Vec3> a = sphere_angles_unwrapped(ev);
  EXPECT_NEAR(a[2][0], 2 * M_PI - 3.1, 1e-12);
  EXPECT_NEAR(a[3][0], 2 * M_PI - 3.0, 1e-12);
  for (std::size_t i = 0; i < ev.size(); ++i) EXPECT_TRUE(Near(sphere(a[i][0], a[i][1]), ev[i], 1e-14));
}

// ---- curvature functions ----------------------------------------------------------------

TEST(RuledInvariants, SphericalArcLengthRateAndGeodesicCurvatureFromUDifferences) {
  const RuledCurves r = general_piece();
  auto e_of = [&](double u) { return ruled_jet(r, u).e.p; };
  for (double u : {0.1, 0.5, 0.9}) {
    const RuledInvariants k = ruled_invariants(ruled_jet(r, u));
    ASSERT_TRUE(k.regular);
    // ds/du from the spherical arc length of eq. (19) by differences.
    const Vec3 ang = hermite_jet(HermiteView{&kAngles, 1}, u).d1;
    const double phi = hermite_jet(HermiteView{&kAngles, 1}, u).p[1];
    EXPECT_TRUE(NearS(k.ds_du, std::sqrt(ang[1] * ang[1] + std::sin(phi) * std::sin(phi) * ang[0] * ang[0]), 1e-14));
    EXPECT_TRUE(NearS(k.ds_du, norm(fd(e_of, u)), 1e-7));
    EXPECT_TRUE(NearS(k.d2s_du2, fds([&](double x) { return ruled_invariants(ruled_jet(r, x)).ds_du; }, u), 1e-6));
    EXPECT_TRUE(NearS(k.d3s_du3, fds([&](double x) { return ruled_invariants(ruled_jet(r, x)).d2s_du2; }, u), 1e-6));
    // gamma = det(e, e_u, e_uu) / |e_u|^3 with e_u, e_uu by differences of e.
    const Vec3 eu = fd(e_of, u);
    const double h = 1e-4;
    const Vec3 euu = (1.0 / (h * h)) * (e_of(u + h) - 2.0 * e_of(u) + e_of(u - h));
    EXPECT_TRUE(NearS(k.gamma, det3(e_of(u), eu, euu) / std::pow(norm(eu), 3), 1e-6));
  }
}

TEST(RuledInvariants, TrihedronObeysItsFrenetEquations) {
  // e' = t, t' = -e + gamma g, g' = -gamma t (primes d/ds = (1/s_u) d/du).
  const RuledCurves r = general_piece();
  auto inv = [&](double u) { return ruled_invariants(ruled_jet(r, u)); };
  for (double u : {0.2, 0.6}) {
    const RuledInvariants k = inv(u);
    EXPECT_NEAR(dot(k.e, k.t), 0.0, 1e-14);
    EXPECT_NEAR(norm(k.t), 1.0, 1e-14);
    EXPECT_NEAR(det3(k.e, k.t, k.g), 1.0, 1e-14);
    const double su = k.ds_du;
    EXPECT_TRUE(Near((1 / su) * fd([&](double x) { return inv(x).e; }, u), k.t, 1e-7));
    EXPECT_TRUE(Near((1 / su) * fd([&](double x) { return inv(x).t; }, u), -1.0 * k.e + k.gamma * k.g, 1e-7));
    EXPECT_TRUE(Near((1 / su) * fd([&](double x) { return inv(x).g; }, u), -k.gamma * k.t, 1e-7));
  }
}

// The feet of the common perpendicular of two lines x = c0 + v e0 and x = c1 + w e1: the foot
// on the first and the distance (independent of the library: two linear equations).
struct Perpendicular {
  Vec3 foot;
  double distance;
};
Perpendicular common_perpendicular(const Vec3& c0, const Vec3& e0, const Vec3& c1, const Vec3& e1) {
  const Vec3 d = c1 - c0;
  const double a = dot(e0, e0), b = dot(e0, e1), c = dot(e1, e1), p = dot(e0, d), q = dot(e1, d);
  const double den = a * c - b * b;
  const double v = (p * c - b * q) / den, w = (b * p - a * q) / den;
  const Vec3 x0 = c0 + v * e0, x1 = c1 + w * e1;
  return {x0, norm(x1 - x0)};
}

TEST(RuledInvariants, StrictionPointAndDistributionParameterAreLimitsOfNeighbouringRulings) {
  const RuledCurves r = general_piece();
  for (double u : {0.15, 0.5, 0.85}) {
    const RuledJet j = ruled_jet(r, u);
    const RuledInvariants k = ruled_invariants(j);
    const double h = 1e-5;
    const RuledJet a = ruled_jet(r, u - h), b = ruled_jet(r, u + h);
    const Perpendicular cp = common_perpendicular(a.c.p, a.e.p, b.c.p, b.e.p);
    // The foot on the ruling at u - h tends to the striction point at u (error O(h)).
    EXPECT_TRUE(Near(cp.foot, k.striction, 1e-4, 10.0));
    EXPECT_TRUE(Near(k.striction, striction_point(j), 1e-12, 10.0));
    // |Delta| = lim distance / angle between the rulings.
    const double angle = std::acos(std::clamp(dot(a.e.p, b.e.p), -1.0, 1.0));
    EXPECT_TRUE(NearS(std::abs(k.Delta), cp.distance / angle, 1e-5));
    EXPECT_TRUE(NearS(k.Delta, distribution_parameter(j), 1e-12));
    // The striction curve's tangent has no t component, and b' = Gamma e + Delta g.
    auto b_of = [&](double x) { return ruled_invariants(ruled_jet(r, x)).striction; };
    const Vec3 db = (1 / k.ds_du) * fd(b_of, u);
    EXPECT_NEAR(dot(db, k.t), 0.0, 1e-6 * norm(db));
    EXPECT_TRUE(Near(db, k.Gamma * k.e + k.Delta * k.g, 1e-6));
  }
}

TEST(RuledInvariants, DerivativesOfTheCurvatureFunctionsMatchDifferences) {
  const RuledCurves r = general_piece();
  auto inv = [&](double u) { return ruled_invariants(ruled_jet(r, u)); };
  for (double u : {0.25, 0.7}) {
    const RuledInvariants k = inv(u);
    const double su = k.ds_du;
    auto d_ds = [&](double (*get)(const RuledInvariants&)) {
      return fds([&](double x) { return get(inv(x)); }, u) / su;
    };
    EXPECT_TRUE(NearS(k.dgamma, d_ds([](const RuledInvariants& q) { return q.gamma; }), 1e-6));
    EXPECT_TRUE(NearS(k.dmu, d_ds([](const RuledInvariants& q) { return q.mu; }), 1e-6));
    EXPECT_TRUE(NearS(k.ddmu, d_ds([](const RuledInvariants& q) { return q.dmu; }), 1e-6));
    EXPECT_TRUE(NearS(k.dGamma, d_ds([](const RuledInvariants& q) { return q.Gamma; }), 1e-6));
    EXPECT_TRUE(NearS(k.dDelta, d_ds([](const RuledInvariants& q) { return q.Delta; }), 1e-6));
    EXPECT_TRUE(NearS(k.ddDelta, d_ds([](const RuledInvariants& q) { return q.dDelta; }), 1e-6));
    EXPECT_TRUE(NearS(k.ddsigma, d_ds([](const RuledInvariants& q) { return q.dsigma; }), 1e-6));
    // sigma' is the derivative of atan2(Delta, mu).
    EXPECT_TRUE(NearS(k.dsigma, d_ds([](const RuledInvariants& q) { return std::atan2(q.Delta, q.mu); }), 1e-6));
  }
}

TEST(RuledInvariants, DirectrixDerivativesInTheTrihedronAreEq21) {
  const RuledCurves r = general_piece();
  for (double u : {0.1, 0.45, 0.95}) {
    const RuledJet j = ruled_jet(r, u);
    const RuledInvariants k = ruled_invariants(j);
    const SeedMotionTerms s = seed_motion_terms(k, {});
    // dc/ds by differences of c along u.
    auto c_of = [&](double x) { return ruled_jet(r, x).c.p; };
    EXPECT_TRUE(Near(s.dc_ds, (1 / k.ds_du) * fd(c_of, u), 1e-7));
    EXPECT_TRUE(Near(s.dc_ds, k.dc_ds, 1e-12));
    EXPECT_TRUE(Near(s.d2c_ds2, k.d2c_ds2, 1e-10));
    auto cs_of = [&](double x) { return ruled_invariants(ruled_jet(r, x)).dc_ds; };
    EXPECT_TRUE(Near(k.d2c_ds2, (1 / k.ds_du) * fd(cs_of, u), 1e-6));
  }
}

// ---- closed forms -----------------------------------------------------------------------

// Analytic jets of a circle of radius a in the plane z = z0, and of a constant vector.
CurveJet circle_jet(double a, double u, double z0 = 0.0) {
  const double c = std::cos(u), s = std::sin(u);
  return {{a * c, a * s, z0}, {-a * s, a * c, 0}, {-a * c, -a * s, 0}, {a * s, -a * c, 0}};
}

TEST(RuledClosedForm, ConeHasItsStrictionAtTheApexAndIsDevelopable) {
  // Directrix any Ferguson curve; ruling the unit vector from the apex: the same Ferguson
  // data shifted by the apex, given as a vector curve (normalised).
  const Vec3 apex{3, -2, 15};
  const HermiteSegment ruling{kDirectrix.p0 - apex, kDirectrix.p1 - apex, kDirectrix.t0, kDirectrix.t1};
  RuledCurves r;
  r.directrix = CurveSource::of(HermiteView{&kDirectrix, 1});
  r.ruling = CurveSource::of(HermiteView{&ruling, 1});
  r.form = RulingForm::kVector;
  for (double u : {0.0, 0.3, 0.6, 1.0}) {
    const RuledInvariants k = ruled_invariants(ruled_jet(r, u));
    ASSERT_TRUE(k.regular);
    EXPECT_TRUE(Near(k.striction, apex, 1e-12, 10.0));
    EXPECT_NEAR(k.Delta, 0.0, 1e-12);
    EXPECT_NEAR(k.dDelta, 0.0, 1e-11);
    // The striction curve stands still: b' = Gamma e + Delta g = 0.
    EXPECT_NEAR(k.Gamma, 0.0, 1e-10);
    // mu = |c - apex|: c = apex + mu e.
    EXPECT_NEAR(k.mu, norm(ruled_jet(r, u).c.p - apex), 1e-12);
  }
}

TEST(RuledClosedForm, TangentDevelopableOfAHelixHasItsEdgeAsStrictionCurve) {
  // c = (a cos u, a sin u, b u), e = c_u / |c_u|: developable (Delta = 0), and the striction
  // curve is the edge of regression, the helix itself (mu = 0). The unit tangent of a helix
  // is a small circle on the sphere: e = (-a sin u, a cos u, b) / L.
  const double a = 3.0, b = 1.2, L = std::hypot(a, b);
  for (double u : {0.0, 0.9, 2.2}) {
    RuledJet j;
    j.c = circle_jet(a, u, b * u);
    j.c.d1[2] = b;
    const double cu = std::cos(u), su = std::sin(u);
    j.e = {{-a * su / L, a * cu / L, b / L}, {-a * cu / L, -a * su / L, 0}, {a * su / L, -a * cu / L, 0},
           {a * cu / L, a * su / L, 0}};
    const RuledInvariants k = ruled_invariants(j);
    EXPECT_NEAR(k.Delta, 0.0, 1e-14);
    EXPECT_NEAR(k.mu, 0.0, 1e-14);
    EXPECT_TRUE(Near(k.striction, j.c.p, 1e-14));
    EXPECT_NEAR(distribution_parameter(j), 0.0, 1e-14);
  }
}

TEST(RuledClosedForm, HelicoidHasDistributionParameterEqualToItsPitchOverTwoPi) {
  // c = (0, 0, b u), e = (cos u, sin u, 0): Delta = b, striction on the axis, gamma = 0.
  const double b = 2.5;
  for (double u : {0.0, 0.7, 2.0}) {
    RuledJet j;
    j.c = {{0, 0, b * u}, {0, 0, b}, {0, 0, 0}, {0, 0, 0}};
    const CurveJet circ = circle_jet(1.0, u);
    j.e = circ;
    const RuledInvariants k = ruled_invariants(j);
    EXPECT_NEAR(k.Delta, b, 1e-14);
    EXPECT_NEAR(k.gamma, 0.0, 1e-14);
    EXPECT_NEAR(k.mu, 0.0, 1e-14);
    EXPECT_TRUE(Near(k.striction, {0, 0, b * u}, 1e-14));
    EXPECT_NEAR(k.ds_du, 1.0, 1e-14);
  }
}

TEST(RuledClosedForm, HyperboloidOfOneSheet) {
  // x^2/a^2 + y^2/a^2 - z^2/c^2 = 1, ruled by c(u) = (a cos u, a sin u, 0) and
  // e = (-a sin u, a cos u, c) / sqrt(a^2 + c^2): the waist circle is the striction curve,
  // the distribution parameter is -c (its magnitude c), the spherical indicatrix a small
  // circle at polar angle phi0 = atan(a / c), geodesic curvature cot(phi0) = c / a.
  const double a = 4.0, cc = 3.0, L = std::hypot(a, cc);
  for (double u : {0.0, 1.0, 2.5}) {
    RuledJet j;
    j.c = circle_jet(a, u);
    const double cu = std::cos(u), su = std::sin(u);
    j.e = {{-a * su / L, a * cu / L, cc / L}, {-a * cu / L, -a * su / L, 0}, {a * su / L, -a * cu / L, 0},
           {a * cu / L, a * su / L, 0}};
    // Every surface point satisfies the quadric.
    for (double v : {-2.0, 0.5, 3.0}) {
      const Vec3 x = ruled_point(j, v);
      EXPECT_NEAR((x[0] * x[0] + x[1] * x[1]) / (a * a) - x[2] * x[2] / (cc * cc), 1.0, 1e-12);
    }
    const RuledInvariants k = ruled_invariants(j);
    EXPECT_NEAR(k.Delta, -cc, 1e-13);
    EXPECT_TRUE(Near(k.striction, j.c.p, 1e-14, 1.0));
    EXPECT_NEAR(k.gamma, cc / a, 1e-13);
    EXPECT_NEAR(k.ds_du, a / L, 1e-14);
    EXPECT_NEAR(k.dgamma, 0.0, 1e-13);
    // The same surface with the ruling in spherical coordinates: theta = u + pi/2, phi = phi0.
    const HermiteSegment ang{{u + M_PI / 2, std::atan2(a, cc), 0}, {u + 1 + M_PI / 2, std::atan2(a, cc), 0},
                             {1, 0, 0}, {1, 0, 0}};
    const CurveJet e2 = sphere_point_jet(hermite_jet(ang, 0.0));
    EXPECT_TRUE(Near(e2.p, j.e.p, 1e-14));
    EXPECT_TRUE(Near(e2.d1, j.e.d1, 1e-14));
    EXPECT_TRUE(Near(e2.d3, j.e.d3, 1e-14));
  }
}

TEST(RuledClosedForm, CylinderHasNoSphericalMotionButTheToolStillMoves) {
  // c = (R cos u, R sin u, 5), e = z constant: ds/du = 0, the s-functions are undefined, and
  // the tool frame (O along the motion) turns about the axis at F / R.
  const double R = 7.0, F = 12.0, dF = 3.0;
  for (double u : {0.0, 1.1, 4.0}) {
    RuledJet j;
    j.c = circle_jet(R, u, 5.0);
    j.e = {{0, 0, 1}, {}, {}, {}};
    const RuledInvariants k = ruled_invariants(j);
    EXPECT_FALSE(k.regular);
    EXPECT_EQ(k.ds_du, 0.0);
    const ToolMotion m = tool_motion(j, u, F, dF);
    ASSERT_TRUE(m.frame_defined);
    const Vec3 tangent{-std::sin(u), std::cos(u), 0}, inward{-std::cos(u), -std::sin(u), 0};
    EXPECT_TRUE(Near(m.O, tangent, 1e-14));
    EXPECT_TRUE(Near(m.N, cross(Vec3{0, 0, 1}, tangent), 1e-14));
    EXPECT_TRUE(Near(m.velocity, F * tangent, 1e-14));
    EXPECT_TRUE(Near(m.acceleration, (F * F / R) * inward + dF * tangent, 1e-13));
    EXPECT_TRUE(Near(m.omega, {0, 0, F / R}, 1e-14));
    EXPECT_TRUE(Near(m.alpha, {0, 0, dF / R}, 1e-13));
  }
}

// ---- the tool's motion ------------------------------------------------------------------

// omega_u of a frame by differences: 1/2 sum f_i x f_i'.
Vec3 frame_rate(const std::function<ToolMotion(double)>& m, double u) {
  const ToolMotion c = m(u);
  auto axis = [&](Vec3 ToolMotion::*f) { return fd([&](double x) { return m(x).*f; }, u); };
  return 0.5 * (cross(c.A, axis(&ToolMotion::A)) + cross(c.O, axis(&ToolMotion::O)) + cross(c.N, axis(&ToolMotion::N)));
}

TEST(RuledToolMotion, FrameAndItsRatesMatchFiniteDifferences) {
  const RuledCurves r = general_piece();
  const double F = 10.0;
  for (bool with_spin : {false, true}) {
    auto spin_at = [&](double u) {
      return with_spin ? SpinJet{0.3 + 0.5 * u + 0.2 * u * u, 0.5 + 0.4 * u, 0.4} : SpinJet{};
    };
    auto m_of = [&](double u) { return tool_motion(ruled_jet(r, u), u, F, 0.0, spin_at(u)); };
    for (double u : {0.1, 0.5, 0.9}) {
      const ToolMotion m = m_of(u);
      ASSERT_TRUE(m.frame_defined);
      EXPECT_NEAR(det3(m.A, m.O, m.N), 1.0, 1e-14);
      EXPECT_NEAR(dot(m.A, m.O), 0.0, 1e-14);
      // O lies in the plane of the motion direction and the axis, turned by eta.
      const Vec3 cu = ruled_jet(r, u).c.d1;
      const Vec3 P = normalized(cu - dot(cu, m.A) * m.A);
      EXPECT_NEAR(dot(m.O, P), std::cos(spin_at(u).eta), 1e-14);
      EXPECT_TRUE(Near(m.omega_u, frame_rate(m_of, u), 1e-7));
      EXPECT_TRUE(Near(m.omega_uu, fd([&](double x) { return m_of(x).omega_u; }, u), 1e-6));
      // Constant feed: |v| = F; alpha = d/du(omega_u F/|c_u|) du/dt, a likewise.
      EXPECT_NEAR(norm(m.velocity), F, 1e-12);
      auto omega_of = [&](double x) { return m_of(x).omega; };
      auto v_of = [&](double x) { return m_of(x).velocity; };
      EXPECT_TRUE(Near(m.alpha, m.du_dt * fd(omega_of, u), 1e-6));
      EXPECT_TRUE(Near(m.acceleration, m.du_dt * fd(v_of, u), 1e-6));
    }
  }
}

TEST(RuledToolMotion, NurbsDirectrixAndNurbsToolVectorsThroughTheSameCalls) {
  // A piece given entirely as NURBS: the directrix and a curve of (unnormalised) tool vectors.
  const NurbsCurve dir = test_nurbs();
  NurbsCurve vec;
  vec.degree = 3;
  vec.points = {{0.2, 0.1, 1}, {0.5, -0.2, 1}, {0.1, 0.4, 0.8}, {-0.3, 0.2, 1.1}, {-0.1, -0.3, 0.9}, {0.3, 0.0, 1}};
  vec.weights = {1, 1.2, 0.8, 1, 1.1, 1};
  vec.knots = dir.knots;  // the same parameter domain [0, 3]
  ASSERT_EQ(validate(vec), "");
  RuledCurves r;
  r.directrix = CurveSource::of(dir.view());
  r.ruling = CurveSource::of(vec.view());
  r.form = RulingForm::kVector;
  EXPECT_DOUBLE_EQ(r.u_max(), 3.0);
  auto m_of = [&](double u) { return tool_motion(ruled_jet(r, u), u, 10.0, 0.0); };
  for (double u : {0.3, 1.2, 2.5}) {
    const RuledJet j = ruled_jet(r, u);
    EXPECT_TRUE(Near(j.c.p, nurbs_eval(dir.view(), u).p, 1e-13));
    EXPECT_TRUE(Near(j.e.p, normalized(nurbs_eval(vec.view(), u).p), 1e-14));
    const ToolMotion m = m_of(u);
    ASSERT_TRUE(m.frame_defined);
    EXPECT_TRUE(Near(m.omega_u, frame_rate(m_of, u), 1e-7));
    EXPECT_TRUE(Near(m.omega_uu, fd([&](double x) { return m_of(x).omega_u; }, u), 1e-6));
    const RuledInvariants k = ruled_invariants(j);
    // Delta changes steeply near u = 0.3 (ds/du = 0.12 there, Delta' = -8648 mm): a finer step.
    EXPECT_TRUE(NearS(
        k.dDelta, fds([&](double x) { return ruled_invariants(ruled_jet(r, x)).Delta; }, u, 1e-4) / k.ds_du, 1e-6));
  }
}

TEST(RuledToolMotion, ChangingFeedMatchesATimeIntegration) {
  // F(t) = F0 + dF t; u(t) from du/dt = F(t) / |c_u(u)| by RK4; v, omega by differences in t.
  const RuledCurves r = general_piece();
  const double F0 = 8.0, dF = 40.0, u0 = 0.4;
  auto udot = [&](double t, double u) { return (F0 + dF * t) / norm(ruled_jet(r, u).c.d1); };
  auto u_at = [&](double t) {
    const int n = 20;
    double u = u0, tt = 0.0;
    const double h = t / n;
    for (int i = 0; i < n; ++i) {
      const double k1 = udot(tt, u), k2 = udot(tt + h / 2, u + h / 2 * k1), k3 = udot(tt + h / 2, u + h / 2 * k2),
                   k4 = udot(tt + h, u + h * k3);
      u += h / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
      tt += h;
    }
    return u;
  };
  auto m_at = [&](double t) {
    const double u = u_at(t);
    return tool_motion(ruled_jet(r, u), u, F0 + dF * t, dF);
  };
  const ToolMotion m = m_at(0.0);
  const double h = 1e-4;
  EXPECT_TRUE(NearS(m.d2u_dt2, (u_at(h) - 2 * u0 + u_at(-h)) / (h * h), 1e-5));
  EXPECT_TRUE(Near(m.velocity, (0.5 / h) * (m_at(h).position - m_at(-h).position), 1e-7));
  EXPECT_TRUE(Near(m.acceleration, (0.5 / h) * (m_at(h).velocity - m_at(-h).velocity), 1e-6));
  EXPECT_TRUE(Near(m.alpha, (0.5 / h) * (m_at(h).omega - m_at(-h).omega), 1e-6, 1e-3));
  EXPECT_TRUE(Near(m.axis_velocity, (0.5 / h) * (m_at(h).A - m_at(-h).A), 1e-7, 1e-3));
  EXPECT_TRUE(Near(m.axis_velocity, cross(m.omega, m.A), 1e-13, 1e-3));
  EXPECT_TRUE(
      Near(m.axis_acceleration, (0.5 / h) * (m_at(h).axis_velocity - m_at(-h).axis_velocity), 1e-6, 1e-3));
  // d2A/dt2 = alpha x A + omega x (omega x A).
  EXPECT_TRUE(Near(m.axis_acceleration, cross(m.alpha, m.A) + cross(m.omega, cross(m.omega, m.A)), 1e-12, 1e-3));
  // Tangential acceleration is the feed's rate.
  EXPECT_NEAR(dot(m.acceleration, normalized(m.velocity)), dF, 1e-10);
}

TEST(RuledToolMotion, SeedRouteThroughTheTrihedronGivesTheSameMotion) {
  // eqs. (25)-(26): v = c' s., a = c' s.. + c'' s.^2, omega = U0 s., alpha = U0 s.. + U0' s.^2
  // with s. = s_u u., s.. = s_uu u.^2 + s_u u.. .
  const RuledCurves r = general_piece();
  for (double u : {0.2, 0.55, 0.8}) {
    const SpinJet spin{0.1, 0.7, -0.3};
    const RuledJet j = ruled_jet(r, u);
    const RuledInvariants k = ruled_invariants(j);
    const ToolMotion m = tool_motion(j, u, 10.0, 2.0, spin);
    const SeedMotionTerms s = seed_motion_terms(k, spin);
    const double sd = k.ds_du * m.du_dt;
    const double sdd = k.d2s_du2 * m.du_dt * m.du_dt + k.ds_du * m.d2u_dt2;
    EXPECT_TRUE(Near(s.dc_ds * sd, m.velocity, 1e-12));
    EXPECT_TRUE(Near(sdd * s.dc_ds + (sd * sd) * s.d2c_ds2, m.acceleration, 1e-10));
    EXPECT_TRUE(Near(sd * s.U0, m.omega, 1e-12));
    EXPECT_TRUE(Near(sdd * s.U0 + (sd * sd) * s.dU0, m.alpha, 1e-10));
  }
}

// ---- the parameter step -----------------------------------------------------------------

std::vector<HermiteSegment> wavy_spline() {
  std::vector<Vec3> pts;
  for (int i = 0; i <= 12; ++i) pts.push_back({10.0 * i, 15.0 * std::sin(0.6 * i), 4.0 * std::cos(0.9 * i)});
  return hermite_through(pts, catmull_rom_tangents(pts));
}

TEST(RuledParameterStep, KeepsTheFeedWithinATenthOfAPercentOverAWholeCurve) {
  const std::vector<HermiteSegment> segs = wavy_spline();
  const CurveSource d = CurveSource::of(HermiteView{segs.data(), static_cast<int>(segs.size())});
  const NurbsCurve nc = test_nurbs();
  const CurveSource dn = CurveSource::of(nc.view());
  // A harsh one: points on a 5 mm circle at uneven angles with Catmull-Rom tangents, whose
  // parametric speed changes sharply within a segment (the Taylor step alone is off by 30 %).
  std::vector<Vec3> ring;
  for (double deg : {0.0, 20.0, 70.0, 95.0, 160.0, 180.0, 250.0, 265.0, 330.0, 360.0})
    ring.push_back({5 * std::cos(deg * M_PI / 180), 5 * std::sin(deg * M_PI / 180), 0.02 * deg});
  const std::vector<HermiteSegment> ring_segs = hermite_through(ring, catmull_rom_tangents(ring));
  const CurveSource dr = CurveSource::of(HermiteView{ring_segs.data(), static_cast<int>(ring_segs.size())});
  for (const CurveSource& src : {d, dn, dr})
    for (double T : {0.0005, 0.01}) {
      const double F = 10.0, dF = 0.0;
      double u = src.u_min(), worst = 0.0, worst_raw = 0.0;
      int steps = 0;
      while (u < src.u_max()) {
        const ParameterStep s = advance_parameter(src, u, F, dF, T, true);
        const ParameterStep raw = advance_parameter(src, u, F, dF, T, false);
        ASSERT_GT(s.u_next, u);
        if (s.u_next >= src.u_max()) break;  // the last, shorter period
        // The chord measured here, independently of the step's own figure.
        const double chord = norm(curve_jet(src, s.u_next).p - curve_jet(src, u).p);
        EXPECT_NEAR(chord, s.chord, 1e-12);
        worst = std::max(worst, std::abs(chord - F * T) / (F * T));
        worst_raw = std::max(worst_raw, std::abs(raw.feed_error()));
        u = s.u_next;
        ++steps;
      }
      EXPECT_GT(steps, 10);
      EXPECT_LT(worst, 1e-3);
      EXPECT_LE(worst, worst_raw);
    }
}

TEST(RuledParameterStep, FollowsAChangingFeed) {
  const std::vector<HermiteSegment> segs = wavy_spline();
  const CurveSource d = CurveSource::of(HermiteView{segs.data(), static_cast<int>(segs.size())});
  const double T = 0.001, dF = 200.0;
  double u = 0.0, F = 2.0;
  for (int i = 0; i < 200; ++i) {
    const ParameterStep s = advance_parameter(d, u, F, dF, T, true);
    EXPECT_NEAR(s.target, F * T + 0.5 * dF * T * T, 1e-15);
    EXPECT_LT(std::abs(s.feed_error()), 1e-3);
    u = s.u_next;
    F += dF * T;
  }
  EXPECT_GT(u, 0.0);
}

// ---- cusp -------------------------------------------------------------------------------

TEST(RuledCusp, PassIntervalByHand) {
  // h = 0.005, R = 1: P = 2 sqrt(0.005 * 1.995) = 2 sqrt(0.009975) = 0.1997498...
  EXPECT_NEAR(pass_interval(0.005, 1.0), 0.19974984355438, 1e-12);
  EXPECT_DOUBLE_EQ(pass_interval(0.0, 3.0), 0.0);
  EXPECT_DOUBLE_EQ(pass_interval(3.0, 3.0), 6.0);  // a full hemisphere deep: the diameter
  // R = 5, h = 1: 2 sqrt(1 * 9) = 6.
  EXPECT_DOUBLE_EQ(pass_interval(1.0, 5.0), 6.0);
  EXPECT_NEAR(cusp_height(6.0, 5.0), 1.0, 1e-15);
  EXPECT_NEAR(cusp_height(pass_interval(0.0123, 2.0), 2.0), 0.0123, 1e-15);
  EXPECT_TRUE(std::isnan(pass_interval(-0.1, 1.0)));
  EXPECT_TRUE(std::isnan(pass_interval(1.5, 1.0)));
  EXPECT_TRUE(std::isnan(pass_interval(0.1, 0.0)));
  EXPECT_TRUE(std::isnan(cusp_height(2.5, 1.0)));
}

}  // namespace
}  // namespace pcnc
