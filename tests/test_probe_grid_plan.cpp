// test_probe_grid_plan.cpp — the probing plan over a rectangle (geometry/probe_grid_plan): the
// count and the CSV order (rows of constant y, y increasing, x increasing within a row), the
// expected contacts on the estimate, start and end on the normal at the clearance and probing
// distance (checked by the point-to-plane distance), a B-spline estimate's normals, refusals.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "geometry/probe_grid_plan.hpp"
#include "geometry/surface_fit.hpp"

namespace pcnc {
namespace {

TEST(ProbeGridPlan, CountAndCsvOrder) {
  ProbeGridSpec s;
  s.x0_mm = 2.0;
  s.x1_mm = 22.0;
  s.y0_mm = 5.0;
  s.y1_mm = 20.0;
  s.nx = 5;
  s.ny = 4;
  const ProbeGridPlan p = plan_probe_grid(s, SurfaceEstimate{1.5, 0.0, 0.0, nullptr});
  ASSERT_TRUE(p.ok()) << p.error;
  ASSERT_EQ(p.points.size(), 20u);
  for (std::size_t i = 0; i < p.points.size(); ++i) {
    const ProbePoint& q = p.points[i];
    EXPECT_EQ(q.row, static_cast<int>(i) / 5);
    EXPECT_EQ(q.col, static_cast<int>(i) % 5);
    EXPECT_DOUBLE_EQ(q.expected_contact[0], 2.0 + 5.0 * q.col);
    EXPECT_DOUBLE_EQ(q.expected_contact[1], 5.0 + 5.0 * q.row);
    EXPECT_DOUBLE_EQ(q.expected_contact[2], 1.5);
    if (i > 0) {
      const ProbePoint& prev = p.points[i - 1];
      if (q.row == prev.row) EXPECT_GT(q.expected_contact[0], prev.expected_contact[0]);
      else EXPECT_GT(q.expected_contact[1], prev.expected_contact[1]);
    }
    EXPECT_EQ(q.approach, (Vec3{0, 0, -1}));
  }
}

TEST(ProbeGridPlan, StartAndEndOnTheNormalOfASlope) {
  const SurfaceEstimate plane{1.0, 0.5, -0.25, nullptr};  // z = 1 + 0.5x − 0.25y
  ProbeGridSpec s{0, 10, 0, 10, 3, 3, 1.0, 2.0, 0.5};
  const ProbeGridPlan p = plan_probe_grid(s, plane);
  ASSERT_TRUE(p.ok()) << p.error;
  const double k = std::sqrt(1 + 0.25 + 0.0625);
  auto distance = [&](const Vec3& c) { return (c[2] - (1.0 + 0.5 * c[0] - 0.25 * c[1])) / k; };  // to the plane
  for (const ProbePoint& q : p.points) {
    EXPECT_NEAR(distance(q.expected_contact), 0.0, 1e-12);
    EXPECT_NEAR(distance(q.start), 1.0 + 2.0, 1e-12);  // ball radius + clearance
    EXPECT_NEAR(distance(q.end), 1.0 - 0.5, 1e-12);    // probing distance past the touch
    EXPECT_NEAR(norm(q.approach), 1.0, 1e-15);
    EXPECT_NEAR(norm(cross(q.start - q.end, q.approach)), 0.0, 1e-12);  // the move is along d
    EXPECT_LT(dot(q.end - q.start, q.normal), 0.0);                     // toward the part
    EXPECT_NEAR(q.normal[0], -0.5 / k, 1e-15);
  }
}

TEST(ProbeGridPlan, BSplineEstimateGivesItsNormals) {
  // a tilted plane as a B-spline estimate: its normals are the plane's
  PointGrid g;
  g.cols = g.rows = 4;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) g.points.push_back({c * 8.0, r * 8.0, 0.2 * c * 8.0 + 0.1 * r * 8.0});
  const SurfaceFit fit = interpolate_grid(g, 3, 1.0);
  ASSERT_TRUE(fit.ok()) << fit.error;
  SurfaceEstimate est;
  est.surface = &fit.surface;
  const ProbeGridPlan p = plan_probe_grid(ProbeGridSpec{1, 23, 1, 23, 4, 3, 0.5, 1, 1}, est);
  ASSERT_TRUE(p.ok()) << p.error;
  const Vec3 n = normalized(Vec3{-0.2, -0.1, 1.0});
  for (const ProbePoint& q : p.points) {
    EXPECT_GT(dot(q.normal, n), 1.0 - 1e-10);
    EXPECT_NEAR(q.expected_contact[2], 0.2 * q.expected_contact[0] + 0.1 * q.expected_contact[1], 1e-9);
  }
}

TEST(ProbeGridPlan, OnePointIsTheGridsPoint) {
  const SurfaceEstimate plane{1.0, 0.5, -0.25, nullptr};
  const ProbeGridSpec s{0, 10, 0, 10, 3, 3, 1.0, 2.0, 0.5};
  const ProbeGridPlan grid = plan_probe_grid(s, plane);
  ASSERT_TRUE(grid.ok()) << grid.error;
  const ProbePoint one = plan_probe_point(5.0, 10.0, s, plane);  // column 1 of row 2
  const ProbePoint& g = grid.points[7];
  EXPECT_EQ(one.start, g.start);
  EXPECT_EQ(one.end, g.end);
  EXPECT_EQ(one.normal, g.normal);
  EXPECT_DOUBLE_EQ(one.expected_contact[2], 1.0 + 0.5 * 5.0 - 0.25 * 10.0);
}

TEST(ProbeGridPlan, RefusesBadSpecs) {
  const SurfaceEstimate flat;
  EXPECT_FALSE(plan_probe_grid(ProbeGridSpec{0, 10, 0, 10, 0, 3, 1, 1, 1}, flat).ok());
  EXPECT_FALSE(plan_probe_grid(ProbeGridSpec{10, 0, 0, 10, 3, 3, 1, 1, 1}, flat).ok());
  EXPECT_FALSE(plan_probe_grid(ProbeGridSpec{0, 10, 0, 10, 3, 3, 1, 0, 1}, flat).ok());
  // a single column is fine
  const ProbeGridPlan one = plan_probe_grid(ProbeGridSpec{5, 5, 0, 10, 1, 3, 1, 1, 1}, flat);
  ASSERT_TRUE(one.ok()) << one.error;
  EXPECT_EQ(one.points.size(), 3u);
}

}  // namespace
}  // namespace pcnc
