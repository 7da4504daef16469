// test_executor.cpp — the block executor on its own (no servo, no plant): path geometry,
// speed law, junction rules, and the stop-within-the-ring guarantee.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "motion/executor.hpp"
#include "motion/junction.hpp"
#include "motion/path.hpp"
#include "gcode/preprocessor.hpp"
#include "gcode/nurbs_schedule.hpp"
#include "geometry/nurbs.hpp"
#include "geometry/arc_limits.hpp"
#include "geometry/axis_caps.hpp"
#include "geometry/plane.hpp"
#include "machine_runner.hpp"
#include "make_blocks.hpp"

namespace pcnc {
namespace {

using test::ProgramBuilder;


struct Sample {
  Vec3 p;
  double v;
  std::uint32_t line;
};

// Runs blocks through an executor, keeping the ring full; returns one sample per cycle.
std::vector<Sample> execute(const MachineConfig& c, const std::vector<Block>& blocks, ExecResult* total = nullptr,
                            std::size_t feed_limit = kRingSlots) {
  Executor ex(c);
  ex.set_position(blocks.front().start);
  MotionRing ring;
  std::size_t next = 0;
  std::vector<Sample> out;
  ExecResult sum;
  for (int i = 0; i < 1000000; ++i) {
    while (next < blocks.size() && ring.size() < feed_limit && ring.try_push(blocks[next])) ++next;
    ExecResult r;
    ex.step(ring, ExecInput{}, r);
    EXPECT_EQ(r.fault, FaultCode::kNone) << r.reason;
    if (r.fault != FaultCode::kNone) break;
    sum.blocks_done += r.blocks_done;
    sum.junction_flows += r.junction_flows;
    sum.junction_stops += r.junction_stops;
    out.push_back({ex.position(), ex.speed(), ex.line()});
    if (r.program_end) break;
  }
  if (total) *total = sum;
  return out;
}

TEST(Junction, StopSpeedBrakesWithinTheDistance) {
  // Braking from stop_speed(d) by a·dt per cycle after moving one cycle at it covers <= d.
  const double a = 2000.0, dt = 0.0005;
  for (double d : {1e-6, 1e-4, 0.01, 0.3, 5.0}) {
    for (double k : {1.0, 2.0}) {
      const double v0 = stop_speed(d, 0.0, a, dt, k);
      double v = v0, x = v0 * dt;
      while (v > 0.0) {
        v = std::max(0.0, v - a * dt);
        x += v * dt;
      }
      EXPECT_LE(x, d * (1.0 + 1e-12)) << d;
      EXPECT_GT(v0, 0.0);
    }
  }
  // at zero distance: one cycle at v, then braking to v_end must fit: v²/2a + v·dt = v_end²/2a
  const double v = stop_speed(0.0, 10.0, a, dt, 1.0);
  EXPECT_NEAR(v * v / (2 * a) + v * dt, 100.0 / (2 * a), 1e-12);
  EXPECT_LT(v, 10.0);
  EXPECT_GT(stop_speed(1.0, 10.0, a, dt, 1.0), stop_speed(1.0, 0.0, a, dt, 1.0));
}

TEST(Junction, ExactStopSpeedBrakesOntoTheDistanceAndNoFaster) {
  // Moving v0·dt this cycle and then braking by a·dt per cycle covers d exactly, up to a last
  // landing cycle slower than a·dt; any faster start overshoots.
  const double a = 2000.0, dt = 0.0005;
  for (double d : {1e-9, 1e-6, 4.9e-4, 5e-4, 1e-3, 0.01, 0.3, 5.0, 123.4}) {
    const double v0 = stop_speed_exact(d, a, dt);
    auto covered = [&](double start) {
      double v = start, x = start * dt;
      while (v > a * dt) {
        v -= a * dt;
        x += v * dt;
      }
      return x;  // then a landing cycle at (d − x)/dt ∈ [0, a·dt] must close the gap
    };
    const double x = covered(v0);
    EXPECT_LE(x, d * (1.0 + 1e-12)) << d;
    const double v_last = v0 - std::floor(v0 / (a * dt) - 1e-12) * a * dt;  // the speed before landing
    EXPECT_LE((d - x) / dt, v_last + 1e-9) << "landing is no faster than the cycle before, d " << d;
    EXPECT_GT(covered(v0 * (1.0 + 1e-6) + 1e-9), d) << "a faster start must overshoot, d " << d;
    // never slower than the margin rule it replaces
    EXPECT_GE(v0, stop_speed(d, 0.0, a, dt, 2.0)) << d;
  }
  EXPECT_EQ(stop_speed_exact(0.0, a, dt), 0.0);
  EXPECT_EQ(stop_speed_exact(-1.0, a, dt), 0.0);
}

TEST(Junction, JunctionDeviationSpeedFollowsTheVirtualArc) {
  const std::array<double, kAxes> a{500.0, 500.0, 200.0};
  // 90° from −Z to +X: the virtual arc has R = δ·sin45°/(1 − sin45°); the velocity change
  // points along (1, 0, 1)/√2, where the axes allow min(500, 200)·√2.
  const double r = 0.01 * std::sqrt(0.5) / (1.0 - std::sqrt(0.5));
  const double v90 = junction_deviation_speed({0, 0, -1}, {1, 0, 0}, a, 0.01);
  EXPECT_NEAR(v90, std::sqrt(200.0 * std::sqrt(2.0) * r), 1e-12);
  EXPECT_NEAR(v90, 2.613, 1e-3);
  // XY corners use the X/Y limits; a shallower turn is faster; more tolerance is faster
  const double vxy = junction_deviation_speed({1, 0, 0}, {0, 1, 0}, a, 0.01);
  EXPECT_NEAR(vxy, std::sqrt(500.0 * std::sqrt(2.0) * r), 1e-12);
  const Vec3 d30 = {std::cos(0.5), std::sin(0.5), 0.0};
  EXPECT_GT(junction_deviation_speed({1, 0, 0}, d30, a, 0.01), vxy);
  EXPECT_GT(junction_deviation_speed({1, 0, 0}, {0, 1, 0}, a, 0.02), vxy);
  // straight on: unlimited; a reversal or no tolerance: a stop
  EXPECT_TRUE(std::isinf(junction_deviation_speed({1, 0, 0}, {1, 0, 0}, a, 0.01)));
  EXPECT_EQ(junction_deviation_speed({1, 0, 0}, {-1, 0, 0}, a, 0.01), 0.0);
  EXPECT_EQ(junction_deviation_speed({1, 0, 0}, {0, 1, 0}, a, 0.0), 0.0);
}

TEST(Junction, CornerSpeedTakesTheLargerOfTheTwoRules) {
  JunctionRules r;
  r.cos_limit = std::cos(10.0 * std::numbers::pi / 180.0);
  r.step_fraction = 0.5;
  r.dt = 0.0005;
  r.axis_accel = {500.0, 500.0, 200.0};
  const Vec3 x{1, 0, 0}, y{0, 1, 0}, small{std::cos(0.05), std::sin(0.05), 0.0};
  // the seed's rule alone: a small turn flows at the velocity-step cap, a 90° corner stops
  EXPECT_DOUBLE_EQ(corner_speed(true, x, small, r), junction_speed_cap(x, small, r.axis_accel, r.dt, 0.5));
  EXPECT_EQ(corner_speed(true, x, y, r), 0.0);
  // with a corner tolerance both flow, each at the larger cap
  r.path_tolerance_mm = 0.01;
  EXPECT_DOUBLE_EQ(corner_speed(true, x, y, r), junction_deviation_speed(x, y, r.axis_accel, 0.01));
  EXPECT_DOUBLE_EQ(corner_speed(true, x, small, r), std::max(junction_speed_cap(x, small, r.axis_accel, r.dt, 0.5),
                                                            junction_deviation_speed(x, small, r.axis_accel, 0.01)));
  EXPECT_GT(corner_speed(true, x, small, r), junction_speed_cap(x, small, r.axis_accel, r.dt, 0.5));
  // M22: every junction stops
  EXPECT_EQ(corner_speed(false, x, small, r), 0.0);
  EXPECT_EQ(corner_speed(false, x, y, r), 0.0);
}

TEST(Junction, ContouringAngleAndSpeedCap) {
  const double lim = std::cos(10.0 * std::numbers::pi / 180.0);
  auto dir = [](double deg) {
    const double r = deg * std::numbers::pi / 180.0;
    return Vec3{std::cos(r), std::sin(r), 0.0};
  };
  EXPECT_TRUE(junction_flows(true, dir(0), dir(9.9), lim));
  EXPECT_FALSE(junction_flows(true, dir(0), dir(10.1), lim));
  EXPECT_FALSE(junction_flows(false, dir(0), dir(1.0), lim));
  EXPECT_FALSE(junction_flows(true, dir(0), dir(90.0), lim));
  const std::array<double, 3> acc{2000.0, 1000.0, 1000.0};
  EXPECT_TRUE(std::isinf(junction_speed_cap(dir(5), dir(5), acc, 0.0005, 0.5)));
  // X changes by 1 - cos 1°, Y by sin 1°: Y (lower accel, bigger change) binds
  const double cap = junction_speed_cap(dir(0), dir(1), acc, 0.0005, 0.5);
  EXPECT_NEAR(cap, 0.5 * 1000.0 * 0.0005 / std::sin(std::numbers::pi / 180.0), 1e-9);
}

TEST(Executor, LineIsTrapezoidalAndEndsExactly) {
  MachineConfig c = test::default_machine_config();
  ProgramBuilder p(c, test::home(c));
  p.line({22.5, 12.5, 25.0}, 50.0).end();
  const auto s = execute(c, p.blocks());
  const double dt = c.cycle_period_s();
  double vmax = 0.0;
  for (const auto& x : s) {
    EXPECT_NEAR(x.p[1], 12.5, 0.0);
    vmax = std::max(vmax, x.v);
  }
  EXPECT_NEAR(vmax, 50.0, 1e-9);
  EXPECT_EQ(s.back().p, (Vec3{22.5, 12.5, 25.0}));
  // time ≈ L/v + v/a for a trapezoid (plus a few cycles of final approach)
  const double t_ideal = 10.0 / 50.0 + 50.0 / 2000.0;
  EXPECT_NEAR(static_cast<double>(s.size()) * dt, t_ideal, 0.01);
}

TEST(Executor, ArcsInEveryPlaneStayOnTheCircle) {
  MachineConfig c = test::default_machine_config();
  for (int normal = 0; normal < 3; ++normal) {
    for (bool cw : {true, false}) {
      Vec3 center{12.5, 12.5, 12.5};
      const int a1 = plane_axes(normal)[0], a2 = plane_axes(normal)[1];
      Vec3 start = center;
      start[a1] += 4.0;
      Vec3 end = center;
      end[a2] += cw ? -4.0 : 4.0;  // a quarter circle either way
      ProgramBuilder p(c, start);
      p.arc(end, center, normal, cw, 30.0).end();
      const auto s = execute(c, p.blocks());
      double worst = 0.0;
      for (const auto& x : s) {
        worst = std::max(worst, std::abs(std::hypot(x.p[a1] - center[a1], x.p[a2] - center[a2]) - 4.0));
        EXPECT_NEAR(x.p[normal], center[normal], 1e-12);
        // stays in the quadrant between start and end
        EXPECT_GE(x.p[a1] - center[a1], -1e-9);
        EXPECT_GE((cw ? -1.0 : 1.0) * (x.p[a2] - center[a2]), -1e-9);
      }
      EXPECT_LT(worst, 1e-9) << "normal " << normal << " cw " << cw;
      EXPECT_EQ(s.back().p, end);
    }
  }
}

// An arc shares its plane's acceleration by speed (path.hpp arc_path_accel): a half circle of
// 1 mm at a feed above its centripetal cap ramps up, runs at the cap and stops exactly at its
// end. On every cycle each axis's acceleration (tangential and centripetal, from the setpoints'
// second differences) stays within its limit; below the top speed it ramps faster than the
// block's constant (its value at the top speed), which is all a fixed split could use.
TEST(Executor, ArcsRampAndBrakeByTheirSpeedWithinTheAxesLimits) {
  MachineConfig c = test::default_machine_config();
  const double a_plane = std::min(c.axes[0].max_accel_mm_s2, c.axes[1].max_accel_mm_s2);
  const Vec3 center{12.5, 12.5, 12.5};
  const double r = 1.0;
  ProgramBuilder p(c, {center[0] + r, center[1], center[2]});
  p.arc({center[0] - r, center[1], center[2]}, center, 2, false, 1000.0).end();
  // the host's own plan of the arc (the builder's is a simpler one)
  Move m;
  m.kind = MoveKind::kArc;
  m.start = {center[0] + r, center[1], center[2]};
  m.end = {center[0] - r, center[1], center[2]};
  m.center = center;
  m.radius = r;
  m.sweep = std::numbers::pi;
  m.normal_axis = 2;
  m.feed_mm_s = 1000.0;
  std::vector<Block> blocks = p.blocks();
  const std::uint64_t seq = blocks.front().seq;
  blocks.front() = make_block(m, c);
  blocks.front().seq = seq;
  const PreparedBlock pb = prepare_block(blocks.front(), c);
  const double cap = std::sqrt(kArcCentripetalShare * a_plane * r);
  ASSERT_NEAR(pb.v_machine, cap, 1e-9);
  ASSERT_LT(pb.accel, 0.35 * a_plane) << "the constant: what the plane leaves at the cap";
  EXPECT_GT(arc_path_accel(pb, 0.0), 0.94 * a_plane);
  EXPECT_NEAR(arc_path_accel(pb, cap), kArcAccelMargin * pb.accel, 1e-6 * a_plane);
  const auto s = execute(c, blocks);
  const double dt = c.cycle_period_s();
  double worst = 0.0, v_max = 0.0;
  for (std::size_t k = 2; k < s.size(); ++k) {
    Vec3 acc{};
    for (int i = 0; i < 3; ++i) acc[i] = (s[k].p[i] - 2.0 * s[k - 1].p[i] + s[k - 2].p[i]) / (dt * dt);
    worst = std::max({worst, std::abs(acc[0]) / c.axes[0].max_accel_mm_s2, std::abs(acc[1]) / c.axes[1].max_accel_mm_s2});
    v_max = std::max(v_max, s[k].v);
  }
  EXPECT_LE(worst, 1.0 + 1e-3) << "every axis within its limit on every cycle";
  EXPECT_NEAR(v_max, cap, 1e-9) << "reaches the cap";
  EXPECT_EQ(s.back().p, blocks.front().end);
  EXPECT_EQ(s.back().v, 0.0);
  // the first half of the cap is reached at nearly the whole plane's acceleration
  std::size_t k_half = 0;
  while (s[k_half].v < 0.5 * cap) ++k_half;
  const double t_half = static_cast<double>(k_half + 1) * dt;
  EXPECT_LT(t_half, 0.5 * cap / (0.9 * a_plane));
  EXPECT_LT(t_half, 0.5 * 0.5 * cap / pb.accel) << "twice as fast as at the constant";
}

// A curve's tangential acceleration by speed (path.hpp curve_tangential_accel), on a circle of
// radius 2 in XY drawn with u the angle: at the point where the tangent is +Y the normal part
// v²/r loads X alone, so the tangential part gets Y's share until v²/r takes X's; at 45° both
// axes carry both parts.
TEST(Executor, CurveTangentialAccelerationIsWhatTheAxesLeaveAtThatSpeed) {
  const MachineConfig c = test::default_machine_config();
  const double ax = c.axes[0].max_accel_mm_s2, ay = c.axes[1].max_accel_mm_s2, m = kArcAccelMargin;
  const double r = 2.0;
  auto at = [&](double th) {
    NurbsEval e;
    e.p = {r * std::cos(th), r * std::sin(th), 0.0};
    e.d1 = {-r * std::sin(th), r * std::cos(th), 0.0};
    e.d2 = {-r * std::cos(th), -r * std::sin(th), 0.0};
    return e;
  };
  EXPECT_NEAR(curve_tangential_accel(at(0.0), c, 0.0), m * ay, 1e-9);
  EXPECT_NEAR(curve_tangential_accel(at(0.0), c, 20.0), m * ay, 1e-9) << "the normal part is on X alone";
  EXPECT_EQ(curve_tangential_accel(at(0.0), c, std::sqrt(m * ax * r) * 1.001), 0.0) << "X has nothing left";
  const double th = std::numbers::pi / 4.0, s = std::sqrt(0.5);
  for (double v : {0.0, 10.0, 30.0, 50.0}) {
    const double room = std::min(m * ax, m * ay) - v * v / r * s;
    EXPECT_NEAR(curve_tangential_accel(at(th), c, v), std::max(0.0, room) / s, 1e-9) << v;
    // a_t·T + (v²/r)·N within m·A on both axes, and the bound is reached on one of them
    const double a_t = curve_tangential_accel(at(th), c, v);
    const double x = std::abs(-a_t * s - v * v / r * s), y = std::abs(a_t * s - v * v / r * s);
    EXPECT_LE(x, m * ax + 1e-9);
    EXPECT_LE(y, m * ay + 1e-9);
  }
}

TEST(Executor, HelixAdvancesTheNormalAxisWithTheAngle) {
  MachineConfig c = test::default_machine_config();
  const Vec3 center{12.5, 12.5, 20.0};
  ProgramBuilder p(c, {15.5, 12.5, 20.0});
  p.arc({15.5, 12.5, 14.0}, center, 2, false, 20.0, 1).end();  // two full turns, down 6 mm
  const auto s = execute(c, p.blocks());
  double prev_angle = 0.0, unwrapped = 0.0;
  for (const auto& x : s) {
    const double ang = std::atan2(x.p[1] - center[1], x.p[0] - center[0]);
    double d = ang - prev_angle;
    if (d < -std::numbers::pi) d += 2 * std::numbers::pi;
    if (d > std::numbers::pi) d -= 2 * std::numbers::pi;
    unwrapped += d;
    prev_angle = ang;
    // z = 20 - 6 * angle / (4π)
    EXPECT_NEAR(x.p[2], 20.0 - 6.0 * unwrapped / (4.0 * std::numbers::pi), 1e-9);
  }
  EXPECT_NEAR(unwrapped, 4.0 * std::numbers::pi, 1e-9);
  EXPECT_EQ(s.back().p, (Vec3{15.5, 12.5, 14.0}));
}

TEST(Executor, RadiusMismatchWithinToleranceStillJoinsStartAndEnd) {
  MachineConfig c = test::default_machine_config();
  ProgramBuilder p(c, {17.5, 12.5, 20.0});
  p.arc({12.5, 17.501, 20.0}, {12.5, 12.5, 20.0}, 2, false, 20.0).end();  // end radius 5.001
  const auto s = execute(c, p.blocks());
  EXPECT_EQ(s.back().p, (Vec3{12.5, 17.501, 20.0}));
  for (std::size_t k = 1; k < s.size(); ++k) EXPECT_LT(norm(s[k].p - s[k - 1].p), 20.0 * c.cycle_period_s() + 1e-9);
}

TEST(Executor, ShortRingCostsSpeedNeverSafety) {
  // Host handing one block at a time: contouring cannot look ahead, so every block ends at
  // rest; with the full ring the same program flows through its vertices.
  MachineConfig c = test::default_machine_config();
  const auto prog = test::polygon_circle_program(c, {12.5, 12.5, 20.0}, 5.0, 72, 25.0, true);
  ExecResult one, full;
  const auto s1 = execute(c, prog, &one, 1);
  const auto s4 = execute(c, prog, &full, kRingSlots);
  EXPECT_EQ(one.junction_flows, 0);
  EXPECT_EQ(full.junction_flows, 71);
  EXPECT_GT(s1.size(), s4.size());
}

TEST(Executor, AlwaysAbleToStopWithinTheRing) {
  // At sampled cycles of an M21 polygon circle at high feed, clone the executor and the ring
  // as they are and let the host vanish: the clone must come to rest within the blocks it
  // already has, never braking harder than the blocks' accelerations allow.
  MachineConfig c = test::default_machine_config();
  const auto prog = test::polygon_circle_program(c, {12.5, 12.5, 12.5}, 5.0, 120, 60.0, true);
  Executor ex(c);
  ex.set_position(prog.front().start);
  MotionRing ring;
  std::size_t next = 0;
  const double dt = c.cycle_period_s();
  int clones = 0;
  for (int i = 0; i < 100000; ++i) {
    while (next < prog.size() && ring.try_push(prog[next])) ++next;
    ExecResult r;
    ex.step(ring, ExecInput{}, r);
    ASSERT_EQ(r.fault, FaultCode::kNone);
    if (r.program_end) break;
    if (i % 5 != 0 || ex.speed() == 0.0) continue;
    Executor cl = ex;
    MotionRing cring;
    for (std::size_t k = 0; k < ring.size(); ++k) cring.try_push(ring.peek(k));
    double v = cl.speed();
    Vec3 p = cl.position();
    for (int j = 0; j < 100000; ++j) {
      ExecResult rr;
      cl.step(cring, ExecInput{}, rr);
      ASSERT_LE(v - cl.speed(), c.axes[0].max_accel_mm_s2 * std::sqrt(2.0) * dt * (1 + 1e-9)) << "cycle " << i;
      v = cl.speed();
      if (rr.starved) break;
      p = cl.position();
    }
    EXPECT_EQ(cl.speed(), 0.0);
    ++clones;
  }
  EXPECT_GT(clones, 50);
}

// A zigzag program's run (segment j from line first + j, direction dirs[j]): every junction a
// cycle crosses (one cycle may cross several) at most at its junction_speed_cap, and no cycle's
// speed change above its blocks' acceleration. Returns the crossings and how many ran within 10 %
// of their cap.
struct Crossings {
  int count = 0;
  int tight = 0;
};

// A zigzag in the XY plane under M21, built move by move from a rapid to `start`: each move
// turns the heading by `turn` (rad, signed) and goes `len` mm; the directions are kept for
// check_zigzag_run, whose `first` line is that of blocks()[1].
struct Zigzag {
  ProgramBuilder p;
  std::vector<Vec3> dirs;
  Vec3 at;
  double heading = 0.0;
  Zigzag(const MachineConfig& c, const Vec3& start) : p(c, test::home(c)), at(start) { p.rapid(start).contouring(true); }
  Vec3 end_of(double turn, double len) const {
    return at + len * Vec3{std::cos(heading + turn), std::sin(heading + turn), 0.0};
  }
  void go(double turn, double len, double feed) {
    heading += turn;
    const Vec3 d{std::cos(heading), std::sin(heading), 0.0};
    at = at + len * d;
    p.line(at, feed);
    dirs.push_back(d);
  }
};

Crossings check_zigzag_run(const std::vector<Sample>& s, std::uint32_t first, const std::vector<Vec3>& dirs,
                           const MachineConfig& c, const std::string& what) {
  const double dt = c.cycle_period_s(), f = c.motion.junction_velocity_step_fraction;
  const std::array<double, kAxes> acc{c.axes[0].max_accel_mm_s2, c.axes[1].max_accel_mm_s2, c.axes[2].max_accel_mm_s2};
  auto segment = [&](std::uint32_t line) { return line >= first && line - first < dirs.size() ? line - first : dirs.size(); };
  Crossings out;
  for (std::size_t k = 1; k < s.size(); ++k) {
    const std::size_t a = segment(s[k - 1].line), b = segment(s[k].line);
    if (a < dirs.size() && b < dirs.size()) {
      // the larger of the two blocks' accelerations where the cycle crosses
      const double limit = std::max(axis_cap(dirs[a], acc), axis_cap(dirs[b], acc));
      EXPECT_LE(std::abs(s[k].v - s[k - 1].v), limit * dt * (1.0 + 1e-9)) << what << " line " << s[k].line;
    }
    if (a >= dirs.size() || s[k].line <= s[k - 1].line) continue;
    for (std::size_t j = a; j < std::min(b, dirs.size() - 1); ++j) {  // from segment j to j + 1
      const double cap = junction_speed_cap(dirs[j], dirs[j + 1], acc, dt, f);
      EXPECT_LE(s[k].v, cap * (1.0 + 1e-9)) << what << " junction " << j;
      ++out.count;
      out.tight += s[k].v > 0.9 * cap;
    }
  }
  return out;
}

TEST(Executor, FlowingJunctionsAreCrossedWithinTheirCapsWhileBraking) {
  // A zigzag under M21 (path tolerance 0: the seed's rule, each junction capped by the velocity
  // step its turn asks, junction_speed_cap) whose turns grow from 0.5° to 9.5° over each run of
  // ten short segments, at a feed far above the caps: the executor brakes through several blocks
  // into ever lower caps. The cycle that crosses each junction runs at most at its cap, also
  // with the junction-restricted cycles (at (1 − f)·a) after each crossing and before the next:
  // the stop rule's margin (docs/rt-executor.md, "Speed law").
  MachineConfig c = test::default_machine_config();
  c.motion.path_tolerance_mm = 0.0;
  Zigzag z(c, {1.5, 12.5, 20.0});
  for (int i = 0; i < 60; ++i) {
    const double turn = (0.5 + 9.0 * static_cast<double>(i % 10) / 9.0) * std::numbers::pi / 180.0;
    // long enough to brake from cap to cap within one segment, then segments of a few cycles
    // each, across which the look-ahead's backward pass must plan the braking
    const double len = (i < 30 ? 0.2 : 0.03) * (1.0 + 0.75 * static_cast<double>(i % 3));
    z.go((i % 2 == 0 ? 1.0 : -1.0) * turn, len, 80.0);
  }
  z.p.end();
  const Crossings x = check_zigzag_run(execute(c, z.p.blocks()), z.p.blocks()[1].line, z.dirs, c, "zigzag");
  EXPECT_GT(x.count, 50);
  EXPECT_GT(x.tight, 20);  // the caps bind: the executor runs up to them
}

TEST(Junction, TheTurnsShareGrowsWithTheCrossingSpeed) {
  const std::array<double, kAxes> acc{2000.0, 2000.0, 1000.0};
  const double dt = 0.0005, f = 0.5;
  const Vec3 x{1, 0, 0};
  const double e = 3.0 * std::numbers::pi / 180.0;
  const Vec3 turned{std::cos(e), std::sin(e), 0.0};
  // a tangent junction takes nothing; a velocity step at its cap takes the whole fraction, and
  // half of it at half the cap
  EXPECT_EQ(turn_share_at(turn_share(x, x, acc, dt, 0.0), 50.0, f), 0.0);
  const double cap = junction_speed_cap(x, turned, acc, dt, f);
  const TurnShare step = turn_share(x, turned, acc, dt, 0.0);
  EXPECT_NEAR(turn_share_at(step, cap, f), f, 1e-12);
  EXPECT_NEAR(turn_share_at(step, 0.5 * cap, f), 0.5 * f, 1e-12);
  EXPECT_EQ(turn_share_at(step, 10.0 * cap, f), f) << "never above the fraction";
  // a corner window of half-length h: its peak turn acceleration v²·1.5·|Δu_i|/(2h) over the axis's
  const double h = 0.02, v = 10.0;
  const TurnShare window = turn_share(x, turned, acc, dt, h);
  const double dy = std::sin(e), dx = 1.0 - std::cos(e);
  EXPECT_NEAR(turn_share_at(window, v, f), v * v * 1.5 * std::max(dx, dy) / (2.0 * h * 2000.0), 1e-12);
  // next to a rotary block: the whole fraction at any speed
  EXPECT_EQ(turn_share_at(TurnShare{}, 1.0, f), f);
}

TEST(Executor, AJunctionCrossedWellBelowItsCapKeepsMostOfTheAcceleration) {
  // Ramping from rest through a 0.5° junction 0.05 mm ahead (crossed at about 14 mm/s, its cap
  // over 50 mm/s): its velocity step takes about a quarter of f there, so the cycles around it
  // keep nearly all of the acceleration (until 2026-11-27 they kept (1 − f)·a, half).
  MachineConfig c = test::default_machine_config();
  c.motion.path_tolerance_mm = 0.0;
  const double dt = c.cycle_period_s(), f = c.motion.junction_velocity_step_fraction;
  const Vec3 a0{2.0, 12.5, 20.0}, a1 = a0 + Vec3{0.05, 0.0, 0.0};
  const double e = 0.5 * std::numbers::pi / 180.0;
  const Vec3 a2 = a1 + 5.0 * Vec3{std::cos(e), std::sin(e), 0.0};
  ProgramBuilder p(c, a0);
  p.contouring(true).line(a1, 80.0).line(a2, 80.0).end();
  const auto s = execute(c, p.blocks());
  const std::array<double, kAxes> acc{c.axes[0].max_accel_mm_s2, c.axes[1].max_accel_mm_s2, c.axes[2].max_accel_mm_s2};
  const double cap = junction_speed_cap({1, 0, 0}, {std::cos(e), std::sin(e), 0}, acc, dt, f);
  int around = 0;
  for (std::size_t k = 2; k + 1 < s.size(); ++k) {
    const bool crossing = s[k].line != s[k - 1].line && s[k - 1].line == p.blocks()[0].line;
    if (!crossing) continue;
    EXPECT_LT(s[k].v, 0.4 * cap);
    // the crossing cycle and the one after it ramp at nearly the full 2000 mm/s²
    for (std::size_t j = k; j <= k + 1; ++j) {
      EXPECT_GT(s[j].v - s[j - 1].v, 0.85 * 2000.0 * dt) << "cycle " << j;
      ++around;
    }
  }
  EXPECT_EQ(around, 2);
}

TEST(Executor, RandomZigzagsAreCrossedWithinTheirCaps) {
  // The test above on random zigzags: 40 programs of 40 segments each, lengths from a small part
  // of a cycle's travel to many cycles', turns from 0.2° to 9.8° either way, feeds 20-100 mm/s,
  // the ring fed 4, 3, 2 and 1 blocks deep. Every crossing runs at most at its cap, and the speed
  // never changes by more than the axes' acceleration allows in a cycle.
  MachineConfig c = test::default_machine_config();
  c.motion.path_tolerance_mm = 0.0;
  std::mt19937 rng(20261127);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int crossings = 0, tight = 0;
  for (int program = 0; program < 40; ++program) {
    Zigzag z(c, {2.0, 12.5, 20.0});
    const double feed = 20.0 + 80.0 * unit(rng);
    int micro = 0;  // moves left in a run of micro moves
    for (int i = 0; i < 40; ++i) {
      // 0.003 to 1 mm turning by 0.2-9.8°; now and then a run of 3-8 collinear micro moves of
      // 0.1-10 µm, as CAM output has (one cycle may cross several, and more than the ring holds)
      if (micro == 0 && unit(rng) < 0.1) micro = 3 + static_cast<int>(6.0 * unit(rng));
      const double turn = (micro > 0 ? 0.0 : 0.2 + 9.6 * unit(rng)) * std::numbers::pi / 180.0;
      const double signed_turn = (unit(rng) < 0.5 ? 1.0 : -1.0) * turn;
      const double len = micro > 0 ? std::pow(10.0, -4.0 + 2.0 * unit(rng)) : std::pow(10.0, -2.5 + 2.5 * unit(rng));
      if (micro > 0) --micro;
      const Vec3 e = z.end_of(signed_turn, len);
      if (e[0] > 23.0 || e[1] < 2.0 || e[1] > 23.0) break;
      z.go(signed_turn, len, feed);
    }
    z.p.end();
    for (const std::size_t feed_limit : {kRingSlots, std::size_t{3}, std::size_t{2}, std::size_t{1}}) {
      const Crossings x = check_zigzag_run(execute(c, z.p.blocks(), nullptr, feed_limit), z.p.blocks()[1].line, z.dirs, c,
                                           "program " + std::to_string(program) + " ring " + std::to_string(feed_limit));
      crossings += x.count;
      tight += x.tight;
    }
  }
  EXPECT_GT(crossings, 1000);
  EXPECT_GT(tight, 200);
}

TEST(Executor, FeedHoldRampsDownAndResumes) {
  MachineConfig c = test::default_machine_config();
  ProgramBuilder p(c, {2.0, 12.5, 20.0});
  p.line({23.0, 12.5, 20.0}, 80.0).end();
  Executor ex(c);
  ex.set_position({2.0, 12.5, 20.0});
  MotionRing ring;
  for (const Block& b : p.blocks()) ring.try_push(b);
  ExecInput in;
  ExecResult r;
  for (int i = 0; i < 200; ++i) ex.step(ring, in, r);
  EXPECT_NEAR(ex.speed(), 80.0, 1e-9);
  in.hold = true;
  int n = 0;
  double prev = ex.speed();
  while (ex.speed() > 0.0) {
    ex.step(ring, in, r);
    EXPECT_NEAR(prev - ex.speed(), 2000.0 * c.cycle_period_s(), 1e-9);
    prev = ex.speed();
    ++n;
  }
  EXPECT_EQ(n, 80);  // 80 mm/s at 2000 mm/s² = 40 ms = 80 cycles
  const Vec3 held = ex.position();
  for (int i = 0; i < 10; ++i) ex.step(ring, in, r);
  EXPECT_EQ(ex.position(), held);
  in.hold = false;
  for (int i = 0; i < 100000 && !r.program_end; ++i) ex.step(ring, in, r);
  EXPECT_EQ(ex.position(), (Vec3{23.0, 12.5, 20.0}));
}

// A block that starts from rest a hair away from where the machine stands (a program resumed
// after a lost host: the block the machine stood at the end of skipped, a curve cut at the point
// nearest to the machine, a hold inside a corner window) is reached by a move of its own within
// every axis's limits: no setpoint steps, however the block begins. Before the gap move the
// first cycle jumped the gap: 0.9 µm in 0.5 ms is 3600 mm/s² on top of the block's ramp.
struct GapRun {
  std::vector<Vec3> p;  // the setpoints, two at the standing point first
  bool ended = false;
};

GapRun run_from(const MachineConfig& c, const Vec3& stand, const std::vector<Block>& blocks, int held_cycles = 0) {
  Executor ex(c);
  ex.set_position(stand);
  MotionRing ring;
  for (const Block& b : blocks) EXPECT_TRUE(ring.try_push(b));
  GapRun run;
  run.p = {stand, stand};
  ExecInput in;
  for (int i = 0; i < 200000; ++i) {
    in.hold = i < held_cycles;
    ExecResult r;
    ex.step(ring, in, r);
    EXPECT_EQ(r.fault, FaultCode::kNone) << r.reason;
    if (r.fault != FaultCode::kNone) break;
    if (i < held_cycles) {
      EXPECT_EQ(ex.position(), stand) << "moved while held, cycle " << i;
    }
    run.p.push_back(ex.position());
    if (r.program_end) {
      run.ended = true;
      break;
    }
  }
  return run;
}

// The largest velocity and acceleration of each axis over the setpoints, as shares of its limits.
void expect_within_axis_limits(const MachineConfig& c, const std::vector<Vec3>& p, const std::string& what) {
  const double dt = c.cycle_period_s();
  for (int i = 0; i < kAxes; ++i) {
    double worst_v = 0.0, worst_a = 0.0;
    for (std::size_t k = 1; k < p.size(); ++k) {
      worst_v = std::max(worst_v, std::abs(p[k][i] - p[k - 1][i]) / dt / c.axes[i].max_velocity_mm_s);
      if (k >= 2) {
        const double a = std::abs(p[k][i] - 2.0 * p[k - 1][i] + p[k - 2][i]) / (dt * dt);
        worst_a = std::max(worst_a, a / c.axes[i].max_accel_mm_s2);
      }
    }
    EXPECT_LE(worst_v, 1.0 + 1e-9) << what << ": axis " << "XYZ"[i];
    EXPECT_LE(worst_a, 1.0 + 1e-6) << what << ": axis " << "XYZ"[i];
  }
}

TEST(Executor, ABlockStartingAHairAwayFromTheMachineIsReachedWithinTheAxisLimits) {
  const MachineConfig c = test::default_machine_config();
  const double gap = 0.9 * c.motion.block_tolerance_mm;
  const Vec3 start{12.4, 0.96, 12.0};
  NurbsCurve curve = make_nurbs({start, {14.0, 2.0, 12.0}, {16.0, 1.0, 12.5}, {18.0, 3.0, 12.0}}, {1, 1, 1, 1}, 4);
  const NurbsBlocks nb = plan_nurbs_blocks(curve, nurbs_limits(c, 20.0));
  ASSERT_EQ(nb.error, "");
  ASSERT_EQ(nb.blocks.size(), 1u);
  struct Case {
    const char* what;
    std::vector<Block> blocks;
  };
  std::vector<Case> cases;
  {
    ProgramBuilder p(c, start);
    p.line({12.0, 5.0, 12.0}, 40.0).end();
    cases.push_back({"line", p.blocks()});
  }
  {
    ProgramBuilder p(c, start);
    p.arc({14.4, 2.96, 12.0}, {14.4, 0.96, 12.0}, 2, true, 30.0).end();
    cases.push_back({"arc", p.blocks()});
  }
  {
    Block end = cases[0].blocks.back();
    std::vector<Block> blocks = nb.blocks;
    blocks[0].seq = 1;
    end.seq = 2;
    blocks.push_back(end);
    cases.push_back({"NURBS", blocks});
  }
  for (const Case& k : cases) {
    const Vec3 to = k.blocks.back().kind == BlockKind::kEnd ? k.blocks[k.blocks.size() - 2].end : k.blocks.back().end;
    for (const Vec3 dir : {Vec3{0.0, 1.0, 0.0}, normalized(Vec3{-0.3, -1.0, 0.2}), normalized(Vec3{1.0, 0.0, -1.0})}) {
      for (const double d : {0.21e-3, gap}) {
        for (const int held : {0, 7}) {
          const Vec3 stand = start + d * dir;
          const GapRun run = run_from(c, stand, k.blocks, held);
          const std::string what = std::string(k.what) + " " + std::to_string(d * 1e3) + " um away, held " + std::to_string(held);
          ASSERT_TRUE(run.ended) << what;
          EXPECT_NEAR(norm(run.p.back() - to), 0.0, 1e-9) << what;
          expect_within_axis_limits(c, run.p, what);
          // the gap is moved in a straight line: every setpoint up to the block's start lies on it
          std::size_t k0 = 2 + static_cast<std::size_t>(held);
          for (; k0 < run.p.size() && norm(run.p[k0] - start) > 1e-12; ++k0) {
            const Vec3 off = run.p[k0] - stand;
            EXPECT_NEAR(norm(off - dot(off, -1.0 * dir) * (-1.0 * dir)), 0.0, 1e-12) << what;
          }
          EXPECT_LT(k0, 12u + static_cast<std::size_t>(held)) << what << ": the block's start reached within a few cycles";
        }
      }
    }
  }
}

}  // namespace
}  // namespace pcnc
