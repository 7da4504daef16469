// test_ruled_passes.cpp — the pass planning of ruled_passes.hpp against independent
// computations: the example surface against its formula; the pass interval on a tilted plane
// (distance between parallel lines) and on a cylinder (the chord 2 r sin(du/2)); the ball
// centre at R along the normal from the formula's gradient; the tip and ruling of each pass's
// model at its set points; the lead angle.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "geometry/cusp.hpp"
#include "geometry/ruled_passes.hpp"
#include "geometry/spherical_curve.hpp"

namespace pcnc {
namespace {

TEST(RuledPasses, ExampleSurfaceIsTheFormula) {
  const double size = 25.0;
  const Vec3 origin{-12.5, -12.5, -2.5};
  const BSplineSurface s = example_surface(size, origin);
  ASSERT_EQ(validate(s), "");
  for (double a : {0.0, 0.13, 0.5, 0.77, 1.0})
    for (double b : {0.0, 0.31, 0.5, 0.9, 1.0}) {
      const Vec3 p = surface_point(s, a, b);
      EXPECT_NEAR(p[0], origin[0] + size * a, 1e-12);
      EXPECT_NEAR(p[1], origin[1] + size * b, 1e-12);
      EXPECT_NEAR(p[2], origin[2] + size / 200.0 * example_height(a, b), 1e-12);
    }
  // 0..20 at scale 1: the height difference is size / 10
  EXPECT_NEAR(example_height(0.5, 0.0), 0.0, 1e-12);
  EXPECT_NEAR(example_height(0.5, 1.0), 20.0, 1e-12);
}

// A tilted plane z = 0.3 x + 0.1 y as a bicubic B-spline over [0, 20] x [0, 10].
BSplineSurface tilted_plane() {
  BSplineSurface s;
  s.degree = 3;
  s.count_u = 4;
  s.count_v = 4;
  s.knots_u = {0, 0, 0, 0, 1, 1, 1, 1};
  s.knots_v = s.knots_u;
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i) {
      const double x = 20.0 * i / 3, y = 10.0 * j / 3;
      s.points.push_back({x, y, 0.3 * x + 0.1 * y});
    }
  return s;
}

TEST(RuledPasses, SpacingOnAPlaneIsP) {
  PassOptions o;
  o.tool_radius = 2.0;
  o.cusp_height = 0.01;
  o.point_spacing = 2.0;
  const PassPlan plan = plan_passes(part_surface(tilted_plane()), o);
  ASSERT_EQ(plan.error, "");
  const double P = 2 * std::sqrt(0.01 * (4.0 - 0.01));
  EXPECT_NEAR(plan.interval, P, 1e-15);
  // The contact curves are parallel lines along d = (0, 1, 0.1); their distance is
  // |(p1 - p0) x d| / |d|.
  const Vec3 d{0, 1, 0.1};
  ASSERT_GT(plan.passes.size(), 3u);
  for (std::size_t k = 0; k + 1 < plan.passes.size(); ++k) {
    const Vec3 p0 = plan.passes[k].points.front().contact, p1 = plan.passes[k + 1].points.front().contact;
    const double dist = norm(cross(p1 - p0, d)) / norm(d);
    if (k + 2 < plan.passes.size())
      EXPECT_NEAR(dist, P, 1e-9) << "pass " << k;
    else
      EXPECT_LE(dist, P + 1e-9);  // the last pass is on the edge
    EXPECT_NEAR(plan.passes[k].gap_to_next, dist, 1e-9);
  }
  // first and last pass on the edges x = 0 and x = 20; the zigzag
  EXPECT_NEAR(plan.passes.front().points.front().contact[0], 0.0, 1e-12);
  EXPECT_NEAR(plan.passes.back().points.front().contact[0], 20.0, 1e-12);
  EXPECT_LT(plan.passes[0].points.front().contact[1], plan.passes[0].points.back().contact[1]);
  EXPECT_GT(plan.passes[1].points.front().contact[1], plan.passes[1].points.back().contact[1]);
  // number of passes: the width across the passes (x with the tilt: 20 * sqrt(1 + 0.3^2) /
  // |(1, 0, 0.3) x d|/|d| ...) over P, rounded up, plus the first
  const double width = norm(cross(Vec3{20, 0, 6}, d)) / norm(d);
  EXPECT_EQ(plan.passes.size(), static_cast<std::size_t>(std::ceil(width / P)) + 1);
}

TEST(RuledPasses, SpacingOnACylinderIsP) {
  // S(u, v) = (r sin u, v, r cos u): passes along the cylinder's axis at constant angle u.
  const double r = 7.0;
  PartSurface cyl;
  cyl.eval = [r](double u, double v) {
    SurfaceEval e;
    e.p = {r * std::sin(u), v, r * std::cos(u)};
    e.su = {r * std::cos(u), 0, -r * std::sin(u)};
    e.sv = {0, 1, 0};
    e.suu = {-r * std::sin(u), 0, -r * std::cos(u)};
    return e;
  };
  cyl.u_min = -0.6;
  cyl.u_max = 0.6;
  cyl.v_min = 0;
  cyl.v_max = 12;
  PassOptions o;
  o.tool_radius = 1.0;
  o.cusp_height = 0.005;
  const PassPlan plan = plan_passes(cyl, o);
  ASSERT_EQ(plan.error, "");
  const double P = pass_interval(0.005, 1.0);
  const double du = 2 * std::asin(P / (2 * r));
  ASSERT_EQ(plan.passes.size(), static_cast<std::size_t>(std::ceil(1.2 / du)) + 1);
  for (std::size_t k = 0; k + 2 < plan.passes.size(); ++k) {
    EXPECT_NEAR(plan.passes[k + 1].u - plan.passes[k].u, du, 1e-10);
    // every set point of the next pass (same v values) is P from this one's
    for (std::size_t i = 0; i < plan.passes[k].points.size(); ++i) {
      const PassPoint& a = plan.passes[k].points[i];
      const PassPoint& b = plan.passes[k + 1].points[plan.passes[k].points.size() - 1 - i];  // zigzag
      EXPECT_NEAR(a.v, b.v, 1e-12);
      EXPECT_NEAR(norm(a.contact - b.contact), P, 1e-9);
    }
  }
  // the normal of a cylinder is radial: the ball centre R further out, the tip on the surface
  for (const Pass& p : plan.passes)
    for (const PassPoint& q : p.points) {
      EXPECT_NEAR(norm(Vec3{q.contact[0], 0, q.contact[2]}), r, 1e-12);
      const Vec3 centre = q.tip + o.tool_radius * q.axis;
      EXPECT_NEAR(norm(Vec3{centre[0], 0, centre[2]}), r + o.tool_radius, 1e-12);
    }
}

TEST(RuledPasses, TipAndAxisOnTheExampleSurface) {
  const double size = 25.0, k = size / 200.0;
  PassOptions o;
  o.tool_radius = 1.0;
  o.cusp_height = 0.05;
  o.point_spacing = 1.0;
  const PassPlan plan = plan_passes(part_surface(example_surface(size, {0, 0, 0})), o);
  ASSERT_EQ(plan.error, "");
  ASSERT_GT(plan.passes.size(), 10u);
  const double hstep = 1e-6;
  for (const Pass& pass : plan.passes) {
    const RuledCurves c = pass.model.curves();
    for (std::size_t i = 0; i < pass.points.size(); ++i) {
      const PassPoint& q = pass.points[i];
      // the normal from the formula's gradient (central differences in the unit square)
      const double a = q.contact[0] / size, b = q.contact[1] / size;
      ASSERT_NEAR(q.contact[2], k * example_height(a, b), 1e-12);
      const double zx = k * (example_height(a + hstep, b) - example_height(a - hstep, b)) / (2 * hstep * size);
      const double zy = k * (example_height(a, b + hstep) - example_height(a, b - hstep)) / (2 * hstep * size);
      const Vec3 n = normalized(Vec3{-zx, -zy, 1});
      EXPECT_LT(norm(q.normal - n), 1e-8);
      // ball centre R from the contact along the normal; lead 0: the axis is the normal, the tip the contact
      const Vec3 centre = q.tip + o.tool_radius * q.axis;
      EXPECT_LT(norm(centre - (q.contact + o.tool_radius * n)), 1e-8);
      EXPECT_LT(norm(q.tip - q.contact), 1e-12);
      // the model passes through the tip with the ruling equal to the axis, unit
      const RuledJet j = ruled_jet(c, static_cast<double>(i));
      EXPECT_LT(norm(j.c.p - q.tip), 1e-12);
      EXPECT_NEAR(norm(j.e.p), 1.0, 1e-14);
      EXPECT_LT(norm(j.e.p - q.axis), 1e-12);
    }
    // the ruling stays unit between set points
    for (double u = 0.25; u < c.u_max(); u += 0.5) EXPECT_NEAR(norm(ruled_jet(c, u).e.p), 1.0, 1e-14);
    // the length against the chord sum (longer, and close)
    double chords = 0;
    for (std::size_t i = 1; i < pass.points.size(); ++i) chords += norm(pass.points[i].tip - pass.points[i - 1].tip);
    EXPECT_GE(pass.length, chords * (1 - 1e-9));
    EXPECT_LT(pass.length, chords * 1.001);
  }
}

TEST(RuledPasses, LeadAngleTiltsTheAxisForward) {
  const double lead = 10.0 * M_PI / 180.0, R = 1.5;
  PassOptions o;
  o.tool_radius = R;
  o.cusp_height = 0.2;
  o.point_spacing = 2.0;
  o.lead_angle = lead;
  const BSplineSurface surf = example_surface(25.0, {0, 0, 0});
  const PassPlan plan = plan_passes(part_surface(surf), o);
  ASSERT_EQ(plan.error, "");
  for (std::size_t k = 0; k < 2; ++k) {
    const Pass& pass = plan.passes[k];
    for (std::size_t i = 0; i + 1 < pass.points.size(); ++i) {
      const PassPoint& q = pass.points[i];
      EXPECT_NEAR(std::acos(std::clamp(dot(q.axis, q.normal), -1.0, 1.0)), lead, 1e-12);
      // toward the direction of travel: the surface's v direction, backwards on a reversed pass
      const Vec3 sv = surface_eval(surf, q.u, q.v).sv;
      const Vec3 ahead = pass.reversed ? -1.0 * sv : sv;
      EXPECT_GT(dot(q.axis - std::cos(lead) * q.normal, ahead), 0.0);
      EXPECT_GT(dot(pass.points[i + 1].contact - q.contact, ahead), 0.0);
      // in the plane of the normal and the travel
      EXPECT_LT(std::abs(det3(q.axis, q.normal, ahead)) / norm(ahead), 1e-12);
      // the ball centre is still R along the normal from the contact
      EXPECT_LT(norm(q.tip + R * q.axis - (q.contact + R * q.normal)), 1e-12);
      EXPECT_NEAR(norm(q.axis), 1.0, 1e-15);
    }
  }
}

TEST(RuledPasses, ModelErrorBetweenSetPoints) {
  // on a cylinder along its axis the tip path is a line and the axis constant: the model is exact
  const double r = 5.0;
  PartSurface cyl;
  cyl.eval = [r](double u, double v) {
    SurfaceEval e;
    e.p = {r * std::sin(u), v, r * std::cos(u)};
    e.su = {r * std::cos(u), 0, -r * std::sin(u)};
    e.sv = {0, 1, 0};
    return e;
  };
  cyl.u_min = -0.2;
  cyl.u_max = 0.2;
  cyl.v_min = 0;
  cyl.v_max = 6;
  PassOptions o;
  o.cusp_height = 0.05;
  const PassPlan pc = plan_passes(cyl, o);
  ASSERT_EQ(pc.error, "");
  const ModelError ec = pass_model_error(cyl, pc.passes[1], o, 8);
  EXPECT_LT(ec.tip, 1e-9);
  EXPECT_LT(ec.axis, 1e-9);
  // on the example it falls at least 8x per halving of the spacing (cubic or better)
  const PartSurface ex = part_surface(example_surface(25.0, {0, 0, 0}));
  double tip[2], axis[2];
  for (int k = 0; k < 2; ++k) {
    o.point_spacing = k == 0 ? 2.0 : 1.0;
    const PassPlan p = plan_passes(ex, o);
    ASSERT_EQ(p.error, "");
    const ModelError e = pass_model_error(ex, p.passes[3], o, 8);
    tip[k] = e.tip;
    axis[k] = e.axis;
  }
  EXPECT_GT(tip[1], 0.0);
  EXPECT_GT(tip[0], 8.0 * tip[1]);
  EXPECT_GT(axis[0], 4.0 * axis[1]);
  EXPECT_LT(tip[0], 1e-3);  // 2 mm spacing on a 25 mm part: under a micrometre
}

TEST(RuledPasses, RefusesBadInput) {
  const PartSurface s = part_surface(example_surface(25.0, {0, 0, 0}));
  PassOptions o;
  o.cusp_height = 2.0;  // above R
  EXPECT_NE(plan_passes(s, o).error, "");
  o = {};
  o.tool_radius = 0.0;
  EXPECT_NE(plan_passes(s, o).error, "");
  o = {};
  o.point_spacing = 0.0;
  EXPECT_NE(plan_passes(s, o).error, "");
  // a surface collapsed to a point along one edge (a cone's apex) has no normal there
  PartSurface cone;
  cone.eval = [](double u, double v) {
    SurfaceEval e;
    e.p = {v * std::cos(u), v * std::sin(u), -v};
    e.su = {-v * std::sin(u), v * std::cos(u), 0};
    e.sv = {std::cos(u), std::sin(u), -1};
    return e;
  };
  cone.u_min = 0;
  cone.u_max = 0.5;
  cone.v_min = 0;
  cone.v_max = 5;
  const PassPlan bad = plan_passes(cone, {});
  EXPECT_NE(bad.error.find("no normal"), std::string::npos) << bad.error;
}

}  // namespace
}  // namespace pcnc
