// test_machine_jog.cpp — jogs on the Machine driven in-process (no processes), as the loop
// drives it under --clock virtual: incremental and continuous jogs, the deadman, soft limits,
// and jogs while a program is paused (the way back to the pause point on resume, M00, the
// refusals while running, stop after a paused jog).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "machine_runner.hpp"
#include "make_blocks.hpp"

namespace pcnc {
namespace {

using test::long_line;
using test::MachineRunner;
using test::ProgramBuilder;
using test::run_to_line;


TEST(Machine, JogIncrementContinuousDeadmanAndSoftLimits) {
  MachineConfig c = test::default_machine_config();
  MachineRunner run(c);
  run.send(CommandKind::kJogIncrement, 1.5, 0, 10.0);
  EXPECT_EQ(run.status().state, MachineState::kJogging);
  run.run_while([](const Status& s) { return s.state == MachineState::kJogging; }, 10000);
  EXPECT_EQ(run.status().state, MachineState::kIdle);
  EXPECT_NEAR(run.status().commanded[0], 14.0, 1e-12);
  // continuous toward +Y with keep-alives: moves; stop: decelerates to rest
  run.send(CommandKind::kJogContinuous, 1.0, 1, 20.0);
  for (int i = 0; i < 400; ++i) {
    if (i % 100 == 0) run.send(CommandKind::kJogKeepAlive);
    run.cycle();
  }
  EXPECT_NEAR(run.status().path_speed, 20.0, 1e-9);
  run.send(CommandKind::kJogStop);
  run.run_while([](const Status& s) { return s.state == MachineState::kJogging; }, 10000);
  const double y_stop = run.status().commanded[1];
  EXPECT_GT(y_stop, 12.5 + 2.0);
  // continuous without keep-alives: the deadman stops it after jog_deadman_s
  run.send(CommandKind::kJogContinuous, -1.0, 1, 50.0);
  const std::size_t n = run.run_while([](const Status& s) { return s.state == MachineState::kJogging; }, 100000);
  EXPECT_LT(static_cast<double>(n) * run.dt(), c.process.jog_deadman_s + 0.1);
  // an increment past the travel stops at the soft limit
  run.send(CommandKind::kJogIncrement, 100.0, 2, 50.0);
  run.run_while([](const Status& s) { return s.state == MachineState::kJogging; }, 100000);
  EXPECT_NEAR(run.status().commanded[2], c.axes[2].travel_max_mm, 1e-12);
  run.send(CommandKind::kJogIncrement, -100.0, 0, 100.0);
  run.run_while([](const Status& s) { return s.state == MachineState::kJogging; }, 100000);
  EXPECT_NEAR(run.status().commanded[0], c.axes[0].travel_min_mm, 1e-12);
  EXPECT_EQ(run.check_setpoint_limits(), "");
  // a program starts from where the jog left the machine
  ProgramBuilder p(c, run.status().commanded);
  p.line({5.0, 5.0, 20.0}, 30.0).end();
  run.start(p.blocks());
  run.run_until_done();
  EXPECT_EQ(run.status().program_done, 1) << run.machine().fault_reason();
}

// ---- jogs while a program is paused ---------------------------------------------------------

// Two feed moves: a diagonal (on which the feed hold falls) and a line down Y to the end point.
std::vector<Block> paused_jog_program(const MachineConfig& c) {
  ProgramBuilder p(c, test::home(c));
  p.rapid({2.0, 2.0, 20.0});
  p.line({22.0, 17.0, 20.0}, 40.0);
  p.line({22.0, 5.0, 20.0}, 40.0);
  p.end();
  return p.blocks();
}

// Runs to full speed on the diagonal, feed hold, at rest. Returns the pause point.
Vec3 pause_at_rest(MachineRunner& run) {
  run.start(paused_jog_program(run.config()));
  run_to_line(run, 2, 40.0);
  run.send(CommandKind::kPause);
  run.run_while([](const Status& s) { return s.path_speed > 0.0; }, 10000);
  run.run(20);
  EXPECT_EQ(run.status().state, MachineState::kPaused);
  return run.status().commanded;
}

void jog_to_rest(MachineRunner& run, int axis, double distance, double feed) {
  run.send(CommandKind::kJogIncrement, distance, axis, feed);
  ASSERT_EQ(run.status().state, MachineState::kJogging);
  run.run_while([](const Status& s) { return s.state == MachineState::kJogging; }, 100000);
}

// First record index >= from whose setpoint differs from `at` (the program leaving the pause point).
std::size_t departure(const std::vector<test::CycleRecord>& r, std::size_t from, const Vec3& at) {
  std::size_t k = from;
  while (k < r.size() && r[k].cmd == at) ++k;
  return k;
}

TEST(Machine, JogWhilePausedReturnsToThePausePointAndResumesTheSamePath) {
  MachineConfig c = test::default_machine_config();
  // Reference: pause and resume without jogging.
  MachineRunner ref(c);
  const Vec3 pp_ref = pause_at_rest(ref);
  const std::size_t ref_resume = ref.records().size();
  ref.send(CommandKind::kResume);
  ref.run_until_done();
  ASSERT_EQ(ref.status().program_done, 1) << ref.machine().fault_reason();

  MachineRunner run(c);
  const Vec3 pp = pause_at_rest(run);
  ASSERT_EQ(pp, pp_ref);
  ASSERT_GT(pp[0], 2.5);  // the hold fell inside the diagonal
  ASSERT_LT(pp[0], 21.5);
  jog_to_rest(run, 0, 1.0, 10.0);
  EXPECT_EQ(run.status().state, MachineState::kPaused);
  EXPECT_EQ(run.status().line, 2u);  // the executor keeps its place in the block
  EXPECT_NEAR(run.status().commanded[0], pp[0] + 1.0, 1e-12);
  jog_to_rest(run, 2, 2.0, 10.0);
  EXPECT_EQ(run.status().state, MachineState::kPaused);
  const Vec3 stand = run.status().commanded;
  EXPECT_NEAR(stand[0], pp[0] + 1.0, 1e-12);
  EXPECT_EQ(stand[1], pp[1]);
  EXPECT_NEAR(stand[2], pp[2] + 2.0, 1e-12);
  run.run(100);
  EXPECT_EQ(run.status().commanded, stand);  // held where the jogs left it
  EXPECT_EQ(run.status().state, MachineState::kPaused);

  const std::size_t resume = run.records().size();
  run.send(CommandKind::kResume);
  EXPECT_EQ(run.status().state, MachineState::kRunning);
  run.run_until_done();
  const Status& s = run.status();
  ASSERT_EQ(s.program_done, 1) << to_string(s.state) << " " << run.machine().fault_reason();
  EXPECT_EQ(s.commanded, (Vec3{22.0, 5.0, 20.0}));  // ends exactly at its last point
  EXPECT_EQ(run.check_setpoint_limits(), "");

  // The way back: RUNNING with a path speed, one axis at a time, X before Z comes down,
  // landing exactly on the pause point.
  const auto& r = run.records();
  std::size_t arrive = resume;
  while (arrive < r.size() && r[arrive].cmd != pp) ++arrive;
  ASSERT_LT(arrive, r.size()) << "never back on the pause point";
  bool moved = false;
  for (std::size_t k = resume; k < arrive; ++k) {
    EXPECT_EQ(r[k].state, MachineState::kRunning) << k;
    const Vec3 prev = r[k - 1].cmd;
    int axes_moving = 0;
    for (int i = 0; i < kAxes; ++i) axes_moving += r[k].cmd[i] != prev[i] ? 1 : 0;
    EXPECT_LE(axes_moving, 1) << k;
    if (axes_moving) moved = true;
    if (r[k].cmd[2] != stand[2]) {
      EXPECT_EQ(r[k].cmd[0], pp[0]) << "Z came down before X was back, cycle " << k;
    }
    if (r[k].speed > 0.0) {
      EXPECT_NEAR(r[k].speed, norm(r[k].cmd - prev) / run.dt(), 1e-6) << k;
    }
  }
  EXPECT_TRUE(moved);

  // From the departure off the pause point on, the commanded path is the one without the jog.
  const std::size_t a = departure(ref.records(), ref_resume, pp);
  const std::size_t b = departure(r, arrive, pp);
  ASSERT_EQ(ref.records().size() - a, r.size() - b);
  for (std::size_t k = 0; a + k < ref.records().size(); ++k) {
    ASSERT_NEAR(norm(ref.records()[a + k].cmd - r[b + k].cmd), 0.0, 1e-12) << "cycle " << k << " after the departure";
  }
  EXPECT_EQ(s.blocks_done, ref.status().blocks_done);
  // the jog's excursion (mm) does not count as a contour error; what remains is the axes
  // still settling from the way back when the program resumes (a few µm)
  EXPECT_LT(s.max_contour_error, 0.01);
}

TEST(Machine, JogWhilePausedAtM00ResumesWithTheNextBlock) {
  MachineConfig c = test::default_machine_config();
  MachineRunner run(c);
  ProgramBuilder p(c, test::home(c));
  p.line({15.0, 12.5, 25.0}, 20.0).pause().line({15.0, 15.0, 25.0}, 20.0).end();
  run.start(p.blocks());
  run.run_while([](const Status& s) { return s.state != MachineState::kPaused; }, 100000);
  jog_to_rest(run, 2, -1.5, 10.0);  // Z down: on the way back it rises first
  EXPECT_EQ(run.status().state, MachineState::kPaused);
  EXPECT_NEAR(run.status().commanded[2], 23.5, 1e-12);
  const std::size_t resume = run.records().size();
  run.send(CommandKind::kResume);
  run.run_until_done();
  ASSERT_EQ(run.status().program_done, 1) << run.machine().fault_reason();
  EXPECT_EQ(run.status().commanded, (Vec3{15.0, 15.0, 25.0}));
  // Z rises back before anything else moves
  for (std::size_t k = resume; k < run.records().size() && run.records()[k].cmd[2] < 25.0; ++k) {
    EXPECT_EQ(run.records()[k].cmd[1], 12.5) << k;
  }
  EXPECT_EQ(run.check_setpoint_limits(), "");
}

TEST(Machine, JogIsRefusedWhileRunningAndWhileTheHoldDecelerates) {
  MachineConfig c = test::default_machine_config();
  MachineRunner run(c);
  run.start(paused_jog_program(c));
  run_to_line(run, 2, 40.0);
  run.send(CommandKind::kJogIncrement, 1.0, 0, 10.0);
  EXPECT_EQ(run.status().state, MachineState::kRunning);
  run.send(CommandKind::kPause);
  run.cycle();
  ASSERT_GT(run.status().path_speed, 0.0);
  run.send(CommandKind::kJogIncrement, 1.0, 2, 10.0);
  EXPECT_EQ(run.status().state, MachineState::kPaused);  // still decelerating: refused
  run.run_while([](const Status& s) { return s.path_speed > 0.0; }, 10000);
  run.send(CommandKind::kJogContinuous, 1.0, 2, 10.0);  // at rest: taken
  EXPECT_EQ(run.status().state, MachineState::kJogging);
  run.send(CommandKind::kJogStop);
  run.run_while([](const Status& s) { return s.state == MachineState::kJogging; }, 10000);
  EXPECT_EQ(run.status().state, MachineState::kPaused);
  run.send(CommandKind::kResume);
  run.run_until_done();
  EXPECT_EQ(run.status().program_done, 1) << run.machine().fault_reason();
  EXPECT_EQ(run.status().commanded, (Vec3{22.0, 5.0, 20.0}));
  // the setpoints stayed on the programmed diagonal whenever line 2 was executing off the jog
  EXPECT_EQ(run.check_setpoint_limits(), "");
}

TEST(Machine, StopAfterAPausedJogIdlesWhereTheMachineStands) {
  MachineConfig c = test::default_machine_config();
  {
    MachineRunner run(c);
    const Vec3 pp = pause_at_rest(run);
    jog_to_rest(run, 1, -1.0, 10.0);
    const Vec3 stand = run.status().commanded;
    EXPECT_NEAR(stand[1], pp[1] - 1.0, 1e-12);
    run.send(CommandKind::kStop);
    EXPECT_EQ(run.status().state, MachineState::kStopping);
    run.run_while([](const Status& s) { return s.state == MachineState::kStopping; }, 10000);
    EXPECT_EQ(run.status().state, MachineState::kIdle);
    EXPECT_EQ(run.status().program_active, 0);
    run.run(100);
    EXPECT_EQ(run.status().commanded, stand);
    EXPECT_TRUE(run.ring().empty());
    // a new program starts from there
    ProgramBuilder p(c, stand);
    p.line({5.0, 5.0, 20.0}, 30.0).end();
    run.start(p.blocks());
    run.run_until_done();
    EXPECT_EQ(run.status().program_done, 1) << run.machine().fault_reason();
    EXPECT_EQ(run.check_setpoint_limits(), "");
  }
  {
    // stop while the paused jog still moves: it decelerates, then IDLE where it came to rest
    MachineRunner run(c);
    const Vec3 pp = pause_at_rest(run);
    run.send(CommandKind::kJogIncrement, 3.0, 0, 5.0);
    run.run(200);
    run.send(CommandKind::kStop);
    EXPECT_EQ(run.status().state, MachineState::kStopping);
    run.run_while([](const Status& s) { return s.state == MachineState::kStopping; }, 10000);
    EXPECT_EQ(run.status().state, MachineState::kIdle);
    const Vec3 stand = run.status().commanded;
    EXPECT_GT(stand[0], pp[0] + 0.1);
    EXPECT_LT(stand[0], pp[0] + 3.0);
    run.run(100);
    EXPECT_EQ(run.status().commanded, stand);
    EXPECT_EQ(run.check_setpoint_limits(), "");
  }
  {
    // pause on the way back: the move stops, PAUSED away from the path; resume finishes it
    MachineRunner run(c);
    const Vec3 pp = pause_at_rest(run);
    jog_to_rest(run, 0, -3.0, 20.0);
    run.send(CommandKind::kResume);
    run.run(100);
    ASSERT_EQ(run.status().state, MachineState::kRunning);
    run.send(CommandKind::kPause);
    run.run_while([](const Status& s) { return s.state == MachineState::kJogging; }, 10000);
    EXPECT_EQ(run.status().state, MachineState::kPaused);
    EXPECT_LT(run.status().commanded[0], pp[0]);
    run.send(CommandKind::kResume);
    run.run_until_done();
    EXPECT_EQ(run.status().program_done, 1) << run.machine().fault_reason();
    EXPECT_EQ(run.status().commanded, (Vec3{22.0, 5.0, 20.0}));
    EXPECT_EQ(run.check_setpoint_limits(), "");
  }
  {
    // stop on the way back: the move comes to rest, IDLE there
    MachineRunner run(c);
    const Vec3 pp = pause_at_rest(run);
    jog_to_rest(run, 0, 3.0, 20.0);
    run.send(CommandKind::kResume);
    run.run(100);
    ASSERT_EQ(run.status().state, MachineState::kRunning);
    run.send(CommandKind::kStop);
    EXPECT_EQ(run.status().state, MachineState::kStopping);
    run.run_while([](const Status& s) { return s.state == MachineState::kStopping; }, 10000);
    EXPECT_EQ(run.status().state, MachineState::kIdle);
    const Vec3 stand = run.status().commanded;
    EXPECT_GT(stand[0], pp[0]);
    EXPECT_LT(stand[0], pp[0] + 3.0);
    run.run(100);
    EXPECT_EQ(run.status().commanded, stand);
    EXPECT_EQ(run.check_setpoint_limits(), "");
  }
  {
    // host lost during a paused jog: the jog stops, HOST_LOST holding where it stands
    MachineRunner run(c);
    pause_at_rest(run);
    run.send(CommandKind::kJogIncrement, 3.0, 1, 5.0);
    run.run(200);
    run.set_host_alive(false);
    run.run_while([](const Status& s) { return s.state != MachineState::kHostLost; }, 10000);
    ASSERT_EQ(run.status().state, MachineState::kHostLost);
    const Vec3 stand = run.status().commanded;
    run.set_host_alive(true);
    run.send(CommandKind::kReset);
    run.run(100);
    EXPECT_EQ(run.status().state, MachineState::kIdle);
    EXPECT_EQ(run.status().commanded, stand);
    EXPECT_EQ(run.check_setpoint_limits(), "");
  }
}

}  // namespace
}  // namespace pcnc
