// test_ruled_model.cpp — a ruled-surface piece through set points (ruled_model.hpp, the seed's
// section 4): the three-point chord derivative is exact on parabolas; the piece passes through
// every set point and tool vector; velocity and the tool axis's rate are continuous across set
// points; the model converges to a known ruled surface (a helical sweep) as the set points
// get denser; bad input is refused with a reason.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "geometry/ruled_model.hpp"
#include "geometry/ruled_motion.hpp"
#include "geometry/spherical_curve.hpp"

namespace pcnc {
namespace {

TEST(RuledSetPoints, ChordDerivativesAreExactOnParabolas) {
  const std::vector<double> l{0.0, 0.3, 1.1, 1.5, 3.0};
  const Vec3 a{1, -2, 0.5}, b{0.3, 2, -1}, c{-0.7, 0.25, 2};
  std::vector<Vec3> f;
  for (double x : l) f.push_back(a + x * b + (x * x) * c);
  const std::vector<Vec3> d = chord_derivatives(l, f);
  for (std::size_t i = 0; i < l.size(); ++i) {
    const Vec3 want = b + (2 * l[i]) * c;
    EXPECT_NEAR(norm(d[i] - want), 0.0, 1e-12) << i;
  }
  const std::vector<Vec3> two = chord_derivatives({0.0, 2.0}, {{0, 0, 0}, {2, 4, 6}});
  EXPECT_NEAR(norm(two[0] - Vec3{1, 2, 3}), 0.0, 1e-15);
}

// A helical sweep: c(t) = (R cos t, R sin t, p t), axis tilted toward the helix axis by a
// varying angle: e(t) = (-sin(a) cos t, -sin(a) sin t, cos(a)), a = 0.3 + 0.2 sin t.
constexpr double kR = 10.0, kPitch = 1.5;
Vec3 helix(double t) { return {kR * std::cos(t), kR * std::sin(t), kPitch * t}; }
Vec3 axis(double t) {
  const double a = 0.3 + 0.2 * std::sin(t);
  return {-std::sin(a) * std::cos(t), -std::sin(a) * std::sin(t), std::cos(a)};
}

// Set points at uneven t over [0, 3]: x + 0.04 sin(4 pi x) is increasing (slope 1 +- 0.5)
// and keeps the ends; neighbouring intervals differ by up to a factor of 3.
std::vector<double> uneven_t(int n) {
  std::vector<double> t;
  for (int i = 0; i <= n; ++i) {
    const double x = static_cast<double>(i) / n;
    t.push_back(3.0 * (x + 0.04 * std::sin(4.0 * M_PI * x)));
  }
  return t;
}

TEST(RuledSetPoints, PassesThroughEverySetPointAndToolVector) {
  for (RulingForm form : {RulingForm::kAngles, RulingForm::kVector}) {
    std::vector<Vec3> pts, vecs;
    for (double t : uneven_t(9)) {
      pts.push_back(helix(t));
      vecs.push_back(2.5 * axis(t));  // not unit: normalised by the model
    }
    const RuledModelResult r = ruled_model_through(pts, vecs, form);
    ASSERT_EQ(r.error, "");
    const RuledCurves c = r.model.curves();
    EXPECT_DOUBLE_EQ(c.u_max(), 9.0);
    for (int i = 0; i <= 9; ++i) {
      const RuledJet j = ruled_jet(c, i);
      EXPECT_NEAR(norm(j.c.p - pts[static_cast<std::size_t>(i)]), 0.0, 1e-12);
      EXPECT_NEAR(norm(j.e.p - normalized(vecs[static_cast<std::size_t>(i)])), 0.0, 1e-12);
    }
  }
}

TEST(RuledSetPoints, VelocityAndAxisRateAreContinuousAcrossSetPoints) {
  std::vector<Vec3> pts, vecs;
  for (double t : uneven_t(7)) {
    pts.push_back(helix(t));
    vecs.push_back(axis(t));
  }
  const RuledModelResult r = ruled_model_through(pts, vecs, RulingForm::kAngles);
  ASSERT_EQ(r.error, "");
  const RuledCurves c = r.model.curves();
  const double F = 10.0;
  for (int i = 1; i < 7; ++i) {
    // Left: the end of segment i-1; right: the start of segment i (what ruled_jet takes).
    RuledJet left;
    left.c = hermite_jet(r.model.directrix[static_cast<std::size_t>(i - 1)], 1.0);
    left.e = sphere_point_jet(hermite_jet(r.model.ruling[static_cast<std::size_t>(i - 1)], 1.0));
    const RuledJet right = ruled_jet(c, i);
    const ToolMotion ml = tool_motion(left, i, F, 0.0), mr = tool_motion(right, i, F, 0.0);
    EXPECT_NEAR(norm(ml.velocity - mr.velocity), 0.0, 1e-12 * F) << i;
    // de/dt = e_u du/dt: continuous (the segments share one chord scale).
    const Vec3 dl = ml.du_dt * left.e.d1, dr = mr.du_dt * right.e.d1;
    EXPECT_NEAR(norm(dl - dr), 0.0, 1e-12 * norm(dr)) << i;
    EXPECT_GT(norm(dr), 0.01);
    // The parameter rate itself changes (segments of different chord lengths).
    if (i == 3) {
      EXPECT_GT(std::abs(ml.du_dt - mr.du_dt), 1e-3 * mr.du_dt);
    }
  }
}

// Largest distance of the model's directrix from the helix and of its ruling from the true
// axis, sampled within every segment (the nearest helix point by the parameter's chord share).
struct SweptModelError {
  double position = 0.0, angle = 0.0;
};
SweptModelError model_error(int n) {
  const std::vector<double> ts = uneven_t(n);
  std::vector<Vec3> pts, vecs;
  for (double t : ts) {
    pts.push_back(helix(t));
    vecs.push_back(axis(t));
  }
  const RuledModelResult r = ruled_model_through(pts, vecs, RulingForm::kAngles);
  const RuledCurves c = r.model.curves();
  SweptModelError e;
  for (int i = 0; i < n; ++i)
    for (double f : {0.25, 0.5, 0.75}) {
      const RuledJet j = ruled_jet(c, i + f);
      // The nearest helix parameter by Newton on (helix(t) - x) . helix'(t) = 0.
      double t = ts[static_cast<std::size_t>(i)] + f * (ts[static_cast<std::size_t>(i + 1)] - ts[static_cast<std::size_t>(i)]);
      for (int k = 0; k < 20; ++k) {
        const Vec3 d = helix(t) - j.c.p, h1{-kR * std::sin(t), kR * std::cos(t), kPitch},
                   h2{-kR * std::cos(t), -kR * std::sin(t), 0};
        t -= dot(d, h1) / (dot(h1, h1) + dot(d, h2));
      }
      e.position = std::max(e.position, norm(helix(t) - j.c.p));
      e.angle = std::max(e.angle, std::acos(std::min(1.0, dot(axis(t), j.e.p))));
    }
  return e;
}

TEST(RuledSetPoints, ConvergesToTheSurfaceItSamples) {
  const SweptModelError coarse = model_error(10), fine = model_error(20), finer = model_error(40);
  EXPECT_LT(fine.position, coarse.position / 4);
  EXPECT_LT(finer.position, fine.position / 4);
  EXPECT_LT(fine.angle, coarse.angle / 4);
  EXPECT_LT(finer.angle, fine.angle / 4);
  EXPECT_LT(finer.position, 1e-3);  // mm, set points about 0.8 mm apart on a 10 mm helix
}

TEST(RuledSetPoints, RefusesBadInputWithAReason) {
  const std::vector<Vec3> pts{{0, 0, 0}, {1, 0, 0}, {2, 1, 0}};
  const std::vector<Vec3> up{{0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
  EXPECT_NE(ruled_model_through({pts[0]}, {up[0]}).error, "");
  EXPECT_NE(ruled_model_through(pts, {up[0], up[1]}).error, "");
  EXPECT_NE(ruled_model_through(pts, {up[0], {0, 0, 0}, up[2]}).error.find("tool vector 2"), std::string::npos);
  EXPECT_NE(ruled_model_through({pts[0], pts[0], pts[2]}, up).error.find("coincide"), std::string::npos);
  EXPECT_EQ(ruled_model_through(pts, up).error, "");
}

}  // namespace
}  // namespace pcnc
