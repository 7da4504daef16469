// test_probe_contact.cpp — the table's objects and the probe's trigger model
// (shared/geometry/probe_contact.hpp) against independent computations: the plane's distance
// from its normal vector, the sphere's and the box's by construction, the bump's first-order
// gap against a brute-force minimum over the surface; and the [probe]/[workpiece] config.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>

#include "config/config.hpp"
#include "geometry/probe_contact.hpp"
#include "test_paths.hpp"

namespace pcnc {
namespace {

TEST(ProbeContact, TiltedPlaneGapIsThePointPlaneDistance) {
  TableScene s;
  s.has_surface = true;
  s.z_mm = 5.0;
  s.slope_x = 0.2;
  s.slope_y = -0.1;
  // the plane through (0, 0, 5) with normal (-0.2, 0.1, 1) (not normalised)
  const Vec3 n = normalized(Vec3{-0.2, 0.1, 1.0});
  for (const Vec3 c : {Vec3{1.0, 2.0, 9.0}, Vec3{-3.0, 4.0, 5.5}, Vec3{7.0, -1.0, 2.0}}) {
    const double expected = dot(c - Vec3{0.0, 0.0, 5.0}, n);
    EXPECT_NEAR(surface_gap(s, c), expected, 1e-12);
  }
  EXPECT_TRUE(ball_touches(s, Vec3{0.0, 0.0, 5.9}, 1.0));
  EXPECT_FALSE(ball_touches(s, Vec3{0.0, 0.0, 6.1}, 1.0));
}

TEST(ProbeContact, SphereAndGaugeBlockGaps) {
  TableScene s;
  s.sphere_center = {10.0, 10.0, 5.0};
  s.sphere_radius_mm = 3.0;
  EXPECT_NEAR(sphere_gap(s, {10.0, 10.0, 10.0}), 2.0, 1e-12);
  EXPECT_NEAR(sphere_gap(s, {13.0, 14.0, 5.0}), 2.0, 1e-12);  // 3-4-5
  EXPECT_NEAR(sphere_gap(s, {10.0, 10.0, 5.0}), -3.0, 1e-12);
  EXPECT_EQ(gauge_gap(s, {0.0, 0.0, 0.0}), kNoContact);
  EXPECT_EQ(surface_gap(s, {0.0, 0.0, 0.0}), kNoContact);

  s.has_gauge = true;
  s.gauge_min = {0.0, 0.0, 0.0};
  s.gauge_max = {4.0, 2.0, 1.0};
  EXPECT_NEAR(gauge_gap(s, {2.0, 1.0, 3.0}), 2.0, 1e-12);                         // above a face
  EXPECT_NEAR(gauge_gap(s, {7.0, 6.0, 0.5}), 5.0, 1e-12);                         // off an edge: 3-4-5
  EXPECT_NEAR(gauge_gap(s, {5.0, 3.0, 2.0}), std::sqrt(3.0), 1e-12);              // off a corner
  EXPECT_NEAR(gauge_gap(s, {3.5, 1.0, 0.5}), -0.5, 1e-12);                        // inside: nearest face
  EXPECT_NEAR(scene_gap(s, {2.0, 1.0, 3.0}), std::min(2.0, norm(Vec3{2.0, 1.0, 3.0} - s.sphere_center) - 3.0), 1e-12);
}

// The bump's gap against the distance to the nearest of a fine grid of surface points.
TEST(ProbeContact, BumpGapAgreesWithBruteForceNearTheSurface) {
  TableScene s;
  s.has_surface = true;
  s.z_mm = 2.0;
  s.bump_x_mm = 10.0;
  s.bump_y_mm = 10.0;
  s.bump_height_mm = 1.0;
  s.bump_sigma_mm = 4.0;
  double dzdx = 0.0, dzdy = 0.0;
  const double h = surface_height(s, 12.0, 9.0, &dzdx, &dzdy);
  EXPECT_NEAR(h, 2.0 + std::exp(-5.0 / 32.0), 1e-12);
  const double e = 1e-6;
  EXPECT_NEAR(dzdx, (surface_height(s, 12.0 + e, 9.0) - surface_height(s, 12.0 - e, 9.0)) / (2 * e), 1e-8);
  EXPECT_NEAR(dzdy, (surface_height(s, 12.0, 9.0 + e) - surface_height(s, 12.0, 9.0 - e)) / (2 * e), 1e-8);
  for (const Vec3 xy : {Vec3{10.0, 10.0, 0.0}, Vec3{13.0, 10.0, 0.0}, Vec3{12.0, 6.0, 0.0}}) {
    const Vec3 c{xy[0], xy[1], surface_height(s, xy[0], xy[1]) + 0.996};  // a 1 mm ball about to trigger
    double best = 1e9;
    for (double x = c[0] - 1.5; x <= c[0] + 1.5; x += 0.005) {
      for (double y = c[1] - 1.5; y <= c[1] + 1.5; y += 0.005) {
        best = std::min(best, norm(c - Vec3{x, y, surface_height(s, x, y)}));
      }
    }
    // first order: off by about R^2 * curvature; the curvature here is below 1/16 mm^-1
    EXPECT_NEAR(surface_gap(s, c), best, 0.03) << xy[0] << "," << xy[1];
    EXPECT_GT(surface_gap(s, c), 0.0);
  }
}

TEST(ProbeContact, PretravelLobesWithTheAzimuth) {
  ProbeModel p;
  p.pretravel_axial_mm = 0.004;
  p.pretravel_lateral_mm = 0.008;
  p.pretravel_lobe_mm = 0.003;
  EXPECT_DOUBLE_EQ(pretravel_mm(p, {0.0, 0.0, -1.0}), 0.004);
  EXPECT_DOUBLE_EQ(pretravel_mm(p, {0.0, 0.0, 2.0}), 0.004);
  EXPECT_NEAR(pretravel_mm(p, {1.0, 0.0, 0.0}), 0.011, 1e-15);                 // cos 0 = 1
  EXPECT_NEAR(pretravel_mm(p, {-1.0, 0.0, 0.0}), 0.005, 1e-15);                // cos 3pi = -1
  EXPECT_NEAR(pretravel_mm(p, {0.0, 1.0, 0.0}), 0.008, 1e-15);                 // cos 3pi/2 = 0
  const double t = 2.0 * std::numbers::pi / 3.0;                               // lobes repeat every 120 deg
  EXPECT_NEAR(pretravel_mm(p, {std::cos(t), std::sin(t), 0.0}), 0.011, 1e-15);
  // 45 deg down and along +X: half axial, half lateral
  EXPECT_NEAR(pretravel_mm(p, {1.0, 0.0, -1.0}), 0.5 * 0.004 + 0.5 * 0.011, 1e-15);
}

TEST(ProbeConfig, TheDefaultMachineHasAProbeAndAFlatWorkpiece) {
  const MachineConfig c = load_config(test::default_config());
  ASSERT_TRUE(c.probe.present);
  EXPECT_DOUBLE_EQ(c.probe.model.ball_radius_mm, 1.0);
  EXPECT_TRUE(c.table.has_surface);
  EXPECT_DOUBLE_EQ(c.table.z_mm, 15.0);
  EXPECT_EQ(c.table.bump_height_mm, 0.0);
  EXPECT_FALSE(c.table.has_gauge);
}

std::string shipped() {
  const MachineConfig c = load_config(test::default_config());
  std::ifstream in(c.source_path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::string probe_refusal(const std::string& text) {
  try {
    parse_config(text, "v.toml");
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(ProbeConfig, TheWorkpieceSectionIsCheckedLikeTheRest) {
  std::string text = shipped();
  const std::string surface = "surface = \"plane\"";
  ASSERT_NE(text.find(surface), std::string::npos);
  auto with = [&](const std::string& to) {
    std::string t = text;
    t.replace(t.find(surface), surface.size(), to);
    return t;
  };
  EXPECT_NE(probe_refusal(with("surface = \"wavy\"")).find("surface 'wavy' must be"), std::string::npos);
  EXPECT_NE(probe_refusal(with("surface = \"bump\"")).find("missing key 'bump_height_mm'"), std::string::npos);
  const MachineConfig bump = parse_config(
      with("surface = \"bump\"\nbump_x_mm = 5.0\nbump_y_mm = 6.0\nbump_height_mm = 0.5\nbump_sigma_mm = 3.0\n"
           "sphere_center_mm = [20.0, 20.0, 10.0]\nsphere_radius_mm = 2.0\n"
           "gauge_min_mm = [1.0, 1.0, 10.0]\ngauge_max_mm = [4.0, 3.0, 16.0]"),
      "v.toml");
  EXPECT_DOUBLE_EQ(bump.table.bump_height_mm, 0.5);
  EXPECT_DOUBLE_EQ(bump.table.sphere_radius_mm, 2.0);
  EXPECT_TRUE(bump.table.has_gauge);
  EXPECT_DOUBLE_EQ(bump.table.gauge_max[2], 16.0);
  EXPECT_NE(probe_refusal(with("surface = \"plane\"\ngauge_min_mm = [1.0, 1.0, 10.0]")).find("go together"), std::string::npos);
  EXPECT_NE(probe_refusal(with("surface = \"plane\"\ngauge_min_mm = [1.0, 1.0, 10.0]\ngauge_max_mm = [0.0, 3.0, 16.0]"))
                .find("must exceed gauge_min_mm"),
            std::string::npos);
  EXPECT_NE(probe_refusal(with("surface = \"plane\"\nsurfce = 1")).find("unknown key 'surfce'"), std::string::npos);
  const std::string lobe = "pretravel_lobe_mm = 0.003";
  std::string t = text;
  t.replace(t.find(lobe), lobe.size(), "pretravel_lobe_mm = 0.009");
  EXPECT_NE(probe_refusal(t).find("must not exceed pretravel_lateral_mm"), std::string::npos);
}

}  // namespace
}  // namespace pcnc
