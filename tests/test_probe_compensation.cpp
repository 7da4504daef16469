// test_probe_compensation.cpp — ball centre to contact point (geometry/probe_compensation):
// grids of latched centres probed straight down on a tilted plane, a 45° slope and a sphere
// (the centres computed here from each shape's own geometry: distance to a plane, |c − O| =
// R + r) are compensated along the normal of the B-spline through the centres and compared
// with the true contact points; the naive reading (centre Z minus the radius) errs by
// r(1/cos α − 1), 0.414 mm for a 1 mm ball at 45°.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <numbers>
#include <random>
#include <vector>

#include "geometry/probe_compensation.hpp"
#include "geometry/probe_grid_plan.hpp"

namespace pcnc {
namespace {

// A plane z = z0 + sx·x + sy·y probed straight down at (x, y) by a ball of effective radius r:
// the centre is r from the plane, on the vertical through (x, y).
struct Plane {
  double z0, sx, sy;
  double z(double x, double y) const { return z0 + sx * x + sy * y; }
  Vec3 n() const { return normalized(Vec3{-sx, -sy, 1.0}); }
  Vec3 centre(double x, double y, double r) const { return {x, y, z(x, y) + r * std::sqrt(1 + sx * sx + sy * sy)}; }
};

PointGrid centre_grid(int n, double lo, double hi, const std::function<Vec3(double, double)>& centre) {
  PointGrid g;
  g.cols = g.rows = n;
  for (int r = 0; r < n; ++r)
    for (int c = 0; c < n; ++c) g.points.push_back(centre(lo + (hi - lo) * c / (n - 1), lo + (hi - lo) * r / (n - 1)));
  return g;
}

const std::vector<Vec3> kDown{{0.0, 0.0, -1.0}};

TEST(ProbeCompensation, ContactPointIsTheCentreMovedBackAlongTheNormal) {
  EXPECT_EQ(contact_point({1, 2, 3}, {0, 0, 2}, 0.5), (Vec3{1, 2, 2.5}));
  const Vec3 q = contact_point({0, 0, 0}, {1, 1, 0}, 2.0);
  EXPECT_NEAR(q[0], -std::sqrt(2.0), 1e-15);
  EXPECT_NEAR(q[1], -std::sqrt(2.0), 1e-15);
}

TEST(ProbeCompensation, TiltedPlaneGivesTheTrueContacts) {
  const Plane pl{2.0, 0.2, -0.1};
  const double r = 0.995;  // a 1 mm ball with 5 µm of pre-travel
  const PointGrid g = centre_grid(7, 0.0, 24.0, [&](double x, double y) { return pl.centre(x, y, r); });
  const GridCompensation comp = compensate_grid(g, kDown, constant_calibration(r));
  ASSERT_TRUE(comp.ok()) << comp.error;
  EXPECT_EQ(comp.degree, 3);
  for (std::size_t i = 0; i < g.points.size(); ++i) {
    const Vec3 truth = g.points[i] - r * pl.n();
    EXPECT_LT(norm(comp.contacts.points[i] - truth), 1e-9);
    EXPECT_GT(dot(comp.normals[i], pl.n()), 1.0 - 1e-12);
    const Vec3& q = comp.contacts.points[i];
    EXPECT_NEAR(q[2], pl.z(q[0], q[1]), 1e-9);  // on the plane
  }
}

TEST(ProbeCompensation, FortyFiveDegreeSlopeNaiveErrorAndCorrection) {
  const Plane slope{0.0, 1.0, 0.0};  // z = x: 45°
  const double r = 1.0;
  const PointGrid g = centre_grid(5, 0.0, 20.0, [&](double x, double y) { return slope.centre(x, y, r); });
  // naive: the centre's Z minus the radius, taken as the height at the centre's X/Y
  for (const Vec3& c : g.points) EXPECT_NEAR((c[2] - r) - slope.z(c[0], c[1]), r * (1.0 / std::cos(std::numbers::pi / 4) - 1.0), 1e-12);
  EXPECT_NEAR(r * (std::sqrt(2.0) - 1.0), 0.41421356, 1e-8);
  const GridCompensation comp = compensate_grid(g, kDown, constant_calibration(r));
  ASSERT_TRUE(comp.ok()) << comp.error;
  for (std::size_t i = 0; i < g.points.size(); ++i) {
    const Vec3& q = comp.contacts.points[i];
    EXPECT_NEAR(q[2], slope.z(q[0], q[1]), 1e-9);
    EXPECT_NEAR(q[0], g.points[i][0] + r / std::sqrt(2.0), 1e-9);  // the touch is uphill of the centre
  }
}

TEST(ProbeCompensation, SphereCapWithinTheNormalsError) {
  // a dome of radius 30 mm centred 25 mm below the grid: slopes up to about 35°
  const Vec3 o{10.0, 10.0, -25.0};
  const double rp = 30.0, r = 1.0;
  const PointGrid g = centre_grid(9, 0.0, 20.0, [&](double x, double y) {
    const double dx = x - o[0], dy = y - o[1];
    return Vec3{x, y, o[2] + std::sqrt((rp + r) * (rp + r) - dx * dx - dy * dy)};
  });
  const GridCompensation comp = compensate_grid(g, kDown, constant_calibration(r));
  ASSERT_TRUE(comp.ok()) << comp.error;
  double worst_point = 0.0, worst_surface = 0.0, worst_angle = 0.0;
  for (std::size_t i = 0; i < g.points.size(); ++i) {
    const Vec3 n_true = normalized(g.points[i] - o);
    const Vec3 truth = o + rp * n_true;
    worst_point = std::max(worst_point, norm(comp.contacts.points[i] - truth));
    worst_surface = std::max(worst_surface, std::abs(norm(comp.contacts.points[i] - o) - rp));
    worst_angle = std::max(worst_angle, std::acos(std::min(1.0, dot(comp.normals[i], n_true))));
  }
  // the point errs by r·(angle error) across the surface, by about r·angle²/2 off it
  EXPECT_LE(worst_point, r * worst_angle * 1.01 + 1e-12);
  EXPECT_LT(worst_angle, 2e-3);     // cubic interpolation of 9 × 9 centres
  EXPECT_LT(worst_surface, 2e-6);   // off the surface: second order
}

TEST(ProbeCompensation, DirectionDependentRadiusUsesTheApproach) {
  // a flat table probed at two approach directions: each gets its own r_eff
  CalibrationLayout layout{3, std::numbers::pi / 2, 0};
  std::vector<ProbeTouch> t;
  const Vec3 c{0, 0, 0};
  for (const Vec3& d : calibration_directions(layout, 4)) {
    const double reff = 1.0 - 0.01 * approach_angles(d).polar;  // linear in θ: exact in the table
    t.push_back({c - (5.0 + reff) * d, d});
  }
  const ProbeCalibrationResult cal = calibrate_probe(t, 5.0, layout, &c);
  ASSERT_TRUE(cal.ok()) << cal.error;
  const Vec3 n{0, 0, 1};
  EXPECT_NEAR(contact_point({0, 0, 1.0}, n, {0, 0, -1}, cal.cal)[2], 0.0, 1e-12);
  const Vec3 slanted = normalized(Vec3{1, 0, -1});  // θ = 45°: r_eff = 1 − 0.01·π/4
  EXPECT_NEAR(contact_point({0, 0, 1.0}, n, slanted, cal.cal)[2], 1.0 - (1.0 - 0.01 * std::numbers::pi / 4), 1e-12);
}

TEST(ProbeCompensation, PlanCalibrateProbeCompensateOnASphereCap) {
  // The chain: a lobed probe calibrated on a reference sphere, a 7 × 7 plan along the normals
  // of a design estimate of a dome, each touch latched where the moving ball's centre comes
  // within r_eff(d) of the dome (|s + t d − O| = Rp + r_eff(d), solved here), then compensated
  // with per-point approaches. The dome's true contact is O + Rp·(p − O)/|p − O|.
  auto reff_true = [](const Vec3& d) {
    const ApproachAngles a = approach_angles(d);
    const double c = std::cos(a.polar), s = std::sin(a.polar);
    return 1.0 - (0.002 * c * c + (0.008 + 0.003 * std::cos(3.0 * a.azimuth)) * s * s);
  };
  const CalibrationLayout layout;
  const Vec3 ref{30, 30, 0};
  std::vector<ProbeTouch> touches;
  for (const Vec3& d : calibration_directions(layout, 12)) touches.push_back({ref - (6.0 + reff_true(d)) * d, d});
  const ProbeCalibrationResult cal = calibrate_probe(touches, 6.0, layout, &ref);
  ASSERT_TRUE(cal.ok()) << cal.error;

  const Vec3 o{12.5, 12.5, -20.0};
  const double rp = 30.0;
  PointGrid design;  // the estimate: the dome itself, as a B-spline through 9 × 9 points
  design.cols = design.rows = 9;
  for (int r = 0; r < 9; ++r)
    for (int c = 0; c < 9; ++c) {
      const double x = 2.5 + 2.5 * c, y = 2.5 + 2.5 * r;
      design.points.push_back({x, y, o[2] + std::sqrt(rp * rp - std::pow(x - o[0], 2) - std::pow(y - o[1], 2))});
    }
  const SurfaceFit est_fit = interpolate_grid(design, 3, 1.0);
  ASSERT_TRUE(est_fit.ok()) << est_fit.error;
  SurfaceEstimate est;
  est.surface = &est_fit.surface;
  const ProbeGridPlan plan = plan_probe_grid(ProbeGridSpec{4, 21, 4, 21, 7, 7, 1.0, 1.0, 1.0}, est);
  ASSERT_TRUE(plan.ok()) << plan.error;

  PointGrid centres;
  centres.cols = centres.rows = 7;
  std::vector<Vec3> approaches;
  for (const ProbePoint& p : plan.points) {
    // the smaller root t of |start + t d − O|² = (Rp + r_eff)²
    const double rr = rp + reff_true(p.approach);
    const Vec3 w = p.start - o;
    const double b = dot(w, p.approach), c = dot(w, w) - rr * rr;
    const double t = -b - std::sqrt(b * b - c);
    ASSERT_GT(t, 0.0);
    centres.points.push_back(p.start + t * p.approach);
    approaches.push_back(p.approach);
  }
  const GridCompensation comp = compensate_grid(centres, approaches, cal.cal);
  ASSERT_TRUE(comp.ok()) << comp.error;
  // the calibration's bound in θ: h²/8 · 2(axial + lateral + lobe), h = 15° (0.22 µm)
  const double interp = std::pow(std::numbers::pi / 12, 2) / 8.0 * 2.0 * (0.002 + 0.008 + 0.003);
  double worst_off = 0.0, worst_across = 0.0, worst_angle = 0.0;
  for (std::size_t i = 0; i < centres.points.size(); ++i) {
    const Vec3 n_true = normalized(centres.points[i] - o);
    const Vec3 truth = o + rp * n_true;
    const Vec3 err = comp.contacts.points[i] - truth;
    worst_off = std::max(worst_off, std::abs(dot(err, n_true)));
    worst_across = std::max(worst_across, norm(err - dot(err, n_true) * n_true));
    worst_angle = std::max(worst_angle, std::acos(std::min(1.0, dot(comp.normals[i], n_true))));
  }
  EXPECT_LT(worst_angle, 2e-3);
  EXPECT_LT(worst_off, interp + 1.0 * worst_angle * worst_angle);  // radial: r_eff's error + rΔ²/2 (×2)
  EXPECT_LT(worst_across, 1.0 * worst_angle * 1.01 + 1e-9);       // tangential: rΔ
}

TEST(ProbeCompensation, ScatteredPointsOnAPlaneAndADome) {
  // a tilted plane, points scattered (a seeded jitter): the plane's contacts exactly
  const Plane pl{0.5, 0.3, 0.2};
  std::mt19937_64 rng(8);
  std::uniform_real_distribution<double> jitter(-0.8, 0.8);
  std::vector<Vec3> centres;
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) centres.push_back(pl.centre(3.0 * i + jitter(rng), 3.0 * j + jitter(rng), 1.0));
  const PointsCompensation comp = compensate_points(centres, kDown, constant_calibration(1.0));
  ASSERT_TRUE(comp.ok()) << comp.error;
  for (std::size_t i = 0; i < centres.size(); ++i) EXPECT_LT(norm(comp.contacts[i] - (centres[i] - pl.n())), 1e-9);
  // a dome (R 30 mm, centres on R' = 31 mm): off the surface each point errs by
  // |q − O| − R ≈ r·(R'/R)·angle²/2 (|q − O|² = (R' − r)² + 2rR'(1 − cos angle))
  const Vec3 o{10, 10, -25};
  std::vector<Vec3> dome;
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) {
      const double x = 2.0 + 3.0 * i + jitter(rng), y = 2.0 + 3.0 * j + jitter(rng);
      dome.push_back({x, y, o[2] + std::sqrt(31.0 * 31.0 - std::pow(x - o[0], 2) - std::pow(y - o[1], 2))});
    }
  const PointsCompensation dc = compensate_points(dome, kDown, constant_calibration(1.0));
  ASSERT_TRUE(dc.ok()) << dc.error;
  for (std::size_t i = 0; i < dome.size(); ++i) {
    const Vec3 n_true = normalized(dome[i] - o);
    const double angle = std::acos(std::min(1.0, dot(dc.normals[i], n_true)));
    // a plane through neighbours on one side (a corner) tilts by about the curvature times
    // their distance: ≈ 4 mm / 31 mm
    EXPECT_LT(angle, 0.15);
    const double rr = std::sqrt(30.0 * 30.0 + 2.0 * 31.0 * (1.0 - std::cos(angle)));
    EXPECT_NEAR(norm(dc.contacts[i] - o), rr, 1e-9);
  }
  EXPECT_FALSE(compensate_points({{0, 0, 0}, {1, 0, 0}}, kDown, constant_calibration(1.0)).ok());
  EXPECT_FALSE(compensate_points({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}}, kDown, constant_calibration(1.0)).ok());
}

TEST(ProbeCompensation, LocalNormalFromNeighboursAndRefusals) {
  const Plane pl{1.0, -0.3, 0.25};
  std::vector<Vec3> pts;
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j) pts.push_back(pl.centre(i * 3.0 + 0.1 * j, j * 2.5, 1.0));
  for (std::size_t i : {0u, 12u, 24u}) EXPECT_GT(dot(local_normal(pts, i, 6, {0, 0, -1}), pl.n()), 1.0 - 1e-12);
  // oriented against the approach
  EXPECT_LT(dot(local_normal(pts, 12, 6, {0, 0, 1}), pl.n()), -1.0 + 1e-12);
  EXPECT_FALSE(compensate_grid(PointGrid{1, 1, {{0, 0, 0}}}, kDown, constant_calibration(1.0)).ok());
  const PointGrid g = centre_grid(3, 0, 1, [](double x, double y) { return Vec3{x, y, 0}; });
  EXPECT_FALSE(compensate_grid(g, {{0, 0, -1}, {0, 0, -1}}, constant_calibration(1.0)).ok());
}

}  // namespace
}  // namespace pcnc
