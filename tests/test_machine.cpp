// test_machine.cpp — Machine driven in-process (no processes), as the loop drives it under
// --clock virtual: programs run end to end, M21/M22 junction behaviour, contour accuracy,
// setpoint limits on every cycle, faults, feed override, feed hold, M00, e-stop, host loss,
// NURBS blocks, and a cycle that never allocates. Jogs: test_machine_jog.cpp; shutdown, restart,
// trace failure and host loss: test_machine_survival.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <new>
#include <numbers>

#include "motion/junction.hpp"
#include "machine_runner.hpp"
#include "make_blocks.hpp"
#include "geometry/nurbs.hpp"
#include "gcode/nurbs_schedule.hpp"

// ---- allocation counter: replaces global operator new for this test executable -----------
namespace {
std::atomic<long> g_allocations{0};
std::atomic<bool> g_counting{false};
void* counted_alloc(std::size_t n) {
  if (g_counting.load(std::memory_order_relaxed)) g_allocations.fetch_add(1, std::memory_order_relaxed);
  void* p = std::malloc(n ? n : 1);
  if (!p) throw std::bad_alloc();
  return p;
}
}  // namespace
void* operator new(std::size_t n) { return counted_alloc(n); }
void* operator new[](std::size_t n) { return counted_alloc(n); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }

namespace pcnc {
namespace {

using test::long_line;
using test::MachineRunner;
using test::run_to_line;
using test::ProgramBuilder;


bool moving_cycle(const test::CycleRecord& a, const test::CycleRecord& b) { return norm(b.cmd - a.cmd) > 0.0; }

// Counts runs of cycles at rest (setpoint unchanged) that lie strictly between motion.
int rests_between_motion(const std::vector<test::CycleRecord>& r, std::size_t from, std::size_t to) {
  int rests = 0;
  bool moved = false, resting = false;
  for (std::size_t k = from + 1; k < to; ++k) {
    const bool m = moving_cycle(r[k - 1], r[k]);
    if (m) {
      if (resting && moved) ++rests;
      moved = true;
      resting = false;
    } else {
      resting = true;
    }
  }
  return rests;
}

TEST(Machine, SquareWithM22StopsAtEveryCorner) {
  MachineConfig c = test::default_machine_config();
  MachineRunner run(c);
  run.start(test::square_program(c, {5, 5, 20}, 10.0, 25.0, false));
  run.run_until_done();
  const Status& s = run.status();
  ASSERT_EQ(s.program_done, 1) << to_string(s.state) << " " << run.machine().fault_reason();
  EXPECT_EQ(s.state, MachineState::kIdle);
  EXPECT_EQ(s.program_active, 0);
  EXPECT_EQ(s.junction_stops, 4u);  // rapid -> side 1, and the three corners
  EXPECT_EQ(s.junction_flows, 0u);
  EXPECT_EQ(s.blocks_done, 6u);
  EXPECT_EQ(rests_between_motion(run.records(), 0, run.records().size()), 4);
  EXPECT_EQ(run.check_setpoint_limits(), "");
  // ends exactly where it started the square
  EXPECT_NEAR(s.commanded[0], 5.0, 1e-12);
  EXPECT_NEAR(s.commanded[1], 5.0, 1e-12);
}

TEST(Machine, SquareWithM21StillStopsAt90Degrees) {
  MachineConfig c = test::default_machine_config();
  MachineRunner run(c);
  run.start(test::square_program(c, {5, 5, 20}, 10.0, 25.0, true));
  run.run_until_done();
  const Status& s = run.status();
  ASSERT_EQ(s.program_done, 1) << run.machine().fault_reason();
  EXPECT_EQ(s.junction_flows, 0u);
  EXPECT_EQ(s.junction_stops, 4u);
  EXPECT_EQ(rests_between_motion(run.records(), 0, run.records().size()), 4);
  EXPECT_EQ(run.check_setpoint_limits(), "");
}

// With a corner tolerance, M21 passes the square's corners at the junction-deviation speed
// instead of stopping: no rest cycle at the three corners, the speed there is above zero and
// no higher than the rule allows, the square ends where it began, and it takes less time.
TEST(Machine, SquareWithACornerTolerancePassesTheCornersAtTheDeviationSpeed) {
  MachineConfig c = test::default_machine_config();
  c.motion.path_tolerance_mm = 0.01;
  MachineRunner run(c);
  run.start(test::square_program(c, {5, 5, 20}, 10.0, 25.0, true));
  const std::size_t cycles = run.run_until_done();
  const Status& s = run.status();
  ASSERT_EQ(s.program_done, 1) << run.machine().fault_reason();
  // the rapid's corner into the first side is under M21 too: all four corners flow
  EXPECT_EQ(s.junction_stops, 0u);
  EXPECT_EQ(s.junction_flows, 4u);
  const std::array<double, kAxes> a{c.axes[0].max_accel_mm_s2, c.axes[1].max_accel_mm_s2, c.axes[2].max_accel_mm_s2};
  const double v_corner = junction_deviation_speed({1, 0, 0}, {0, 1, 0}, a, 0.01);
  // the speed in the cycles on either side of the three corners between the sides (lines
  // 2|3, 3|4, 4|5)
  const auto& rec = run.records();
  int corners = 0;
  for (std::size_t i = 1; i < rec.size(); ++i) {
    if (rec[i].line == rec[i - 1].line || rec[i - 1].line < 2 || rec[i - 1].line > 4) continue;
    ++corners;
    for (const double v : {rec[i - 1].speed, rec[i].speed}) {
      EXPECT_GT(v, 0.5 * v_corner) << "line " << rec[i - 1].line;
      EXPECT_LE(v, v_corner + a[0] * run.dt() + 1e-9) << "line " << rec[i - 1].line;
    }
  }
  EXPECT_EQ(corners, 3);
  EXPECT_EQ(run.check_setpoint_limits(100.0), "") << "velocity and travel stay within the limits";
  EXPECT_NEAR(s.commanded[0], 5.0, 1e-12);
  EXPECT_NEAR(s.commanded[1], 5.0, 1e-12);
  // the corners cost the servo a little contour accuracy, far less than the tolerance
  EXPECT_LT(s.max_contour_error, 0.01);
  MachineRunner stops(test::default_machine_config());
  stops.start(test::square_program(test::default_machine_config(), {5, 5, 20}, 10.0, 25.0, true));
  EXPECT_LT(cycles, stops.run_until_done());
}

double run_polygon(bool contouring, Status* out, std::string* limits, int* rests) {
  MachineConfig c = test::default_machine_config();
  MachineRunner run(c);
  run.start(test::polygon_circle_program(c, {12.5, 12.5, 20}, 5.0, 360, 25.0, contouring));
  run.run_until_done();
  *out = run.status();
  *limits = run.check_setpoint_limits();
  // rests between the first and the last segment of the circle (lines 2 .. 361)
  const auto& r = run.records();
  std::size_t first = 0, last = 0;
  for (std::size_t k = 0; k < r.size(); ++k) {
    if (r[k].line == 2 && !first) first = k;
    if (r[k].line == 361) last = k;
  }
  *rests = rests_between_motion(r, first, last);
  double t0 = 0, t1 = 0;
  for (std::size_t k = 0; k < r.size(); ++k) {
    if (r[k].line >= 2 && r[k].line <= 361) {
      if (!t0) t0 = static_cast<double>(k);
      t1 = static_cast<double>(k);
    }
  }
  return (t1 - t0) * c.cycle_period_s();
}

TEST(Machine, PolygonCircleWithM21NeverStopsAndTakesUnderHalfTheM22Time) {
  Status s22, s21;
  std::string lim22, lim21;
  int rest22 = 0, rest21 = 0;
  const double t22 = run_polygon(false, &s22, &lim22, &rest22);
  const double t21 = run_polygon(true, &s21, &lim21, &rest21);
  ASSERT_EQ(s22.program_done, 1);
  ASSERT_EQ(s21.program_done, 1);
  EXPECT_EQ(s22.junction_flows, 0u);
  EXPECT_EQ(s22.junction_stops, 360u);  // rapid->circle + 359 vertices
  EXPECT_EQ(rest22, 359);
  EXPECT_EQ(s21.junction_flows, 359u);  // every vertex of the circle flows
  EXPECT_EQ(s21.junction_stops, 1u);    // only rapid -> circle (90 degrees)
  EXPECT_EQ(rest21, 0);
  EXPECT_LT(t21, 0.5 * t22);
  EXPECT_EQ(lim22, "");
  EXPECT_EQ(lim21, "");
  std::printf("polygon circle (360 segments, r 5 mm, F1500): M22 %.3f s, M21 %.3f s (ratio %.3f)\n", t22, t21,
              t21 / t22);
}

TEST(Machine, ArcCircleAtF500ContourErrorUnder5Micrometres) {
  MachineConfig c = test::default_machine_config();
  MachineRunner run(c);
  const Vec3 center{12.5, 12.5, 20.0};
  ProgramBuilder p(c, test::home(c));
  p.rapid({17.5, 12.5, 20.0});
  p.arc({17.5, 12.5, 20.0}, center, 2, /*cw=*/true, 500.0 / 60.0);  // full circle, G02
  p.end();
  run.start(p.blocks());
  run.run_until_done();
  ASSERT_EQ(run.status().program_done, 1) << run.machine().fault_reason();
  EXPECT_EQ(run.check_setpoint_limits(), "");
  double worst = 0.0, worst_cmd = 0.0;
  int n = 0;
  for (const auto& r : run.records()) {
    if (r.line != 2) continue;
    const double e = std::hypot(r.act[0] - center[0], r.act[1] - center[1]) - 5.0;
    const double ec = std::hypot(r.cmd[0] - center[0], r.cmd[1] - center[1]) - 5.0;
    worst = std::max(worst, std::abs(e));
    worst_cmd = std::max(worst_cmd, std::abs(ec));
    ++n;
  }
  EXPECT_GT(n, 7000);  // 2π·5 mm at 8.33 mm/s ≈ 3.8 s ≈ 7540 cycles
  EXPECT_LT(worst_cmd, 1e-9);
  EXPECT_LT(worst, 5e-3);
  // the status's contour error (nearest point of the programmed arc) finds the same maximum;
  // the rapid before it is not measured
  const Status& st = run.status();
  EXPECT_NEAR(st.max_contour_error, worst, 1e-7);
  EXPECT_GT(st.program_cycles, static_cast<std::uint64_t>(n));
  for (int i = 0; i < 2; ++i) {
    const double rms = std::sqrt(st.following_error_sq_sum[i] / static_cast<double>(st.program_cycles));
    EXPECT_GT(rms, 0.0);
    EXPECT_LT(rms, st.max_following_error[i]);
  }
  std::printf("circle r 5 mm G02 F500: max radial contour error %.3f um over %d cycles\n", worst * 1e3, n);
}

TEST(Machine, HelixAndArcsInAllPlanesRespectLimits) {
  MachineConfig c = test::default_machine_config();
  MachineRunner run(c);
  ProgramBuilder p(c, test::home(c));
  p.contouring(true);
  p.rapid({15, 12.5, 15});
  p.arc({15, 12.5, 12}, {12.5, 12.5, 0}, 2, false, 20.0, 1);  // G17 helix, 1 extra turn, down 3 mm
  p.arc({10, 12.5, 12}, {12.5, 12.5, 12}, 1, true, 20.0);     // G18 half circle (Z-X plane)
  p.arc({10, 15, 14.5}, {10, 12.5, 14.5}, 0, false, 20.0);    // G19 quarter (Y-Z plane)
  p.end();
  run.start(p.blocks());
  run.run_until_done();
  ASSERT_EQ(run.status().program_done, 1) << run.machine().fault_reason();
  EXPECT_EQ(run.check_setpoint_limits(), "");
  EXPECT_NEAR(run.status().commanded[0], 10.0, 1e-12);
  EXPECT_NEAR(run.status().commanded[1], 15.0, 1e-12);
  EXPECT_NEAR(run.status().commanded[2], 14.5, 1e-12);
}

TEST(Machine, FeedOverrideChangesSpeedWithoutVelocityStep) {
  MachineConfig c = test::default_machine_config();
  MachineRunner run(c);
  run.start(long_line(c, 10.0));
  run_to_line(run, 2, 10.0);
  ASSERT_NEAR(run.status().path_speed, 10.0, 1e-9);
  run.send(CommandKind::kFeedOverride, 2.0);
  run.run(200);
  EXPECT_NEAR(run.status().path_speed, 20.0, 1e-9);
  EXPECT_NEAR(run.status().feed_override, 2.0, 0.0);
  run.send(CommandKind::kFeedOverride, 0.0);
  run.run(200);
  EXPECT_EQ(run.status().path_speed, 0.0);
  EXPECT_EQ(run.status().state, MachineState::kRunning);
  run.send(CommandKind::kFeedOverride, 7.0);  // clamped to 200 %
  EXPECT_EQ(run.status().feed_override, 2.0);
  run.send(CommandKind::kFeedOverride, std::numeric_limits<double>::quiet_NaN());  // ignored
  EXPECT_EQ(run.status().feed_override, 2.0);
  run.send(CommandKind::kFeedOverride, 1.0);
  run.run_until_done();
  ASSERT_EQ(run.status().program_done, 1);
  // the path speed never jumps: at most the line's acceleration per cycle
  const auto& r = run.records();
  for (std::size_t k = 1; k < r.size(); ++k) {
    if (r[k].line != 2 || r[k - 1].line != 2) continue;
    ASSERT_LE(std::abs(r[k].speed - r[k - 1].speed), c.axes[0].max_accel_mm_s2 * run.dt() + 1e-9) << "cycle " << k;
  }
  EXPECT_EQ(run.check_setpoint_limits(), "");
}

TEST(Machine, FeedHoldDeceleratesOnThePathAndResumesThere) {
  MachineConfig c = test::default_machine_config();
  MachineRunner run(c);
  ProgramBuilder p(c, test::home(c));
  p.rapid({2.0, 2.0, 20.0});
  p.line({22.0, 17.0, 20.0}, 40.0);  // diagonal: staying on the path is visible on both axes
  p.end();
  run.start(p.blocks());
  run_to_line(run, 2, 40.0);
  const std::size_t hold_at = run.records().size();
  run.send(CommandKind::kPause);
  EXPECT_EQ(run.status().state, MachineState::kPaused);
  run.run(400);
  EXPECT_EQ(run.status().state, MachineState::kPaused);
  EXPECT_EQ(run.status().path_speed, 0.0);
  const Vec3 held = run.status().commanded;
  run.run(100);
  EXPECT_EQ(run.status().commanded, held);  // at rest while held
  run.send(CommandKind::kResume);
  run.run_until_done();
  ASSERT_EQ(run.status().program_done, 1);
  const auto& r = run.records();
  // On the line (y - 2) / (x - 2) = 15/20 every cycle; speed decreasing during the hold.
  for (std::size_t k = hold_at; k < r.size(); ++k) {
    if (r[k].line != 2) continue;
    EXPECT_NEAR((r[k].cmd[1] - 2.0) * 20.0 - (r[k].cmd[0] - 2.0) * 15.0, 0.0, 1e-9);
    if (k > hold_at && k < hold_at + 400) {
      EXPECT_LE(r[k].speed, r[k - 1].speed + 1e-12);
    }
  }
  EXPECT_NEAR(run.status().commanded[0], 22.0, 1e-12);
  EXPECT_EQ(run.check_setpoint_limits(), "");
}

TEST(Machine, M00PausesAtTheBlockEndUntilResume) {
  MachineConfig c = test::default_machine_config();
  MachineRunner run(c);
  ProgramBuilder p(c, test::home(c));
  p.line({15.0, 12.5, 25.0}, 20.0).pause().line({15.0, 15.0, 25.0}, 20.0).end();
  run.start(p.blocks());
  run.run_while([](const Status& s) { return s.state != MachineState::kPaused; }, 100000);
  EXPECT_EQ(run.status().line, 2u);
  EXPECT_NEAR(run.status().commanded[0], 15.0, 1e-12);  // at the end of the first block
  run.run(1000);
  EXPECT_EQ(run.status().state, MachineState::kPaused);
  EXPECT_NEAR(run.status().commanded[1], 12.5, 1e-12);
  run.send(CommandKind::kResume);
  run.run_until_done();
  EXPECT_EQ(run.status().program_done, 1);
  EXPECT_NEAR(run.status().commanded[1], 15.0, 1e-12);  EXPECT_EQ(run.check_setpoint_limits(), "");
}

TEST(Machine, DwellWaitsItsTime) {
  MachineConfig c = test::default_machine_config();
  MachineRunner run(c);
  ProgramBuilder p(c, test::home(c));
  p.dwell(0.25).end();
  run.start(p.blocks());
  const std::size_t n = run.run_until_done();
  EXPECT_EQ(run.status().program_done, 1);
  EXPECT_NEAR(static_cast<double>(n) * run.dt(), 0.25, 3 * run.dt());
}

TEST(Machine, StopDeceleratesFlushesAndDiscardsTheRest) {
  MachineConfig c = test::default_machine_config();
  MachineRunner run(c);
  run.start(long_line(c, 40.0));
  run_to_line(run, 2, 40.0);
  run.send(CommandKind::kStop);
  EXPECT_EQ(run.status().state, MachineState::kStopping);
  run.run_while([](const Status& s) { return s.state == MachineState::kStopping; }, 10000);
  EXPECT_EQ(run.status().state, MachineState::kIdle);
  EXPECT_EQ(run.status().program_active, 0);
  EXPECT_EQ(run.status().program_done, 0);
  run.run(10);
  EXPECT_TRUE(run.ring().empty());
  EXPECT_EQ(run.check_setpoint_limits(), "");
}

// pcnc-rt asked to exit (SIGTERM): the program stops along the path as on a stop, and nothing
// starts moving again, neither a new program, a resume, queued blocks nor a jog.
TEST(Machine, UnderrunsAreCountedWhenTheHostIsSlow) {
  MachineConfig c = test::default_machine_config();
  MachineRunner run(c);
  run.set_feeding(false);
  run.start(test::polygon_circle_program(c, {12.5, 12.5, 20}, 5.0, 36, 25.0, false));
  EXPECT_TRUE(run.machine().wants_more_blocks(run.ring()));
  // waiting for the program's first block is not an underrun: nothing has moved yet
  run.run(50);
  EXPECT_EQ(run.status().underruns, 0u);
  // the host falls silent after the first two blocks: every cycle that finds the ring dry
  // in the middle of the program is one
  run.set_feeding(true);
  run.run_while([](const Status& s) { return s.blocks_done < 2; });
  run.set_feeding(false);
  run.run_while([](const Status& s) { return s.underruns == 0; }, 200000);
  ASSERT_EQ(run.status().underruns, 1u);
  run.run(50);
  EXPECT_EQ(run.status().underruns, 51u);
  EXPECT_EQ(run.status().state, MachineState::kRunning);
  run.set_feeding(true);
  run.run_until_done();
  EXPECT_EQ(run.status().program_done, 1);
  EXPECT_EQ(run.status().underruns, 51u);
  EXPECT_FALSE(run.machine().wants_more_blocks(run.ring()));
  EXPECT_EQ(run.check_setpoint_limits(), "");
}

TEST(Machine, FollowingErrorFaultOnABlockedAxis) {
  MachineConfig c = test::default_machine_config();
  MachineRunner run(c);
  run.start(long_line(c, 40.0));
  run_to_line(run, 2, 40.0);
  run.machine().set_axis_blocked(0, true);
  run.run_until_done(10000);
  const Status& s = run.status();
  ASSERT_EQ(s.state, MachineState::kFault);
  EXPECT_EQ(s.fault, FaultCode::kFollowingError);
  EXPECT_EQ(s.fault_axis, 0);
  EXPECT_GT(std::abs(s.fault_value), c.axes[0].following_error_limit_mm);
  EXPECT_EQ(s.fault_line, 2u);
  EXPECT_EQ(s.program_active, 0);
  EXPECT_TRUE(run.ring().empty());
  EXPECT_STRNE(run.machine().fault_reason(), "");
  // amplifiers off: nothing moves afterwards, the setpoint follows the axes
  const Vec3 at = run.machine().true_position();
  run.run(100);
  EXPECT_LT(norm(run.machine().true_position() - at), 0.05);
  EXPECT_EQ(run.status().following_error, (Vec3{0, 0, 0}));
  run.machine().set_axis_blocked(0, false);
  run.send(CommandKind::kReset);
  EXPECT_EQ(run.status().state, MachineState::kIdle);
  run.run(100);
  EXPECT_EQ(run.status().state, MachineState::kIdle);
}

TEST(Machine, FollowingErrorFaultWithAnImpossibleAcceleration) {
  MachineConfig c = test::default_machine_config();
  c.axes[0].max_accel_mm_s2 = 200000.0;  // the X motor can give about 24 m/s² (48 N on 2 kg)
  c.axes[0].max_velocity_mm_s = 1000.0;
  MachineRunner run(c);
  run.start(long_line(c, 1000.0));
  run.run_until_done(20000);
  EXPECT_EQ(run.status().state, MachineState::kFault);
  EXPECT_EQ(run.status().fault, FaultCode::kFollowingError);
  EXPECT_EQ(run.status().fault_axis, 0);
}

struct BadCase {
  const char* name;
  void (*corrupt)(Block&);
  FaultCode code;
};

TEST(Machine, CorruptBlocksAreRefusedWithAReasonAndNeverMovedOn) {
  const BadCase cases[] = {
      {"NaN end", [](Block& b) { b.end[1] = std::numeric_limits<double>::quiet_NaN(); }, FaultCode::kBadBlock},
      {"length", [](Block& b) { b.length *= 1.5; }, FaultCode::kBadBlock},
      {"outside travel", [](Block& b) { b.end[0] = 40.0; b.length = norm(b.end - b.start); }, FaultCode::kBadBlock},
      {"speed 0", [](Block& b) { b.speed = 0.0; }, FaultCode::kBadBlock},
      {"accel < 0", [](Block& b) { b.accel = -5.0; }, FaultCode::kBadBlock},
      {"start jump", [](Block& b) { b.start[2] -= 0.5; }, FaultCode::kBadBlock},
      {"kind", [](Block& b) { b.kind = static_cast<BlockKind>(42); }, FaultCode::kBadBlock},
      {"seq gap", [](Block& b) { b.seq += 1; }, FaultCode::kSequence},
      {"seq repeat", [](Block& b) { b.seq -= 1; }, FaultCode::kSequence},
  };
  MachineConfig c = test::default_machine_config();
  for (const BadCase& bc : cases) {
    for (std::size_t which : {0u, 1u}) {  // the first block, or one further down the ring
      if (which == 0 && std::string(bc.name) == "seq repeat") continue;
      MachineRunner run(c);
      ProgramBuilder p(c, test::home(c));
      p.line({14.0, 12.5, 25.0}, 10.0).line({14.0, 14.0, 25.0}, 10.0).line({12.5, 14.0, 25.0}, 10.0).end();
      bc.corrupt(p.blocks()[which]);
      run.start(p.blocks());
      run.run_until_done(20000);
      const Status& s = run.status();
      ASSERT_EQ(s.state, MachineState::kFault) << bc.name;
      EXPECT_EQ(s.fault, bc.code) << bc.name;
      EXPECT_EQ(s.fault_line, which + 1) << bc.name;
      EXPECT_STRNE(run.machine().fault_reason(), "") << bc.name;
      EXPECT_TRUE(run.ring().empty()) << bc.name;
      // the machine never moved on the bad block: every setpoint lies on the good blocks before it
      for (const auto& r : run.records()) {
        if (which == 0) {
          ASSERT_EQ(r.cmd, test::home(c)) << bc.name;
        } else {
          ASSERT_NEAR(r.cmd[1], 12.5, 1e-12) << bc.name;
        }
      }
    }
  }
}

TEST(Machine, PointsWithinToleranceOfTheTravelEndAreHeldOnIt) {
  MachineConfig c = test::default_machine_config();
  {
    MachineRunner run(c);
    ProgramBuilder p(c, test::home(c));
    p.line({-0.0005, 12.5, 25.0}, 50.0).line({3.0, 12.5, 25.0}, 50.0).end();  // 0.5 µm past X min
    run.start(p.blocks());
    run.run_until_done();
    EXPECT_EQ(run.status().program_done, 1) << run.machine().fault_reason();
    for (const auto& r : run.records()) ASSERT_GE(r.cmd[0], c.axes[0].travel_min_mm);
  }
  {
    MachineRunner run(c);
    ProgramBuilder p(c, test::home(c));
    p.line({-0.005, 12.5, 25.0}, 50.0).end();  // 5 µm past: refused
    run.start(p.blocks());
    run.run_until_done();
    EXPECT_EQ(run.status().fault, FaultCode::kBadBlock);
    EXPECT_STREQ(run.machine().fault_reason(), "end point outside the travel");
  }
}

TEST(Machine, ArcRadiusMismatchIsRefused) {
  MachineConfig c = test::default_machine_config();
  MachineRunner run(c);
  ProgramBuilder p(c, test::home(c));
  p.arc({12.5, 17.5, 25.0}, {12.5, 15.0, 25.0}, 2, false, 10.0).end();
  p.blocks()[0].arc.radius = 2.6;  // the points say 2.5
  run.start(p.blocks());
  run.run_until_done(1000);
  EXPECT_EQ(run.status().fault, FaultCode::kBadBlock);
  EXPECT_STREQ(run.machine().fault_reason(), "arc: start point is not on the radius");
}

TEST(Machine, ArcBulgingOutsideTheTravelIsRefused) {
  MachineConfig c = test::default_machine_config();
  MachineRunner run(c);
  ProgramBuilder p(c, test::home(c));
  p.rapid({24.0, 12.5, 25.0});
  p.arc({24.0, 12.5, 25.0}, {18.0, 18.0, 25.0}, 2, false, 10.0).end();  // r ≈ 8.1 about (18,18): y up to 26
  run.start(p.blocks());
  run.run_until_done(100000);
  EXPECT_EQ(run.status().fault, FaultCode::kBadBlock);
  EXPECT_STREQ(run.machine().fault_reason(), "arc: bulges outside the travel");
  EXPECT_EQ(run.status().fault_line, 2u);
}

TEST(Machine, EstopCutsAmplifiersAndZHoldsOnItsBrake) {
  MachineConfig c = test::default_machine_config();
  MachineRunner run(c);
  run.start(long_line(c, 40.0));
  run_to_line(run, 2, 40.0);
  run.send(CommandKind::kEstop);
  EXPECT_EQ(run.status().state, MachineState::kEstop);
  run.run(2000);
  EXPECT_EQ(run.status().state, MachineState::kEstop);
  EXPECT_TRUE(run.ring().empty());
  EXPECT_NEAR(run.machine().true_position()[2], 20.0, 0.01);  // Z did not drop
  run.send(CommandKind::kReset);
  run.run(200);
  EXPECT_EQ(run.status().state, MachineState::kIdle);
  EXPECT_LT(std::abs(run.status().following_error[2]), 0.005);
}

// A rational quadratic NURBS quarter circle (an exact circle) of radius 5 about (12.5, 12.5),
// planned by the shared NURBS planner into ring blocks, after a line from home to its start.
std::vector<Block> nurbs_quarter_program(const MachineConfig& c, double feed, bool contouring) {
  const double r = 5.0, w = std::sqrt(0.5);
  NurbsCurve curve = make_nurbs({{17.5, 12.5, 20.0}, {17.5, 17.5, 20.0}, {12.5, 17.5, 20.0}}, {1.0, w, 1.0}, 3);
  EXPECT_EQ(validate(curve), "");
  NurbsBlocks nb = plan_nurbs_blocks(curve, nurbs_limits(c, feed));
  EXPECT_EQ(nb.error, "");
  ProgramBuilder p(c, test::home(c));
  p.contouring(contouring);
  p.rapid({17.5, 12.5, 20.0});
  std::vector<Block> out = p.blocks();
  std::uint64_t seq = out.size();
  for (Block b : nb.blocks) {
    b.seq = ++seq;
    b.line = static_cast<std::uint32_t>(seq);
    b.contouring = 1;  // pieces of one curve join tangentially
    out.push_back(b);
  }
  out.back().contouring = contouring ? 1 : 0;
  ProgramBuilder tail(c, {12.5, 17.5, 20.0});
  tail.contouring(contouring).line({5.0, 17.5, 20.0}, feed).end();  // tangent continuation
  for (Block b : tail.blocks()) {
    b.seq = ++seq;
    b.line = static_cast<std::uint32_t>(seq);
    out.push_back(b);
  }
  (void)r;
  return out;
}

TEST(Machine, NurbsBlocksRunOnTheExactCurve) {
  MachineConfig c = test::default_machine_config();
  MachineRunner run(c);
  const auto prog = nurbs_quarter_program(c, 20.0, true);
  ASSERT_GE(prog.size(), 4u);
  run.start(prog);
  run.run_until_done();
  ASSERT_EQ(run.status().program_done, 1) << run.machine().fault_reason();
  EXPECT_EQ(run.check_setpoint_limits(), "");
  const std::uint32_t first = 2, last = static_cast<std::uint32_t>(prog.size() - 2);
  double worst_cmd = 0.0, worst_act = 0.0;
  int n = 0;
  for (const auto& r : run.records()) {
    if (r.line < first || r.line > last) continue;
    worst_cmd = std::max(worst_cmd, std::abs(std::hypot(r.cmd[0] - 12.5, r.cmd[1] - 12.5) - 5.0));
    worst_act = std::max(worst_act, std::abs(std::hypot(r.act[0] - 12.5, r.act[1] - 12.5) - 5.0));
    ++n;
  }
  EXPECT_GT(n, 300);  // 7.85 mm at 20 mm/s ≈ 0.39 s
  EXPECT_LT(worst_cmd, 1e-9);
  EXPECT_LT(worst_act, 5e-3);
  // the curve's end joins the tangent line without stopping; the line ends exactly
  EXPECT_EQ(run.status().junction_stops, 1u);  // only rapid -> curve
  EXPECT_NEAR(run.status().commanded[0], 5.0, 1e-12);
  std::printf("NURBS quarter circle r 5 mm at 20 mm/s: setpoint radius error %.2e mm, contour error %.3f um\n",
              worst_cmd, worst_act * 1e3);
}

TEST(Machine, CorruptNurbsBlockIsRefused) {
  MachineConfig c = test::default_machine_config();
  auto prog = nurbs_quarter_program(c, 20.0, false);
  prog[1].nurbs.knots[3] = -1.0;  // decreasing knots
  MachineRunner run(c);
  run.start(prog);
  run.run_until_done(100000);
  EXPECT_EQ(run.status().fault, FaultCode::kBadBlock);
  EXPECT_STREQ(run.machine().fault_reason(), "nurbs: knots decrease");
  EXPECT_EQ(run.status().fault_line, 2u);
}

TEST(Machine, CycleNeverAllocates) {
  MachineConfig c = test::default_machine_config();
  Machine m(c);
  MotionRing ring;
  ProgramBuilder p(c, test::home(c));
  p.contouring(true);
  p.rapid({17.5, 12.5, 20.0});
  p.arc({17.5, 12.5, 20.0}, {12.5, 12.5, 20.0}, 2, true, 20.0);
  p.line({17.6, 12.6, 20.0}, 20.0).line({17.7, 12.65, 20.0}, 20.0).dwell(0.01).pause();
  p.arc({17.7, 12.65, 16.0}, {17.7, 12.65, 18.0}, 1, false, 20.0);  // G18 half circle about (x 17.7, z 18)
  p.line({3.0, 3.0, 3.0}, 50.0).end();
  const std::vector<Block> blocks = p.blocks();
  std::size_t next = 0;
  Command cmd;
  long cycles = 0;
  g_allocations = 0;
  g_counting = true;
  auto send = [&](CommandKind k, double v = 0.0, int axis = 0, double feed = 0.0) {
    cmd.id++;
    cmd.kind = k;
    cmd.value = v;
    cmd.axis = static_cast<std::uint8_t>(axis);
    cmd.feed = feed;
    m.command(cmd);
  };
  send(CommandKind::kProgramStart);
  for (int i = 0; i < 40000 && !m.status().program_done; ++i) {
    while (next < blocks.size() && ring.try_push(blocks[next])) ++next;
    if (i == 3000) send(CommandKind::kFeedOverride, 1.7);
    if (i == 4000) send(CommandKind::kPause);
    if (i == 4500) send(CommandKind::kResume);
    if (m.status().state == MachineState::kPaused && i > 4500) send(CommandKind::kResume);
    m.set_host_alive(true);
    m.cycle(ring);
    ++cycles;
  }
  const bool done = m.status().program_done;
  send(CommandKind::kJogIncrement, 2.0, 0, 20.0);
  for (int i = 0; i < 2000; ++i) m.cycle(ring);
  m.set_axis_blocked(1, true);
  send(CommandKind::kJogIncrement, 2.0, 1, 50.0);
  for (int i = 0; i < 2000; ++i) m.cycle(ring);
  const bool faulted = m.status().state == MachineState::kFault;
  g_counting = false;
  EXPECT_TRUE(done) << to_string(m.status().state) << " " << m.fault_reason();
  EXPECT_TRUE(faulted);
  EXPECT_GT(cycles, 5000);
  EXPECT_EQ(g_allocations.load(), 0);
}

TEST(Machine, NurbsCycleNeverAllocates) {
  MachineConfig c = test::default_machine_config();
  const std::vector<Block> blocks = nurbs_quarter_program(c, 30.0, true);
  Machine m(c);
  MotionRing ring;
  Command cmd;
  cmd.id = 1;
  cmd.kind = CommandKind::kProgramStart;
  std::size_t next = 0;
  g_allocations = 0;
  g_counting = true;
  m.command(cmd);
  long cycles = 0;
  while (!m.status().program_done && cycles < 100000 && m.status().state != MachineState::kFault) {
    while (next < blocks.size() && ring.try_push(blocks[next])) ++next;
    m.cycle(ring);
    ++cycles;
  }
  g_counting = false;
  EXPECT_TRUE(m.status().program_done) << m.fault_reason();
  EXPECT_EQ(g_allocations.load(), 0);
}

}  // namespace
}  // namespace pcnc
