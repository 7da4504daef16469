// test_sim_table.cpp — the simulated table's additions for issue 15 item 1: a B-spline surface
// as the workpiece top (height and gradient against the plane it represents), the seed's
// Wiener machining error added to it (the gradient against finite differences), the ball
// plate, the config keys that describe them, and the machine's volumetric error seen by the
// simulated probe only (the trigger height moves by the error).
#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "config/config.hpp"
#include "drive/sim_probe.hpp"
#include "geometry/probe_contact.hpp"
#include "subprocess.hpp"

namespace pcnc {
namespace {

// z = 5 + 0.2 x - 0.1 y over [0, 10]^2 as a bicubic patch with unevenly spaced control points
// in x (the parameter is not x: the gradient must come through the Jacobian).
BSplineSurface tilted_table_plane() {
  return bicubic_patch([](int i, int j) {
    const double u = i / 3.0, v = j / 3.0;
    const double x = 10.0 * u * u * 0.5 + 10.0 * u * 0.5, y = 10.0 * v;  // x = 5u² + 5u: monotone, not linear
    return Vec3{x, y, 5.0 + 0.2 * x - 0.1 * y};
  });
}

TEST(SimTable, ABSplineTopGivesTheHeightAndGradientOfThePlaneItHolds) {
  // z of every control point is the same affine function of its x and y, so (the basis sums
  // to 1) every point of the patch lies on the plane, whatever x(u) is
  TableScene s;
  s.has_surface = true;
  s.bspline = std::make_shared<const BSplineSurface>(tilted_table_plane());
  for (double x : {1.0, 3.3, 7.9})
    for (double y : {0.5, 4.0, 9.5}) {
      double gx = 0, gy = 0;
      const double z = surface_height(s, x, y, &gx, &gy);
      EXPECT_NEAR(z, 5.0 + 0.2 * x - 0.1 * y, 1e-9) << x << " " << y;
      EXPECT_NEAR(gx, 0.2, 1e-9);
      EXPECT_NEAR(gy, -0.1, 1e-9);
      // the gap is the exact distance to the plane
      const Vec3 c{x, y, z + 1.0};
      EXPECT_NEAR(surface_gap(s, c), 1.0 / std::sqrt(1.0 + 0.04 + 0.01), 1e-9);
    }
}

TEST(SimTable, TheWienerErrorIsAddedWithItsGradient) {
  TableScene s;
  s.has_surface = true;
  s.z_mm = 3.0;
  s.error = std::make_shared<const WienerSurface>(7, 4, 0.01);
  s.error_x0_mm = 10.0, s.error_x1_mm = 30.0, s.error_y0_mm = -5.0, s.error_y1_mm = 15.0;
  double rms = 0.0;
  int n = 0;
  for (double x = 10.5; x < 30.0; x += 1.7)
    for (double y = -4.5; y < 15.0; y += 1.9) {
      double gx = 0, gy = 0;
      const double z = surface_height(s, x, y, &gx, &gy);
      const double e = s.error->smooth_value((x - 10.0) / 20.0, (y + 5.0) / 20.0);
      EXPECT_NEAR(z, 3.0 + e, 1e-12);
      const double h = 1e-3;
      const double fx = (surface_height(s, x + h, y) - surface_height(s, x - h, y)) / (2 * h);
      const double fy = (surface_height(s, x, y + h) - surface_height(s, x, y - h)) / (2 * h);
      EXPECT_NEAR(gx, fx, 1e-7);
      EXPECT_NEAR(gy, fy, 1e-7);
      rms += e * e, ++n;
    }
  rms = std::sqrt(rms / n);
  EXPECT_GT(rms, 0.003);  // an error of about the asked size is there
  EXPECT_LT(rms, 0.03);
}

TEST(SimTable, TheBallPlateIsTouchable) {
  TableScene s;
  s.artefact_balls = 2;
  s.artefact_centres[0] = {0, 0, 0};
  s.artefact_centres[1] = {10, 0, 0};
  s.artefact_ball_radius_mm = 2.0;
  EXPECT_NEAR(artefact_gap(s, {10, 0, 3}), 1.0, 1e-12);
  EXPECT_NEAR(scene_gap(s, {4, 0, 0}), 2.0, 1e-12);
  s.artefact_balls = 0;
  EXPECT_EQ(scene_gap(s, {4, 0, 0}), kNoContact);
}

const char* kKeys = R"(surface = "plane"
z_mm = 15.0
error_seed = 3
error_rms_mm = 0.005
artefact_balls_mm = [[2.0, 2.0, 20.0], [22.0, 2.0, 20.0]]
artefact_ball_radius_mm = 1.5

[machine_error]
pitch_x_mm = [0.0, 0.002]
pitch_x_start_mm = 0.0
pitch_x_step_mm = 25.0
origin_drift_mm = [0.0, 0.0, 0.01]
)";

TEST(SimTable, ConfigKeysAndTheMachineErrorSeenByTheProbeOnly) {
  const std::string dir = test::make_temp_dir("simtable");
  const std::string path = test::write_test_config(
      dir, "simtable",
      {{"surface = \"plane\"                 # \"plane\", \"bump\" (a Gaussian bump on the plane) or \"none\"\nz_mm = 15.0",
        kKeys}});
  const MachineConfig c = load_config(path);
  ASSERT_TRUE(c.has_machine_error);
  EXPECT_EQ(c.machine_error.pitch[0].count, 2);
  EXPECT_DOUBLE_EQ(c.machine_error.pitch[0].error_mm[1], 0.002);
  EXPECT_DOUBLE_EQ(c.machine_error.origin_drift_mm[2], 0.01);
  ASSERT_NE(c.table.error, nullptr);
  EXPECT_DOUBLE_EQ(c.table.error_x1_mm, c.axes[0].travel_max_mm);  // the rectangle defaults to the travel
  EXPECT_EQ(c.table.artefact_balls, 2);
  EXPECT_DOUBLE_EQ(c.table.artefact_centres[1][0], 22.0);

  // an origin drift of +0.01 mm in Z puts the ball 0.01 mm above the commanded centre, so it
  // reaches the top when the commanded centre is 0.01 mm lower than without the error
  MachineConfig quiet = c;
  quiet.probe.model.repeatability_mm = 0.0;
  MachineConfig ideal = quiet;
  ideal.has_machine_error = false;
  SimProbe with(quiet), without(ideal);
  with.arm({0, 0, -1});
  without.arm({0, 0, -1});
  auto trigger_z = [](SimProbe& p) {
    double lo = 10.0, hi = 20.0;  // bisection on the commanded Z at X 12.5 Y 12.5
    for (int i = 0; i < 60; ++i) {
      const double mid = 0.5 * (lo + hi);
      (p.sense({12.5, 12.5, mid}) ? lo : hi) = mid;
    }
    return lo;
  };
  const double z_with = trigger_z(with), z_without = trigger_z(without);
  // E at (12.5, 12.5): pitch X 0.001 (in X), drift 0.01 in Z; the X shift moves the contact on
  // the Wiener error by its slope times 0.001 mm, negligible
  EXPECT_NEAR(z_without - z_with, 0.01, 1e-6);
}

TEST(SimTable, ABadMachineErrorIsRefusedByName) {
  const std::string dir = test::make_temp_dir("simtablebad");
  const std::string path = test::write_test_config(
      dir, "simtablebad",
      {{"surface = \"plane\"                 # \"plane\", \"bump\" (a Gaussian bump on the plane) or \"none\"\nz_mm = 15.0",
        "surface = \"plane\"\nz_mm = 15.0\n\n[machine_error]\npitch_y_mm = [0.0, 0.5]\npitch_y_start_mm = 0.0\n"
        "pitch_y_step_mm = 1.0\n"}});
  try {
    (void)load_config(path);
    FAIL() << "a pitch slope of 50 % was accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("[machine_error]"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("pitch"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace pcnc
