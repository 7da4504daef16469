// test_machine_survival.cpp — the Machine driven in-process (no processes) when something
// outside it goes wrong: a shutdown request (the first SIGTERM) stops a program or a jog along
// the path and starts nothing; a restarted rt takes up the last measured position at rest; a
// trace that cannot be written stops the program or only tells (process.on_trace_failure);
// the host lost mid-program (the rt stops along the path and holds).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "machine_runner.hpp"
#include "make_blocks.hpp"

namespace pcnc {
namespace {

using test::long_line;
using test::MachineRunner;
using test::run_to_line;


TEST(Machine, ShutdownStopsAlongThePathAndStartsNothing) {
  MachineConfig c = test::default_machine_config();
  MachineRunner run(c);
  run.start(long_line(c, 40.0));
  run_to_line(run, 2, 40.0);
  EXPECT_FALSE(run.machine().motion_at_rest());
  run.machine().begin_shutdown();
  EXPECT_EQ(run.status().state, MachineState::kStopping);
  run.run_while([](const Status& s) { return s.state == MachineState::kStopping; }, 10000);
  EXPECT_EQ(run.status().state, MachineState::kIdle);
  EXPECT_EQ(run.status().path_speed, 0.0);
  EXPECT_TRUE(run.machine().motion_at_rest());
  EXPECT_EQ(run.check_setpoint_limits(), "");
  const Vec3 held = run.status().commanded;
  run.send(CommandKind::kProgramStart);
  run.send(CommandKind::kJogIncrement, 1.5, 0, 10.0);
  run.start(long_line(c, 40.0));  // a new program's blocks arrive too
  run.run(200);
  EXPECT_EQ(run.status().state, MachineState::kIdle);
  EXPECT_EQ(run.status().commanded, held);
  EXPECT_TRUE(run.machine().motion_at_rest());
}

TEST(Machine, ShutdownWhileJoggingDeceleratesTheJog) {
  MachineConfig c = test::default_machine_config();
  MachineRunner run(c);
  run.send(CommandKind::kJogContinuous, 1.0, 0, 20.0);
  run.run(200);
  EXPECT_NEAR(run.status().path_speed, 20.0, 1e-9);
  run.machine().begin_shutdown();
  run.run_while([](const Status& s) { return s.state == MachineState::kJogging; }, 10000);
  EXPECT_EQ(run.status().state, MachineState::kIdle);
  EXPECT_TRUE(run.machine().motion_at_rest());
  EXPECT_EQ(run.check_setpoint_limits(), "");
}

// A restarted rt takes up where its predecessor last measured the axes: at rest there, IDLE,
// the setpoint on the measured position (no jump when the servo comes on), jogs start there.
TEST(Machine, TakeUpPositionStandsAtRestThere) {
  MachineConfig c = test::default_machine_config();
  MachineRunner run(c);
  const Vec3 at{3.2501, 20.0, 21.5};
  ASSERT_TRUE(run.machine().take_up_position(at));
  run.run(200);
  EXPECT_EQ(run.status().state, MachineState::kIdle);
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(run.status().actual[i], at[i], c.axes[i].encoder_resolution_mm) << "axis " << i;
    EXPECT_EQ(run.status().commanded[i], at[i]);
    EXPECT_EQ(run.status().velocity[i], 0.0);
  }
  // every cycle's setpoint on the taken-up position: no jump when the servo comes on (the
  // runner's record 0 is from before the take-up)
  for (std::size_t k = 1; k < run.records().size(); ++k) ASSERT_EQ(run.records()[k].cmd, at) << "cycle " << k;
  run.send(CommandKind::kJogIncrement, 1.0, 0, 10.0);
  run.run_while([](const Status& s) { return s.state == MachineState::kJogging; }, 10000);
  EXPECT_NEAR(run.status().commanded[0], at[0] + 1.0, 1e-12);
  // outside the travel: put onto it; not finite: refused
  MachineRunner other(c);
  EXPECT_TRUE(other.machine().take_up_position({-0.5, 30.0, 10.0}));
  other.run(10);
  EXPECT_EQ(other.status().commanded, (Vec3{0.0, 25.0, 10.0}));
  EXPECT_FALSE(other.machine().take_up_position({std::numeric_limits<double>::quiet_NaN(), 1.0, 1.0}));
}

// The trace failed with process.on_trace_failure = "stop": the program stops along the path,
// the status says so, and no program starts afterwards (jogs still do).
TEST(Machine, TraceFailureWithStopStopsTheProgramAndStartsNoOther) {
  MachineConfig c = test::default_machine_config();
  MachineRunner run(c);
  run.start(long_line(c, 40.0));
  run_to_line(run, 2, 40.0);
  run.machine().trace_failed(true);
  EXPECT_EQ(run.status().trace_failed, 1);
  EXPECT_EQ(run.status().state, MachineState::kStopping);
  run.run_while([](const Status& s) { return s.state == MachineState::kStopping; }, 10000);
  EXPECT_EQ(run.status().state, MachineState::kIdle);
  EXPECT_EQ(run.status().program_done, 0);
  EXPECT_EQ(run.check_setpoint_limits(), "");
  run.start(long_line(c, 40.0));
  run.run(200);
  EXPECT_EQ(run.status().state, MachineState::kIdle);
  EXPECT_EQ(run.status().program_active, 0);
  run.send(CommandKind::kJogIncrement, 1.0, 0, 10.0);
  EXPECT_EQ(run.status().state, MachineState::kJogging) << "jogs still move the machine";
}

TEST(Machine, TraceFailureWithContinueOnlyTellsTheStatus) {
  MachineConfig c = test::default_machine_config();
  MachineRunner run(c);
  run.start(long_line(c, 40.0));
  run_to_line(run, 2, 40.0);
  run.machine().trace_failed(false);
  EXPECT_EQ(run.status().trace_failed, 1);
  run.run_until_done();
  EXPECT_EQ(run.status().program_done, 1);
}

TEST(Machine, HostLostStopsAlongThePathThenHolds) {
  MachineConfig c = test::default_machine_config();
  MachineRunner run(c);
  run.start(long_line(c, 40.0));
  run_to_line(run, 2, 40.0);
  run.set_host_alive(false);
  run.cycle();
  EXPECT_EQ(run.status().state, MachineState::kStopping);
  run.run_while([](const Status& s) { return s.state == MachineState::kStopping; }, 10000);
  EXPECT_EQ(run.status().state, MachineState::kHostLost);
  EXPECT_EQ(run.status().path_speed, 0.0);
  EXPECT_NEAR(run.status().commanded[1], 12.5, 1e-12);  // stopped on the line
  EXPECT_EQ(run.check_setpoint_limits(), "");
  run.set_host_alive(true);
  run.send(CommandKind::kReset);
  EXPECT_EQ(run.status().state, MachineState::kIdle);
}

}  // namespace
}  // namespace pcnc
