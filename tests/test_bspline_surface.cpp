// test_bspline_surface.cpp — the measured B-spline surface (issue 15, item 4) against
// independent computations: interpolation through every data point; exact reproduction of a
// plane, a bilinear and a bicubic polynomial surface; derivatives against finite differences;
// normal curvatures against circles through three surface points (and a sphere); F(e) of
// eq. 15 against the same independent curvatures; fairing lowers F; the height query; the
// Wiener surface and the grid baselines; the surface file's round trip and every refusal.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "config/surface_file.hpp"
#include "geometry/bspline_surface.hpp"
#include "geometry/surface_fit.hpp"
#include "geometry/surface_interp.hpp"
#include "geometry/wiener_surface.hpp"

namespace pcnc {
namespace {

template <class F>
PointGrid grid_of(const std::vector<double>& xs, const std::vector<double>& ys, F z) {
  PointGrid g;
  g.cols = static_cast<int>(xs.size());
  g.rows = static_cast<int>(ys.size());
  for (double y : ys)
    for (double x : xs) g.points.push_back({x, y, z(x, y)});
  return g;
}

std::vector<double> uniform(double a, double b, int n) {
  std::vector<double> v;
  for (int i = 0; i < n; ++i) v.push_back(a + (b - a) * i / (n - 1));
  return v;
}

// A wavy grid with uneven spacing: what a measured freeform surface gives.
PointGrid wavy_grid() {
  return grid_of({0, 1.5, 4, 5, 7.5, 10, 11, 14}, {0, 2, 3, 6, 8, 11}, [](double x, double y) {
    return 1.5 * std::sin(0.4 * x) * std::cos(0.3 * y) + 0.05 * x;
  });
}

// Curvature vector at b of the circle through a, b, c.
Vec3 circle_curvature(const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 u = a - b, w = c - b;
  const Vec3 n = cross(u, w);
  const double nn = dot(n, n);
  if (nn <= 1e-30 * dot(u, u) * dot(w, w)) return {0, 0, 0};  // collinear: a straight line
  // centre - b = ((|u|^2 w - |w|^2 u) x n) / (2 |n|^2)
  const Vec3 centre = (1.0 / (2.0 * nn)) * cross(dot(u, u) * w - dot(w, w) * u, n);
  return (1.0 / dot(centre, centre)) * centre;
}

// Normal curvatures from surface points alone: circles through three points along each
// parameter line (one-sided at the domain's ends), the normal from central differences.
// Points equally spaced in the parameter are not equally spaced along the curve, so the
// circle is off by O(h); curvatures() below removes that term (Richardson).
NormalCurvatures circle_curvatures(const BSplineSurface& s, double u, double v, double h) {
  auto pt = [&](double a, double b) { return surface_point(s, a, b); };
  const double uc = std::clamp(u, h, 1.0 - h), vc = std::clamp(v, h, 1.0 - h);
  const Vec3 du = pt(std::min(u + h, 1.0), v) - pt(std::max(u - h, 0.0), v);
  const Vec3 dv = pt(u, std::min(v + h, 1.0)) - pt(u, std::max(v - h, 0.0));
  const Vec3 n = normalized(cross(du, dv));
  NormalCurvatures k;
  k.ku = dot(circle_curvature(pt(uc - h, v), pt(uc, v), pt(uc + h, v)), n);
  k.kv = dot(circle_curvature(pt(u, vc - h), pt(u, vc), pt(u, vc + h)), n);
  return k;
}

NormalCurvatures independent_curvatures(const BSplineSurface& s, double u, double v) {
  const NormalCurvatures a = circle_curvatures(s, u, v, 1e-4), b = circle_curvatures(s, u, v, 5e-5);
  return {2 * b.ku - a.ku, 2 * b.kv - a.kv};
}

TEST(SurfaceFit, PassesThroughEveryDataPoint) {
  const PointGrid g = wavy_grid();
  for (int degree : {1, 2, 3, 5}) {
    for (double e : {0.0, 0.5, 1.0}) {
      const SurfaceFit f = interpolate_grid(g, degree, e);
      ASSERT_TRUE(f.ok()) << f.error;
      ASSERT_EQ(validate(f.surface), "");
      for (int r = 0; r < g.rows; ++r)
        for (int c = 0; c < g.cols; ++c) {
          const Vec3 p = surface_point(f.surface, f.params_u[c], f.params_v[r]);
          EXPECT_LT(norm(p - g.at(c, r)), 1e-9) << "degree " << degree << " e " << e << " point " << c << "," << r;
        }
    }
  }
}

TEST(SurfaceFit, ParametersAndKnotsFollowTheSeed) {
  // one row: chord lengths 1, 4 (and 1 again): e = 1 gives 0, 1/6, 5/6, 1; e = 0.5: 0, 1/4, 3/4, 1
  PointGrid g = grid_of({0, 1, 5, 6}, {0, 1, 2, 3}, [](double, double) { return 0.0; });
  const auto u1 = grid_params_u(g, 1.0), uh = grid_params_u(g, 0.5), u0 = grid_params_u(g, 0.0);
  EXPECT_NEAR(u1[1], 1.0 / 6, 1e-15);
  EXPECT_NEAR(u1[2], 5.0 / 6, 1e-15);
  EXPECT_NEAR(uh[1], 0.25, 1e-15);
  EXPECT_NEAR(u0[2], 2.0 / 3, 1e-15);
  // eq. 9: the interior knot of 6 points, degree 3, is the mean of params 1..3
  const std::vector<double> k = averaging_knots({0, 0.1, 0.3, 0.6, 0.8, 1}, 3);
  ASSERT_EQ(k.size(), 10u);
  EXPECT_NEAR(k[4], (0.1 + 0.3 + 0.6) / 3, 1e-15);
  EXPECT_NEAR(k[5], (0.3 + 0.6 + 0.8) / 3, 1e-15);
  EXPECT_EQ(k[3], 0.0);
  EXPECT_EQ(k[6], 1.0);
}

TEST(SurfaceFit, ReproducesAPlaneEverywhere) {
  auto plane = [](double x, double y) { return 0.3 * x - 0.2 * y + 4.0; };
  const PointGrid g = grid_of({0, 2, 3, 7, 8, 12}, {0, 1, 4, 5, 9}, plane);
  for (double e : {0.0, 0.5, 1.0}) {
    const SurfaceFit f = interpolate_grid(g, 3, e);
    ASSERT_TRUE(f.ok());
    for (double u = 0; u <= 1.0; u += 0.037)
      for (double v = 0; v <= 1.0; v += 0.041) {
        const Vec3 p = surface_point(f.surface, u, v);
        EXPECT_NEAR(p[2], plane(p[0], p[1]), 1e-10);
      }
    const SurfaceHeight h = surface_height(f.surface, 5.5, 2.5);
    EXPECT_TRUE(h.inside);
    EXPECT_NEAR(h.z, plane(5.5, 2.5), 1e-10);
  }
}

TEST(SurfaceFit, ReproducesPolynomialsOfItsDegree) {
  // uniform grid, e = 0: x and y are linear in u and v, so z(x, y) of degree <= p in each
  // variable is in the spline space and comes back exactly, between the data points too
  auto bicubic = [](double x, double y) {
    return 0.002 * x * x * x - 0.01 * x * x * y + 0.0007 * x * y * y * y + 0.03 * y * y - 0.1 * x + 1.0;
  };
  auto bilinear = [](double x, double y) { return 0.5 + 0.2 * x - 0.1 * y + 0.03 * x * y; };
  const auto xs = uniform(-3, 17, 7), ys = uniform(2, 20, 6);
  struct Case {
    int degree;
    double (*z)(double, double);
  };
  for (const Case& c : {Case{3, +bicubic}, Case{1, +bilinear}, Case{2, +bilinear}}) {
    const SurfaceFit f = interpolate_grid(grid_of(xs, ys, c.z), c.degree, 0.0);
    ASSERT_TRUE(f.ok());
    for (double u = 0; u <= 1.0; u += 0.029)
      for (double v = 0; v <= 1.0; v += 0.031) {
        const Vec3 p = surface_point(f.surface, u, v);
        EXPECT_NEAR(p[0], -3 + 20 * u, 1e-10);
        EXPECT_NEAR(p[2], c.z(p[0], p[1]), 1e-10) << "degree " << c.degree << " at " << u << "," << v;
      }
    for (double x : {-3.0, 0.3, 8.8, 16.99})
      for (double y : {2.0, 7.7, 19.2}) {
        const SurfaceHeight h = surface_height(f.surface, x, y);
        EXPECT_TRUE(h.inside);
        EXPECT_NEAR(h.z, c.z(x, y), 1e-9);
      }
  }
}

TEST(BSplineSurface, DerivativesMatchFiniteDifferences) {
  const SurfaceFit f = interpolate_grid(wavy_grid(), 3, 0.5);
  ASSERT_TRUE(f.ok());
  const double h = 1e-6;
  for (double u : {0.013, 0.21, 0.5, 0.77, 0.96})
    for (double v : {0.02, 0.33, 0.61, 0.93}) {
      const SurfaceEval e = surface_eval(f.surface, u, v);
      const Vec3 fu = (1.0 / (2 * h)) * (surface_point(f.surface, u + h, v) - surface_point(f.surface, u - h, v));
      const Vec3 fv = (1.0 / (2 * h)) * (surface_point(f.surface, u, v + h) - surface_point(f.surface, u, v - h));
      const Vec3 fuu = (1.0 / (2 * h)) * (surface_eval(f.surface, u + h, v).su - surface_eval(f.surface, u - h, v).su);
      const Vec3 fuv = (1.0 / (2 * h)) * (surface_eval(f.surface, u, v + h).su - surface_eval(f.surface, u, v - h).su);
      const Vec3 fvv = (1.0 / (2 * h)) * (surface_eval(f.surface, u, v + h).sv - surface_eval(f.surface, u, v - h).sv);
      EXPECT_NEAR(norm(e.p - surface_point(f.surface, u, v)), 0.0, 1e-12);
      EXPECT_LT(norm(e.su - fu), 1e-6 * (1 + norm(e.su)));
      EXPECT_LT(norm(e.sv - fv), 1e-6 * (1 + norm(e.sv)));
      EXPECT_LT(norm(e.suu - fuu), 1e-5 * (1 + norm(e.suu)));
      EXPECT_LT(norm(e.suv - fuv), 1e-5 * (1 + norm(e.suv)));
      EXPECT_LT(norm(e.svv - fvv), 1e-5 * (1 + norm(e.svv)));
      EXPECT_NEAR(norm(surface_normal(e)), 1.0, 1e-12);
      EXPECT_NEAR(dot(surface_normal(e), e.su), 0.0, 1e-9);
    }
}

TEST(BSplineSurface, NormalCurvaturesMatchCirclesThroughSurfacePoints) {
  const SurfaceFit f = interpolate_grid(wavy_grid(), 3, 1.0);
  ASSERT_TRUE(f.ok());
  for (double u : {0.1, 0.37, 0.5, 0.81})
    for (double v : {0.12, 0.45, 0.88}) {
      const NormalCurvatures k = normal_curvatures(surface_eval(f.surface, u, v));
      const NormalCurvatures r = independent_curvatures(f.surface, u, v);
      EXPECT_NEAR(k.ku, r.ku, 1e-5 + 1e-4 * std::fabs(r.ku)) << u << "," << v;
      EXPECT_NEAR(k.kv, r.kv, 1e-5 + 1e-4 * std::fabs(r.kv)) << u << "," << v;
    }
}

TEST(BSplineSurface, NormalCurvatureOfASphericalCapIsOneOverR) {
  const double R = 30.0;
  const auto xs = uniform(-8, 8, 11);
  const PointGrid g = grid_of(xs, xs, [&](double x, double y) { return std::sqrt(R * R - x * x - y * y); });
  const SurfaceFit f = interpolate_grid(g, 3, 1.0);
  ASSERT_TRUE(f.ok());
  for (int r = 2; r <= 8; ++r)
    for (int c = 2; c <= 8; ++c) {
      // the normal points up (+z), the sphere's centre lies below: curvature -1/R
      const NormalCurvatures k = normal_curvatures(surface_eval(f.surface, f.params_u[c], f.params_v[r]));
      EXPECT_NEAR(k.ku, -1.0 / R, 0.002 / R);
      EXPECT_NEAR(k.kv, -1.0 / R, 0.002 / R);
    }
}

TEST(SurfaceFit, FairnessMatchesAnIndependentSum) {
  for (double e : {0.0, 0.4, 1.0}) {
    const SurfaceFit f = interpolate_grid(wavy_grid(), 3, e);
    ASSERT_TRUE(f.ok());
    double sum = 0.0;
    for (double v : f.params_v)
      for (double u : f.params_u) {
        const NormalCurvatures k = independent_curvatures(f.surface, u, v);
        EXPECT_TRUE(std::isfinite(k.ku) && std::isfinite(k.kv)) << u << "," << v;
        sum += k.ku * k.ku + k.kv * k.kv;
      }
    EXPECT_NEAR(fairness(f), sum, 2e-3 * sum) << "e " << e;
  }
}

TEST(SurfaceFit, FairingLowersF) {
  const PointGrid g = wavy_grid();
  const FairFit fair = fair_fit(g, 3);
  ASSERT_TRUE(fair.fit.ok());
  EXPECT_GE(fair.e, 0.0);
  EXPECT_LE(fair.e, 1.0);
  EXPECT_NEAR(fairness(fair.fit), fair.fairness, 1e-12 * fair.fairness);
  double worst = 0.0;
  for (double e = 0.0; e <= 1.0; e += 0.01) {
    const double F = fairness(interpolate_grid(g, 3, e));
    EXPECT_LE(fair.fairness, F * (1 + 1e-9)) << "e " << e;
    worst = std::max(worst, F);
  }
  EXPECT_LT(fair.fairness, 0.99 * worst) << "F(e) is flat on this grid: the test proves nothing";
  EXPECT_LT(fair.fairness, fairness(interpolate_grid(g, 3, 1.0)));
}

TEST(SurfaceFit, RefusesWhatCannotBeInterpolated) {
  EXPECT_NE(interpolate_grid(grid_of(uniform(0, 1, 3), uniform(0, 1, 5), [](double, double) { return 0.0; }), 3, 1.0)
                .error.find("too small"),
            std::string::npos);
  EXPECT_FALSE(interpolate_grid(wavy_grid(), 3, 1.5).ok());
  EXPECT_FALSE(interpolate_grid(wavy_grid(), 0, 1.0).ok());
  PointGrid twin = wavy_grid();
  for (int r = 0; r < twin.rows; ++r) twin.points[static_cast<std::size_t>(r * twin.cols + 1)] = twin.at(0, r);
  EXPECT_NE(interpolate_grid(twin, 3, 1.0).error.find("coincide"), std::string::npos);
  PointGrid nan = wavy_grid();
  nan.points[5][2] = std::nan("");
  EXPECT_FALSE(interpolate_grid(nan, 3, 1.0).ok());
}

TEST(SurfaceHeight, OutsideTheFootprintHoldsTheEdge) {
  const SurfaceFit f = interpolate_grid(wavy_grid(), 3, 1.0);
  const SurfaceHeight in = surface_height(f.surface, 14.0, 5.0);
  const SurfaceHeight out = surface_height(f.surface, 20.0, 5.0);
  EXPECT_TRUE(in.inside);
  EXPECT_FALSE(out.inside);
  EXPECT_NEAR(out.u, 1.0, 1e-12);
  EXPECT_NEAR(out.z, in.z, 1e-9);
  // every data point is found again
  const PointGrid g = wavy_grid();
  for (const Vec3& p : g.points) EXPECT_NEAR(surface_height(f.surface, p[0], p[1]).z, p[2], 1e-9);
}

TEST(WienerSurface, DeterministicSymmetricAndScaled) {
  const WienerSurface a(42, 16, 0.02), b(42, 16, 0.02), c(43, 16, 0.02);
  double sq = 0.0, diff = 0.0;
  for (int j = 0; j <= 16; ++j)
    for (int i = 0; i <= 16; ++i) {
      EXPECT_EQ(a.node(i, j), b.node(i, j));
      EXPECT_NEAR(a.node(i, j), a.node(16 - i, j), 1e-15);
      EXPECT_NEAR(a.node(i, j), a.node(i, 16 - j), 1e-15);
      sq += a.node(i, j) * a.node(i, j);
      diff += std::fabs(a.node(i, j) - c.node(i, j));
    }
  EXPECT_NEAR(std::sqrt(sq / (17 * 17)), 0.02, 1e-12);
  EXPECT_GT(diff, 0.01);
  EXPECT_NEAR(a.value(0.25, 0.5), a.node(4, 8), 1e-15);
  EXPECT_NEAR(a.value(0.3, 0.7), a.value(0.7, 0.7), 1e-15);
  EXPECT_NEAR(a.smooth_value(0.3, 0.7), a.smooth_value(0.7, 0.3 + 0.4), 1e-15);
}

TEST(GridHeights, BaselinesPassThroughTheProbes) {
  const PointGrid g = wavy_grid();
  const GridHeights h(g);
  for (const Vec3& p : g.points) {
    EXPECT_NEAR(h.bilinear(p[0], p[1]), p[2], 1e-12);
    EXPECT_NEAR(h.catmull_rom(p[0], p[1]), p[2], 1e-12);
  }
  auto bil = [](double x, double y) { return 1 + 0.1 * x - 0.2 * y + 0.01 * x * y; };
  const GridHeights b(grid_of(uniform(0, 10, 5), uniform(0, 8, 4), bil));
  EXPECT_NEAR(b.bilinear(3.3, 5.1), bil(3.3, 5.1), 1e-12);
  EXPECT_NEAR(b.catmull_rom(3.3, 5.1), bil(3.3, 5.1), 1e-12);  // uniform grid: Catmull-Rom keeps linear terms
}

// ---- the surface file ----------------------------------------------------------------------

BSplineSurface sample_surface() { return interpolate_grid(wavy_grid(), 3, 0.5).surface; }

TEST(SurfaceFile, RoundTripIsExact) {
  const BSplineSurface s = sample_surface();
  const BSplineSurface r = parse_surface_json(surface_json(s), "s.json");
  EXPECT_EQ(r.degree, s.degree);
  EXPECT_EQ(r.count_u, s.count_u);
  EXPECT_EQ(r.count_v, s.count_v);
  EXPECT_EQ(r.knots_u, s.knots_u);
  EXPECT_EQ(r.knots_v, s.knots_v);
  EXPECT_EQ(r.points, s.points);
  EXPECT_EQ(r.e, s.e);
  const std::string path = ::testing::TempDir() + "/pcnc_surface_roundtrip.json";
  save_surface_file(path, s);
  EXPECT_EQ(load_surface_file(path).points, s.points);
}

// The message of the refusal of `text`, or "" when it was read.
std::string refusal(const std::string& text) {
  try {
    (void)parse_surface_json(text, "S.json");
  } catch (const SurfaceFileError& e) {
    return e.what();
  }
  return "";
}

std::string with(const std::string& key, const std::string& value) {
  std::string t = surface_json(sample_surface());
  const auto at = t.find("\"" + key + "\": ");
  const auto start = at + key.size() + 4;
  auto end = t.find(",\n  \"", start);
  if (end == std::string::npos) end = t.rfind("\n}");
  return t.substr(0, start) + value + t.substr(end);
}

std::string without(const std::string& key) {
  std::string t = surface_json(sample_surface());
  const auto at = t.find("  \"" + key + "\": ");
  auto end = t.find(",\n  \"", at);
  if (end == std::string::npos) return t.substr(0, t.rfind(",\n", at)) + "\n}\n";
  return t.substr(0, at) + t.substr(end + 2);
}

TEST(SurfaceFile, EveryKeyIsRequired) {
  for (const char* key : {"format", "version", "units", "degree", "e", "knots_u", "knots_v", "control_points"}) {
    const std::string why = refusal(without(key));
    EXPECT_NE(why.find("S.json: missing key '" + std::string(key) + "'"), std::string::npos) << key << ": " << why;
  }
}

TEST(SurfaceFile, RefusesEveryBrokenRule) {
  struct Case {
    std::string text, expect;
  };
  const std::vector<Case> cases = {
      {"not json", "not valid JSON"},
      {"[1, 2]", "expected a JSON object"},
      {with("units", "\"inch\""), "key 'units'"},
      {with("format", "\"other\""), "key 'format'"},
      {with("version", "2"), "key 'version'"},
      {with("version", "1.5"), "key 'version'"},
      {with("degree", "0"), "key 'degree'"},
      {with("degree", "\"3\""), "key 'degree'"},
      {with("e", "1.5"), "key 'e'"},
      {with("e", "1e999"), "number overflow"},
      {with("knots_u", "[0, 0, 0, 0, 1, 1, 1, 1]"), "key 'knots_u'"},
      {with("knots_v", "[0, 0, 0, 0, 0.5, 0.2, 0.6, 1, 1, 1]"), "key 'knots_v'"},
      {with("knots_v", "[0, 0, 0, 0.1, 0.3, 0.5, 1, 1, 1, 1]"), "clamped"},
      {with("knots_u", "[0, 0, 0, 0, 0.2, \"x\", 0.5, 0.7, 1, 1, 1, 1]"), "key 'knots_u[5]'"},
      {with("control_points", "[[[0, 0, 0]]]"), "key '"},
      {with("control_points", "[]"), "key 'control_points'"},
      {with("control_points", "[[[0, 0]]]"), "key 'control_points[0][0]'"},
      {with("control_points", "[[[0, 0, null]]]"), "key 'control_points[0][0]'"},
  };
  for (const Case& c : cases) {
    const std::string why = refusal(c.text);
    EXPECT_NE(why.find(c.expect), std::string::npos) << "expected '" << c.expect << "', got '" << why << "'";
    EXPECT_EQ(why.rfind("S.json: ", 0), 0u) << why;
  }
  // a short first row: the next row is refused against it
  std::string t = surface_json(sample_surface());
  const auto row = t.find("    [[");
  t.erase(row + 5, t.find("], [", row) - row - 3);
  EXPECT_NE(refusal(t).find("key 'control_points[1]': expected a row of 7"), std::string::npos) << refusal(t);
  // unknown key
  std::string extra = surface_json(sample_surface());
  extra.insert(2, "\"colour\": 1,\n  ");
  EXPECT_NE(refusal(extra).find("unknown key 'colour'"), std::string::npos);
}

TEST(SurfaceFile, RefusesFilesThatAreNotThere) {
  EXPECT_THROW(load_surface_file("/nonexistent/S.json"), SurfaceFileError);
  EXPECT_THROW(load_surface_file(::testing::TempDir()), SurfaceFileError);
}

}  // namespace
}  // namespace pcnc
