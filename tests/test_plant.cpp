// test_plant.cpp — the simulated axis: exact ZOH integration, friction and stiction,
// saturation, gravity and brake, encoder quantisation, step-size independence.
#include <gtest/gtest.h>

#include <cmath>

#include "machine_runner.hpp"
#include "make_blocks.hpp"
#include "drive/plant.hpp"

namespace pcnc {
namespace {

AxisConfig axis() {
  AxisConfig a;
  a.moving_mass_kg = 2.0;
  a.force_constant_n_per_a = 12.0;
  a.current_limit_a = 4.0;
  a.viscous_friction_n_s_per_m = 8.0;
  a.coulomb_friction_n = 0.0;
  a.gravity_load_n = 0.0;
  a.encoder_resolution_mm = 0.0001;
  return a;
}

TEST(Plant, MatchesTheAnalyticSolutionUnderConstantCurrent) {
  const AxisConfig a = axis();
  AxisPlant p(a, 0.0005, 1, 0.0);
  const double F = 12.0 * 1.0, m = 2.0, b = 8.0;  // 1 A
  for (int k = 0; k < 400; ++k) p.step(1.0, true);
  const double t = 400 * 0.0005, lam = b / m, vinf = 1000.0 * F / b;
  const double x = vinf * t - vinf * (1.0 - std::exp(-lam * t)) / lam;
  EXPECT_NEAR(p.position(), x, 1e-9);
  EXPECT_NEAR(p.velocity(), vinf * (1.0 - std::exp(-lam * t)), 1e-9);
}

TEST(Plant, CurrentSaturatesAtTheAmplifierLimit) {
  AxisPlant p(axis(), 0.0005, 4, 0.0);
  p.step(100.0, true);
  EXPECT_EQ(p.applied_current(), 4.0);
  p.step(-100.0, true);
  EXPECT_EQ(p.applied_current(), -4.0);
}

TEST(Plant, StictionHoldsUntilTheForceBeatsCoulombFriction) {
  AxisConfig a = axis();
  a.coulomb_friction_n = 1.5;  // 0.125 A
  AxisPlant p(a, 0.0005, 8, 5.0);
  for (int k = 0; k < 100; ++k) p.step(0.12, true);
  EXPECT_EQ(p.position(), 5.0);
  for (int k = 0; k < 100; ++k) p.step(0.2, true);
  EXPECT_GT(p.position(), 5.0);
  // coasting with the current off: friction stops it and it stays stopped (no chatter)
  for (int k = 0; k < 4000; ++k) p.step(0.0, true);
  const double x = p.position();
  EXPECT_EQ(p.velocity(), 0.0);
  for (int k = 0; k < 100; ++k) p.step(0.0, true);
  EXPECT_EQ(p.position(), x);
}

TEST(Plant, GravityPullsZDownUnlessTheBrakeHolds) {
  AxisConfig a = axis();
  a.moving_mass_kg = 0.8;
  a.gravity_load_n = 7.85;
  a.viscous_friction_n_s_per_m = 0.0;
  AxisPlant p(a, 0.0005, 8, 20.0);
  for (int k = 0; k < 20; ++k) p.step(0.0, true);  // amplifier on, no current: free fall
  const double t = 0.01;
  EXPECT_NEAR(p.position(), 20.0 - 0.5 * 1000.0 * 7.85 / 0.8 * t * t, 1e-9);
  AxisPlant q(a, 0.0005, 8, 20.0);
  for (int k = 0; k < 200; ++k) q.step(0.0, false);  // amplifier off: brake
  EXPECT_EQ(q.position(), 20.0);
  AxisPlant h(a, 0.0005, 8, 20.0);
  for (int k = 0; k < 200; ++k) h.step(7.85 / 12.0, true);  // holding current
  EXPECT_NEAR(h.position(), 20.0, 1e-9);
}

TEST(Plant, EncoderQuantisesToItsResolution) {
  AxisPlant p(axis(), 0.0005, 1, 1.23456789);
  EXPECT_NEAR(p.encoder(), 1.2346, 1e-12);
  EXPECT_LE(std::abs(p.encoder() - p.position()), 0.00005 + 1e-15);
}

TEST(Plant, BlockedAxisDoesNotMove) {
  AxisPlant p(axis(), 0.0005, 1, 3.0);
  p.set_blocked(true);
  for (int k = 0; k < 100; ++k) p.step(4.0, true);
  EXPECT_EQ(p.position(), 3.0);
}

// The reference move: a diagonal rapid and a fast line with reversal, max |ferr| per axis.
Vec3 reference_following_error(double substeps) {
  MachineConfig c = test::default_machine_config();
  c.motion.subsample_steps = substeps;
  for (auto& a : c.axes) a.encoder_resolution_mm = 0.0;  // isolate the integration
  test::MachineRunner run(c);
  test::ProgramBuilder p(c, test::home(c));
  p.rapid({2.0, 3.0, 15.0}).line({23.0, 20.0, 15.0}, 80.0).line({5.0, 20.0, 18.0}, 60.0).end();
  run.start(p.blocks());
  run.run_until_done();
  EXPECT_EQ(run.status().program_done, 1);
  return run.status().max_following_error;
}

TEST(Plant, HalvingTheIntegrationStepChangesTheFollowingErrorByUnderOnePercent) {
  for (double n : {1.0, 4.0, 8.0}) {
    const Vec3 e1 = reference_following_error(n);
    const Vec3 e2 = reference_following_error(2.0 * n);
    for (int i = 0; i < kAxes; ++i) {
      ASSERT_GT(e1[i], 0.0);
      EXPECT_LT(std::abs(e2[i] - e1[i]) / e1[i], 0.01) << "axis " << i << " substeps " << n;
    }
    if (n == 8.0) {
      std::printf("reference move max ferr (8 / 16 substeps): X %.4f/%.4f Y %.4f/%.4f Z %.4f/%.4f um\n", e1[0] * 1e3,
                  e2[0] * 1e3, e1[1] * 1e3, e2[1] * 1e3, e1[2] * 1e3, e2[2] * 1e3);
    }
  }
}

}  // namespace
}  // namespace pcnc
