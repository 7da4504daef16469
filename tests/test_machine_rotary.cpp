// test_machine_rotary.cpp — the rotary joints in the rt's machine, in-process (virtual time, no
// timing): they start at their homes and stand still under the servo, a jog moves one (axis 3, 4,
// 5 = A, B, C) and stops at its travel, a joint the machine lacks is not jogged, and the trace
// sample of the joints follows the status.
#include <gtest/gtest.h>

#include <cmath>

#include "config/config.hpp"
#include "machine_runner.hpp"
#include "test_paths.hpp"

namespace pcnc {
namespace {


TEST(MachineRotary, JointsStartAtHomeAndHoldStill) {
  test::MachineRunner run(test::five_axis_config());
  run.run(2000);
  const Status& s = run.status();
  EXPECT_EQ(s.rotary_mask, 0b101);
  for (int i : {0, 2}) {
    EXPECT_EQ(s.rot_commanded[static_cast<std::size_t>(i)], 0.0);
    EXPECT_LT(std::abs(s.rot_actual[static_cast<std::size_t>(i)]), 1e-4);
  }
  EXPECT_EQ(run.machine().trace_joints().mask, 0b101);
}

TEST(MachineRotary, JogMovesAJointAndStopsAtItsTravel) {
  const MachineConfig cfg = test::five_axis_config();
  test::MachineRunner run(cfg);
  const double deg = kRadPerDeg;
  run.send(CommandKind::kJogIncrement, 10.0 * deg, 3, 60.0 * deg);  // A +10 deg at 60 deg/s
  run.run(5);
  EXPECT_EQ(run.status().state, MachineState::kJogging);
  run.run_while([](const Status& s) { return s.state == MachineState::kJogging; }, 100000);
  EXPECT_EQ(run.status().state, MachineState::kIdle);
  EXPECT_NEAR(run.status().rot_commanded[0], 10.0 * deg, 1e-12);
  run.run(2000);
  EXPECT_NEAR(run.status().rot_actual[0], 10.0 * deg, 2e-5);
  EXPECT_NEAR(run.machine().trace_joints().actual[0], run.status().rot_actual[0], 1e-15);
  // the velocity never exceeded the jog's feed
  double vmax = 0.0;
  test::MachineRunner run2(cfg);
  run2.send(CommandKind::kJogIncrement, 200.0 * deg, 3, 90.0 * deg);  // beyond the 95 deg travel
  for (int i = 0; i < 20000 && (i < 5 || run2.status().state == MachineState::kJogging); ++i) {
    run2.cycle();
    vmax = std::max(vmax, std::abs(run2.status().rot_velocity[0]));
  }
  EXPECT_NEAR(run2.status().rot_commanded[0], cfg.rotary[0]->travel_max_rad, 1e-12) << "clamped to the travel";
  EXPECT_LE(vmax, 90.0 * deg * (1.0 + 1e-9));
  EXPECT_EQ(run2.status().fault, FaultCode::kNone);
  // C is continuous: a jog past a turn is fine
  run2.send(CommandKind::kJogIncrement, 400.0 * deg, 5, 360.0 * deg);
  run2.run(5);
  run2.run_while([](const Status& s) { return s.state == MachineState::kJogging; }, 200000);
  EXPECT_NEAR(run2.status().rot_commanded[2], 400.0 * deg, 1e-9);
  // the executor took the joints up where the jog left them: a program continues from there
  EXPECT_EQ(run2.status().state, MachineState::kIdle);
}

TEST(MachineRotary, AJointTheMachineLacksIsNotJogged) {
  test::MachineRunner run(test::five_axis_config());
  run.send(CommandKind::kJogIncrement, 0.1, 4, 1.0);  // B on an XYZAC machine
  run.run(10);
  EXPECT_EQ(run.status().state, MachineState::kIdle);
  EXPECT_EQ(run.status().rot_commanded[1], 0.0);
  test::MachineRunner three(load_config(test::default_config()));
  three.send(CommandKind::kJogIncrement, 0.1, 3, 1.0);
  three.run(10);
  EXPECT_EQ(three.status().state, MachineState::kIdle);
  EXPECT_EQ(three.status().rotary_mask, 0);
  EXPECT_EQ(three.machine().trace_joints().mask, 0);
}

}  // namespace
}  // namespace pcnc
