// test_machine_probe.cpp — the probe in the rt (rt/drive/sim_probe, the executor's probing
// blocks): contact sensed at the commanded ball centre against the flat workpiece of the
// default machine, the latch, the stop within the overtravel, the sync point after a probing
// block, and the outcomes of G38.2-G38.5, against the contact rule computed here.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "geometry/probe_contact.hpp"
#include "machine_runner.hpp"
#include "make_blocks.hpp"

namespace pcnc {
namespace {

MachineConfig quiet_probe_config() {
  MachineConfig c = test::default_machine_config();
  c.probe.model.repeatability_mm = 0.0;  // the trigger point is then exact
  return c;
}

// From `from`: a probing line to `to` at `feed` (mm/s) with `rule`, seq numbers from `seq`.
std::vector<Block> probe_move(const MachineConfig& c, const Vec3& from, const Vec3& to, double feed, ProbeRule rule) {
  test::ProgramBuilder p(c, from);
  p.line(to, feed);
  std::vector<Block> blocks = p.blocks();
  blocks.back().probe_rule = rule;
  return blocks;
}

// Blocks made by a builder numbered from 1: renumbered to continue after `after`.
std::vector<Block> renumbered(std::vector<Block> blocks, std::uint64_t after) {
  for (Block& b : blocks) b.seq += after;
  return blocks;
}

struct Probed {
  test::MachineRunner run;
  explicit Probed(const MachineConfig& c) : run(c) {}
  // Runs the blocks as a program until the rt reports a probe result (or faults).
  void until_result(const std::vector<Block>& blocks) {
    const std::uint64_t before = run.status().probe_count;
    run.start(blocks);
    run.run_while([&](const Status& s) { return s.probe_count == before && s.state != MachineState::kFault; }, 200000);
  }
};

TEST(MachineProbe, G38_2StopsOnTheFlatWorkpieceWithinTheOvertravel) {
  const MachineConfig c = quiet_probe_config();
  ASSERT_TRUE(c.probe.present);
  const Vec3 home = test::home(c);
  test::ProgramBuilder p(c, home);
  p.rapid({12.5, 12.5, 17.0});
  const double feed = 2.0;
  std::vector<Block> blocks = p.blocks();
  const auto probe = renumbered(probe_move(c, {12.5, 12.5, 17.0}, {12.5, 12.5, 10.0}, feed, kProbeTowardError), 1);
  blocks.insert(blocks.end(), probe.begin(), probe.end());
  Probed t(c);
  t.until_result(blocks);
  const Status& s = t.run.status();
  ASSERT_EQ(s.state, MachineState::kRunning) << to_string(s.state);
  EXPECT_EQ(s.probe_outcome, ProbeOutcome::kContact);
  EXPECT_EQ(s.probe_seq, 2u);
  // the trigger: ball centre within R - pre-travel (straight down: the axial value) of z = 15
  const double z_trigger = c.table.z_mm + c.probe.model.ball_radius_mm - c.probe.model.pretravel_axial_mm;
  EXPECT_LE(s.probe_latched[2], z_trigger + 1e-12);
  EXPECT_GT(s.probe_latched[2], z_trigger - feed * t.run.dt() - 1e-12) << "latched in the first cycle past the trigger";
  EXPECT_DOUBLE_EQ(s.probe_latched[0], 12.5);
  EXPECT_LT(s.probe_stop[2], s.probe_latched[2]);
  EXPECT_LE(s.probe_latched[2] - s.probe_stop[2], c.probe.model.overtravel_mm);
  EXPECT_EQ(s.probe_input, 1);
  // the machine waits at the sync point without counting underruns
  t.run.run(200);
  EXPECT_EQ(t.run.status().underruns, 0u);
  EXPECT_EQ(t.run.status().state, MachineState::kRunning);
  EXPECT_DOUBLE_EQ(t.run.status().commanded[2], s.probe_stop[2]);

  // the host continues from where the probe stopped: retract, G38.4 away from the surface
  const Vec3 stop = t.run.status().probe_stop;
  auto away = renumbered(probe_move(c, stop, {12.5, 12.5, 18.0}, feed, kProbeAwayError), 2);
  for (const Block& b : away) ASSERT_TRUE(t.run.ring().try_push(b));
  t.run.run_while([&](const Status& st) { return st.probe_count == 1 && st.state != MachineState::kFault; }, 200000);
  const Status& a = t.run.status();
  EXPECT_EQ(a.probe_outcome, ProbeOutcome::kContact) << "released";
  EXPECT_GT(a.probe_latched[2], z_trigger) << "released once above the trigger height";
  EXPECT_LT(a.probe_latched[2], z_trigger + feed * t.run.dt() + 1e-9);
  EXPECT_EQ(a.probe_input, 0);

  test::ProgramBuilder rest(c, a.probe_stop);
  rest.rapid({12.5, 12.5, 20.0}).end();
  for (const Block& b : renumbered(rest.blocks(), 3)) ASSERT_TRUE(t.run.ring().try_push(b));
  t.run.run_until_done();
  EXPECT_TRUE(t.run.status().program_done);
  EXPECT_EQ(t.run.status().fault, FaultCode::kNone);
  EXPECT_EQ(t.run.check_setpoint_limits(), "");
}

TEST(MachineProbe, G38_3ThatMissesEndsAtItsEndWithoutContact) {
  const MachineConfig c = quiet_probe_config();
  Probed t(c);
  t.until_result(probe_move(c, test::home(c), {12.5, 12.5, 20.0}, 5.0, kProbeToward));
  EXPECT_EQ(t.run.status().probe_outcome, ProbeOutcome::kNoContact);
  EXPECT_DOUBLE_EQ(t.run.status().probe_stop[2], 20.0);
  EXPECT_EQ(t.run.status().probe_input, 0);
}

TEST(MachineProbe, AProbeAlreadyTriggeredDoesNotMove) {
  const MachineConfig c = quiet_probe_config();
  Probed t(c);
  test::ProgramBuilder p(c, test::home(c));
  p.rapid({12.5, 12.5, 15.5});  // the ball 0.5 mm into the workpiece's top: triggered
  std::vector<Block> blocks = p.blocks();
  const auto probe = renumbered(probe_move(c, {12.5, 12.5, 15.5}, {12.5, 12.5, 14.0}, 1.0, kProbeToward), 1);
  blocks.insert(blocks.end(), probe.begin(), probe.end());
  t.until_result(blocks);
  EXPECT_EQ(t.run.status().probe_outcome, ProbeOutcome::kAlreadyTriggered);
  EXPECT_DOUBLE_EQ(t.run.status().probe_stop[2], 15.5);
  // G38.5 away from a probe that is not triggered: the same outcome
  Probed u(c);
  u.until_result(probe_move(c, test::home(c), {12.5, 12.5, 24.0}, 1.0, kProbeAway));
  EXPECT_EQ(u.run.status().probe_outcome, ProbeOutcome::kAlreadyTriggered);
}

TEST(MachineProbe, ABlockQueuedBehindAProbingMoveIsRefused) {
  const MachineConfig c = quiet_probe_config();
  test::ProgramBuilder p(c, {12.5, 12.5, 25.0});
  p.line({12.5, 12.5, 10.0}, 2.0).line({12.5, 12.5, 20.0}, 2.0).end();
  std::vector<Block> blocks = p.blocks();
  blocks[0].probe_rule = kProbeTowardError;
  test::MachineRunner run(c);
  run.start(blocks);
  run.run_until_done(200000);
  EXPECT_EQ(run.status().state, MachineState::kFault);
  EXPECT_EQ(run.status().fault, FaultCode::kBadBlock);
  EXPECT_STREQ(run.machine().fault_reason(),
               "a block was queued behind a probing move (the host must wait for the probe's result)");
}

TEST(MachineProbe, TheProbingSpeedMustStopWithinTheOvertravel) {
  const MachineConfig c = quiet_probe_config();
  const double dt = c.cycle_period_s();
  const double a = 200.0, ot = c.probe.model.overtravel_mm;
  const double v = probe_speed_limit(a, dt, ot);
  EXPECT_NEAR(v * v / (2 * a) + 2 * v * dt, ot, 1e-12);
  // a probing block faster than that is refused by the rt's block check
  std::vector<Block> blocks = probe_move(c, test::home(c), {12.5, 12.5, 10.0}, 40.0, kProbeTowardError);
  ASSERT_GT(blocks[0].speed, probe_speed_limit(blocks[0].accel, dt, ot));
  test::MachineRunner run(c);
  run.start(blocks);
  run.run(5);
  EXPECT_EQ(run.status().fault, FaultCode::kBadBlock);
  EXPECT_STREQ(run.machine().fault_reason(), "probing speed would not stop within the probe's overtravel");
}

// Horizontal touches: the gauge block's face along +X and the reference sphere along an
// azimuth of 120 deg trigger at R minus the lobed lateral pre-travel, as computed here.
TEST(MachineProbe, SideTouchesOnTheGaugeBlockAndTheSphereFollowTheLobing) {
  MachineConfig c = quiet_probe_config();
  c.table.has_surface = false;
  c.table.has_gauge = true;
  c.table.gauge_min = {15.0, 5.0, 0.0};
  c.table.gauge_max = {20.0, 10.0, 20.0};
  c.table.sphere_center = {8.0, 18.0, 15.0};
  c.table.sphere_radius_mm = 3.0;
  const ProbeModel& pm = c.probe.model;
  const double feed = 1.0;
  {
    Probed t(c);
    test::ProgramBuilder p(c, test::home(c));
    p.rapid({10.0, 7.5, 15.0});
    std::vector<Block> blocks = p.blocks();
    const auto probe = renumbered(probe_move(c, {10.0, 7.5, 15.0}, {16.0, 7.5, 15.0}, feed, kProbeTowardError), 1);
    blocks.insert(blocks.end(), probe.begin(), probe.end());
    t.until_result(blocks);
    ASSERT_EQ(t.run.status().probe_outcome, ProbeOutcome::kContact);
    // along +X: azimuth 0, lateral + lobe
    const double x_trigger = 15.0 - (pm.ball_radius_mm - (pm.pretravel_lateral_mm + pm.pretravel_lobe_mm));
    EXPECT_LE(t.run.status().probe_latched[0], x_trigger + 1e-12);
    EXPECT_GT(t.run.status().probe_latched[0], x_trigger - feed * t.run.dt() - 1e-12);
  }
  {
    Probed t(c);
    const double az = 2.0 * 3.14159265358979323846 / 3.0;  // approach direction: 120 deg
    const Vec3 d{std::cos(az), std::sin(az), 0.0};
    const Vec3 start = c.table.sphere_center - 6.0 * d;
    test::ProgramBuilder p(c, test::home(c));
    p.rapid(start);
    std::vector<Block> blocks = p.blocks();
    const auto probe = renumbered(probe_move(c, start, c.table.sphere_center, feed, kProbeTowardError), 1);
    blocks.insert(blocks.end(), probe.begin(), probe.end());
    t.until_result(blocks);
    ASSERT_EQ(t.run.status().probe_outcome, ProbeOutcome::kContact);
    // cos(3 * 120 deg) = 1: the same pre-travel as along +X; the centre stops at 3 + R - delta
    const double r_trigger = 3.0 + pm.ball_radius_mm - (pm.pretravel_lateral_mm + pm.pretravel_lobe_mm);
    const double dist = norm(t.run.status().probe_latched - c.table.sphere_center);
    EXPECT_LE(dist, r_trigger + 1e-9);
    EXPECT_GT(dist, r_trigger - feed * t.run.dt() - 1e-9);
  }
}

// Repeatability: one Gaussian draw per touch, from the configured seed: the same run twice gives
// the same points, and over many touches their spread is about the configured sigma.
TEST(MachineProbe, RepeatabilityNoiseIsDeterministicAndOfTheConfiguredSize) {
  MachineConfig c = test::default_machine_config();
  c.probe.model.repeatability_mm = 0.002;
  auto touches = [&](int n) {
    std::vector<double> z;
    Probed t(c);
    Vec3 at = test::home(c);
    std::uint64_t seq = 0;
    test::ProgramBuilder first(c, at);
    first.rapid({12.5, 12.5, 16.1});
    std::vector<Block> blocks = first.blocks();
    seq = 1;
    at = {12.5, 12.5, 16.1};
    for (int i = 0; i < n; ++i) {
      auto down = renumbered(probe_move(c, at, {12.5, 12.5, 15.5}, 0.4, kProbeTowardError), seq);
      ++seq;
      if (i == 0) {
        blocks.insert(blocks.end(), down.begin(), down.end());
        t.until_result(blocks);
      } else {
        const std::uint64_t before = t.run.status().probe_count;
        EXPECT_TRUE(t.run.ring().try_push(down[0]));
        t.run.run_while([&](const Status& s) { return s.probe_count == before; }, 200000);
      }
      z.push_back(t.run.status().probe_latched[2]);
      test::ProgramBuilder up(c, t.run.status().probe_stop);
      up.rapid({12.5, 12.5, 16.1});
      const std::uint64_t done = t.run.status().blocks_done;
      EXPECT_TRUE(t.run.ring().try_push(renumbered(up.blocks(), seq)[0]));
      ++seq;
      t.run.run_while([&](const Status& s) { return s.blocks_done == done; }, 200000);
      at = {12.5, 12.5, 16.1};
    }
    return z;
  };
  const auto a = touches(40), b = touches(40);
  ASSERT_EQ(a, b);
  double mean = 0.0;
  for (double z : a) mean += z / 40.0;
  double var = 0.0;
  for (double z : a) var += (z - mean) * (z - mean) / 39.0;
  // sigma 2 um, quantised by the feed per cycle (0.2 um): the sample's spread within 40 %
  EXPECT_NEAR(std::sqrt(var), 0.002, 0.0008);
  EXPECT_NEAR(mean, 16.0 - 0.004, 0.001);
}

}  // namespace
}  // namespace pcnc
