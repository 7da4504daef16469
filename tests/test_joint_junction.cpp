// test_joint_junction.cpp — the joint-space junction rule (rt/motion/junction.hpp
// joint_junction_speed) and the joints' rates at a block's ends it is fed with (rt/motion/path.hpp
// prepare_block, tcp_end_rates), on configs/desktop-5axis.toml: a straight continuation passes at
// the blocks' own speed, a joint that reverses passes only at the speed at which its whole reversal
// is one cycle's allowed velocity step (practically a stop), and at the speed returned every joint's
// velocity step stays within its budget, the limiting joint exactly on it.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "config/joint_map.hpp"
#include "gcode_test_util.hpp"
#include "ipc/block_check.hpp"
#include "motion/junction.hpp"
#include "motion/path.hpp"
#include "test_paths.hpp"
#include "machine_runner.hpp"

namespace pcnc {
namespace {

using test::run_program;


JointRate joint_accels(const MachineConfig& cfg) {
  JointRate a{};
  for (int i = 0; i < kAxes; ++i) a[static_cast<std::size_t>(i)] = cfg.axes[static_cast<std::size_t>(i)].max_accel_mm_s2;
  for (int i = 0; i < kRotaryJoints; ++i) {
    const auto& r = cfg.rotary[static_cast<std::size_t>(i)];
    a[static_cast<std::size_t>(kAxes + i)] = r ? r->max_accel_rad_s2 : 0.0;
  }
  return a;
}

// The program's motion blocks prepared as the rt prepares them (the TCP ones with their end rates
// from the joints each starts at).
std::vector<PreparedBlock> prepared(const std::string& program, const MachineConfig& cfg) {
  JobOptions o;
  o.start_position = Vec3{12.5, 12.5, 25.0};
  const auto r = run_program(program, cfg, o);
  EXPECT_TRUE(r.check.ok) << (r.first_error() ? r.first_error()->message : "");
  std::vector<PreparedBlock> out;
  Vec3 xyz = *o.start_position;
  Rot3 rot{};
  for (const Block& b : r.motion()) {
    PreparedBlock p = prepare_block(b, cfg);
    if (p.tcp) tcp_end_rates(p, b, cfg, xyz);
    block_tail(b, xyz, rot);
    out.push_back(p);
  }
  return out;
}

double junction(const PreparedBlock& p, const PreparedBlock& q, const MachineConfig& cfg) {
  return joint_junction_speed(p.jrate_end, p.jcurv_end, q.jrate_start, q.jcurv_start, joint_accels(cfg),
                              cfg.cycle_period_s(), cfg.motion.junction_velocity_step_fraction);
}

TEST(JointJunction, AStraightContinuationPassesAtSpeed) {
  const MachineConfig cfg = test::five_axis_config();
  // TCP off: two lines turning C at the same rate per mm along the same direction
  {
    const auto b = prepared("G21 G90 M21\nG1 X0 Y0 Z-5 F600\nG1 X1 C10 F600\nG1 X2 C20\nM2\n", cfg);
    ASSERT_EQ(b.size(), 3u);
    ASSERT_TRUE(b[1].rotary && !b[1].tcp);
    EXPECT_NEAR(b[1].jrate_end[5], 10.0 * kRadPerDeg, 1e-12) << "C's rate: rad per mm of path";
    EXPECT_EQ(junction(b[1], b[2], cfg), std::numeric_limits<double>::infinity());
  }
  // TCP on: the tool axis tilting about X on one great circle (C = 0, A 10 -> 20 -> 30) while the
  // tip runs on one line: the joints' rates at the junction agree, only the joints' curvature
  // bounds the speed (what the blocks' own caps already hold along them), above the blocks' speeds
  const auto b = prepared("G21 G90 M21\nG1 X0 Y0 Z-5 F600\nG1 A10 F3600\nM428\nG1 X1 A20 F600\nG1 X2 A30\nM2\n", cfg);
  ASSERT_EQ(b.size(), 4u);
  ASSERT_TRUE(b[2].tcp && b[3].tcp);
  for (int j = 0; j < kMachineJoints; ++j) {
    EXPECT_NEAR(b[2].jrate_end[static_cast<std::size_t>(j)], b[3].jrate_start[static_cast<std::size_t>(j)], 1e-9) << "joint " << j;
  }
  EXPECT_NEAR(b[2].jrate_end[3], 10.0 * kRadPerDeg, 1e-9) << "A turns 10 deg per mm";
  const double v = junction(b[2], b[3], cfg);
  EXPECT_GT(v, std::max(b[2].speed, b[3].speed));
}

TEST(JointJunction, AJointThatReversesPracticallyStops) {
  const MachineConfig cfg = test::five_axis_config();
  // TCP on, the tip straight on along X, A 10 -> 20 -> 10: A's rate reverses at the junction
  const auto b = prepared("G21 G90 M21\nG1 X0 Y0 Z-5 F600\nG1 A10 F3600\nM428\nG1 X1 A20 F600\nG1 X2 A10\nM2\n", cfg);
  ASSERT_EQ(b.size(), 4u);
  const double rate = b[2].jrate_end[3];
  EXPECT_NEAR(rate, 10.0 * kRadPerDeg, 1e-9);
  EXPECT_NEAR(b[3].jrate_start[3], -rate, 1e-9);
  const double f = cfg.motion.junction_velocity_step_fraction;
  const double a_A = cfg.rotary[0]->max_accel_rad_s2;
  const double dt = cfg.cycle_period_s();
  const double v = junction(b[2], b[3], cfg);
  // A's whole reversal, 2·rate·v, fits in one cycle's allowed step, and so A's speed at the
  // junction is at most half of that step: 0.9 deg/s against its 180 deg/s
  EXPECT_LE(2.0 * rate * v, f * a_A * dt * (1.0 + 1e-12));
  EXPECT_LE(rate * v, 0.5 * f * a_A * dt * (1.0 + 1e-12));
  EXPECT_LT(v, 0.01 * std::min(b[2].speed, b[3].speed)) << "under 1 % of the blocks' speed";
  EXPECT_GT(v, 0.0);
}

TEST(JointJunction, EveryJointsVelocityStepStaysWithinItsBudget) {
  std::mt19937 rng(16);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  JointRate accel{2000.0, 2000.0, 1500.0, 62.8, 0.0, 125.7};
  const double dt = 5e-4, f = 0.5;
  for (int trial = 0; trial < 2000; ++trial) {
    JointRate re{}, rs{}, ce{}, cs{};
    for (int j = 0; j < kMachineJoints; ++j) {
      if (j == 4) continue;  // a joint the machine lacks never moves
      const auto k = static_cast<std::size_t>(j);
      const double scale = j < 3 ? 1.0 : 0.3;
      re[k] = scale * u(rng);
      rs[k] = re[k] + scale * 0.05 * u(rng) * (trial % 3 == 0 ? 20.0 : 1.0);
      ce[k] = (trial % 2 == 0) ? 0.5 * u(rng) : 0.0;
      cs[k] = (trial % 2 == 0) ? 0.5 * u(rng) : 0.0;
    }
    const double v = joint_junction_speed(re, ce, rs, cs, accel, dt, f);
    ASSERT_TRUE(std::isfinite(v) && v > 0.0) << trial;
    double tightest = 1e300;  // the smallest slack over the joints, relative to the budget
    for (int j = 0; j < kMachineJoints; ++j) {
      const auto k = static_cast<std::size_t>(j);
      if (accel[k] == 0.0) continue;
      const double curv = std::max(std::abs(ce[k]), std::abs(cs[k]));
      const double budget = f * (accel[k] - curv * v * v) * dt;
      const double step = v * std::abs(rs[k] - re[k]);
      ASSERT_LE(step, budget + 1e-12 * f * accel[k] * dt) << "trial " << trial << " joint " << j;
      tightest = std::min(tightest, (budget - step) / (f * accel[k] * dt));
    }
    EXPECT_LT(tightest, 1e-9) << "trial " << trial << ": the limiting joint is on its budget";
  }
  // nothing changes and nothing is curved: no cap
  const JointRate same{0.3, -0.2, 0.1, 0.05, 0.0, -0.4};
  EXPECT_EQ(joint_junction_speed(same, {}, same, {}, accel, dt, f), std::numeric_limits<double>::infinity());
}

}  // namespace
}  // namespace pcnc
