// test_time_causes.cpp — where the time goes: the plan check records per line (cruise cause,
// acceleration cause, junction kinds and angles), each trace row's cause, seconds per cause
// adding up to the program time, the summary's plan round trip, and the latency quantiles'
// order (p50 <= p99 <= max).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numeric>
#include <string>

#include "gcode_test_util.hpp"
#include "ipc/latency_histogram.hpp"
#include "report/run_summary.hpp"
#include "report/time_causes.hpp"
#include "report/trace_reader.hpp"
#include "test_paths.hpp"

namespace pcnc::test {
namespace {

std::vector<LinePlan> plan_of(const std::string& text, const MachineConfig& c) {
  JobOptions o;
  o.start_position = Vec3{0, 0, 0};
  const CheckResult r = check_program_text(text, "t.ngc", c, o);
  EXPECT_TRUE(r.ok);
  for (const auto& d : r.diagnostics) {
    if (d.severity == Diagnostic::Severity::kError) ADD_FAILURE() << d.message;
  }
  return r.plan;
}

const LinePlan* entry(const std::vector<LinePlan>& plan, std::uint32_t line) {
  for (const LinePlan& p : plan) {
    if (p.first <= line && line <= p.last) return &p;
  }
  return nullptr;
}

TEST(TimeCausePlan, CruiseCausesFromThePreprocessorsRules) {
  const MachineConfig c = wide_config();  // X, Y 100 mm/s 2000 mm/s², Z 50 mm/s 1000 mm/s²
  ASSERT_EQ(c.axes[2].max_velocity_mm_s, 50.0);
  const auto plan = plan_of(
      "G21 G90 M21\n"      // 1
      "G1 X10 F600\n"      // 2 feed-limited, 10 mm/s
      "G1 Z10 F6000\n"     // 3 Z alone at 100 mm/s: Z's 50 mm/s caps it
      "G1 X20 F9000\n"     // 4 F above the machine maximum (100 mm/s): clamped
      "G0 X0\n"            // 5 rapid
      "G1 X1 F6000\n"      // 6
      "G2 X3 I1 J0\n"      // 7 r = 1 mm at 100 mm/s: the centripetal limit sqrt(0.5*2000*1) = 31.6 mm/s
      "M30\n",
      c);
  ASSERT_NE(entry(plan, 2), nullptr);
  EXPECT_EQ(entry(plan, 2)->cruise, TimeCause::kFeed);
  EXPECT_NEAR(entry(plan, 2)->speed, 10.0, 1e-9);
  EXPECT_EQ(entry(plan, 2)->accel, TimeCause::kAccelX);
  EXPECT_EQ(entry(plan, 3)->cruise, TimeCause::kAxisVelocityZ);
  EXPECT_EQ(entry(plan, 3)->accel, TimeCause::kAccelZ);
  EXPECT_EQ(entry(plan, 4)->cruise, TimeCause::kFeedClamp);
  EXPECT_EQ(entry(plan, 5)->cruise, TimeCause::kRapid);
  EXPECT_EQ(entry(plan, 7)->cruise, TimeCause::kArcCentripetal);
  EXPECT_EQ(entry(plan, 7)->accel, TimeCause::kAccelArcCurve);
  // junctions: the program starts and ends at rest; X then Z turns by 90° (over the angle), and
  // the desktop mill's path tolerance (0.005 mm) lets the rt pass it at the junction-deviation
  // speed: a corner, not a stop
  ASSERT_GT(c.motion.path_tolerance_mm, 0.0);
  EXPECT_EQ(entry(plan, 2)->before, JunctionKind::kStartEnd);
  EXPECT_EQ(entry(plan, 2)->after, JunctionKind::kCorner);
  EXPECT_NEAR(entry(plan, 2)->angle_after_deg, 90.0, 1e-6);
  EXPECT_EQ(entry(plan, 3)->before, JunctionKind::kCorner);
  EXPECT_EQ(entry(plan, 7)->after, JunctionKind::kStartEnd);
}

// The junction after a block is judged by that block's path tolerance, as the rt judges it
// (rt/motion/junction.hpp corner_speed): over the contouring angle it stops only without a
// tolerance; a reversal stops either way. (The plan once forgot the block's tolerance and
// named every real corner between LHchips4's smoothed curves a stop: 19.5 s of "junction stop"
// in a run with no stop.)
TEST(TimeCausePlan, CornersOverTheAngleStopOnlyWithoutATolerance) {
  const std::string text = "G21 G90 M21\nG1 X1 F600\nG1 X1 Y1\nG1 X0.5 Y1.01\nG1 X1 Y1\nM30\n";
  MachineConfig c = wide_config();
  c.motion.path_tolerance_mm = 0.005;
  auto plan = plan_of(text, c);
  ASSERT_NE(entry(plan, 2), nullptr);
  EXPECT_EQ(entry(plan, 2)->after, JunctionKind::kCorner);     // 90°, passed at sqrt(a·R)
  EXPECT_NEAR(entry(plan, 2)->angle_after_deg, 90.0, 1e-6);
  EXPECT_EQ(entry(plan, 3)->after, JunctionKind::kCorner);     // 91.1°
  EXPECT_EQ(entry(plan, 4)->before, JunctionKind::kCorner);
  EXPECT_EQ(entry(plan, 4)->after, JunctionKind::kAngleStop);  // 180° (back along line 3): a reversal stops
  EXPECT_NEAR(entry(plan, 4)->angle_after_deg, 180.0, 1e-6);
  c.motion.path_tolerance_mm = 0.0;  // the seed's rule: over 10° is a stop
  plan = plan_of(text, c);
  EXPECT_EQ(entry(plan, 2)->after, JunctionKind::kAngleStop);
  EXPECT_EQ(entry(plan, 3)->after, JunctionKind::kAngleStop);
  EXPECT_EQ(entry(plan, 4)->after, JunctionKind::kAngleStop);
}

TEST(TimeCausePlan, JunctionKindsAndMergedRuns) {
  MachineConfig c = wide_config();
  c.motion.path_tolerance_mm = 0.0;  // the seed's rule: the G1 runs stay lines (no smoothing)
  auto plan = plan_of("G21 G90 M21\nG1 X1 F600\nG1 X2\nG1 X3\nG1 X4 Y0.05\nM22\nG1 X5 Y0.05\nM30\n", c);
  // lines 2-4 are collinear with one plan: one entry
  const LinePlan* a = entry(plan, 2);
  ASSERT_NE(a, nullptr);
  EXPECT_EQ(a, entry(plan, 4));
  EXPECT_EQ(a->first, 2u);
  EXPECT_EQ(a->last, 4u);
  // line 5 turns by ~2.9°: under the 10° angle with M21, a corner passed
  EXPECT_EQ(a->after, JunctionKind::kCorner);
  EXPECT_NEAR(a->angle_after_deg, 2.862, 0.01);
  // the junction after line 5 belongs to a block with M21 ... line 7 runs under M22: its start junction
  // is judged by line 5's block (M21), its end is the program's end
  EXPECT_EQ(entry(plan, 7)->after, JunctionKind::kStartEnd);
  // under M22 every junction stops, even a straight one
  plan = plan_of("G21 G90 M22\nG1 X1 F600\nG1 X2\nM30\n", c);
  EXPECT_EQ(entry(plan, 2)->after, JunctionKind::kContouringOff);
  EXPECT_EQ(entry(plan, 3)->before, JunctionKind::kContouringOff);
}

TraceSample row(std::uint32_t line, double speed, MachineState s = MachineState::kRunning) {
  TraceSample r;
  r.line = line;
  r.speed = speed;
  r.state = s;
  return r;
}

// A block that only turns the tool (TCP off: the linear axes stand still while C turns) is
// started and ended at rest by the rt (rt/motion/executor.cpp: an angular block never flows):
// both its junctions are stops (kTurnStop, a junction_stop), while a rotary move that also moves
// X flows like any other straight continuation.
TEST(TimeCausePlan, ABlockThatOnlyTurnsTheToolStopsAtBothEnds) {
  const MachineConfig c = load_config(source_dir() + "/configs/desktop-5axis.toml");
  const auto plan = plan_of(
      "G21 G90 G94 M21\n"  // 1
      "G1 X1 F600\n"       // 2
      "G1 C30 F600\n"      // 3 only C turns: angular
      "G1 X2 F600\n"       // 4
      "G1 X3 C40 F600\n"   // 5 X moves while C turns: not angular
      "G1 X4 F600\n"       // 6
      "M30\n",
      c);
  ASSERT_NE(entry(plan, 3), nullptr);
  EXPECT_EQ(entry(plan, 2)->after, JunctionKind::kTurnStop);
  EXPECT_EQ(entry(plan, 3)->before, JunctionKind::kTurnStop);
  EXPECT_EQ(entry(plan, 3)->after, JunctionKind::kTurnStop);
  EXPECT_EQ(entry(plan, 4)->before, JunctionKind::kTurnStop);
  EXPECT_EQ(entry(plan, 3)->angle_before_deg, 0.0);
  // lines 4 to 6 run on along X, line 5 turning C as well: straight junctions, one merged entry
  EXPECT_EQ(entry(plan, 4)->last, 6u);
  EXPECT_EQ(entry(plan, 6)->after, JunctionKind::kStartEnd);
  // the summary keeps the new kind (its compact plan entry)
  RunSummary s;
  s.plan = plan;
  const RunSummary back = run_summary_from_json(to_json(s));
  ASSERT_EQ(back.plan.size(), plan.size());
  for (std::size_t i = 0; i < plan.size(); ++i) {
    EXPECT_EQ(back.plan[i].before, plan[i].before) << i;
    EXPECT_EQ(back.plan[i].after, plan[i].after) << i;
  }
}

TEST(TimeCauseClassifier, EachRowOneCause) {
  LinePlan p;
  p.first = 5;
  p.last = 6;
  p.cruise = TimeCause::kFeed;
  p.accel = TimeCause::kAccelY;
  p.speed = 10.0;
  p.before = JunctionKind::kAngleStop;
  p.after = JunctionKind::kCorner;
  LinePlan q = p;
  q.first = q.last = 7;
  q.before = JunctionKind::kCorner;
  q.after = JunctionKind::kStraight;
  LinePlan dw;
  dw.first = dw.last = 8;
  dw.cruise = TimeCause::kDwell;
  const CauseClassifier k({p, q, dw});
  EXPECT_EQ(k.classify(row(5, 10.0), 10.0).cause, TimeCause::kFeed);
  EXPECT_NEAR(k.classify(row(5, 10.0), 10.0).planned_speed, 10.0, 1e-12);
  EXPECT_EQ(k.classify(row(6, 9.9), 9.0).cause, TimeCause::kFeed) << "within 2 % of the limit: cruising";
  EXPECT_EQ(k.classify(row(5, 5.0), 4.0).cause, TimeCause::kJunctionStop) << "speeding up from the stop before";
  EXPECT_EQ(k.classify(row(6, 5.0), 6.0).cause, TimeCause::kJunctionCorner) << "slowing for the corner after";
  EXPECT_EQ(k.classify(row(7, 5.0), 6.0).cause, TimeCause::kAccelY) << "slowing with a straight junction ahead";
  EXPECT_EQ(k.classify(row(7, 5.0), 5.0).cause, TimeCause::kOverride) << "steady below the limit";
  EXPECT_EQ(k.classify(row(7, 12.0), 12.0).cause, TimeCause::kOverride) << "above the limit";
  EXPECT_EQ(k.classify(row(8, 0.0), 0.0).cause, TimeCause::kDwell);
  EXPECT_EQ(k.classify(row(5, 0.0, MachineState::kPaused), 0.0).cause, TimeCause::kPaused);
  EXPECT_EQ(k.classify(row(99, 3.0), 2.0).cause, TimeCause::kOther) << "a line with no plan";
}

TEST(TimeCauseSeconds, AddUpToTheProgramTime) {
  std::array<std::uint64_t, kTimeCauseCount> rows{};
  rows[static_cast<std::size_t>(TimeCause::kFeed)] = 7001;
  rows[static_cast<std::size_t>(TimeCause::kJunctionStop)] = 333;
  rows[static_cast<std::size_t>(TimeCause::kRapid)] = 17;
  const double program_time = 3.6755;
  const auto m = time_by_cause(rows, program_time);
  ASSERT_EQ(m.size(), 3u) << "causes with no row are left out";
  double sum = 0.0;
  for (const auto& [k, v] : m) sum += v;
  EXPECT_NEAR(sum, program_time, 1e-12);
  EXPECT_NEAR(m.at("junction_stop"), program_time * 333.0 / 7351.0, 1e-12);
  EXPECT_TRUE(time_by_cause({}, 1.0).empty());
}

TEST(TimeCauseSeconds, DigestCountsEveryProgramRowOnce) {
  LinePlan p;
  p.first = 1;
  p.last = 1;
  p.speed = 10.0;
  const CauseClassifier k({p});
  DigestOptions o;
  o.max_buckets = 8;
  o.cause_of = [&k](const TraceSample& r, double prev) { return k.classify(r, prev); };
  TraceDigester dig(o);
  for (int i = 0; i < 1000; ++i) {
    TraceSample r = row(1, std::min(10.0, i * 0.1));
    r.t = i * 0.0005;
    dig.add(r);
  }
  const TraceDigest d = dig.finish();
  ASSERT_TRUE(d.classified);
  EXPECT_EQ(std::accumulate(d.cause_rows.begin(), d.cause_rows.end(), std::uint64_t{0}), d.program_rows);
  std::uint64_t in_buckets = 0;
  for (const TraceBucket& b : d.buckets) {
    EXPECT_EQ(std::accumulate(b.cause_rows.begin(), b.cause_rows.end(), 0u), b.rows);
    in_buckets += b.rows;
  }
  EXPECT_EQ(in_buckets, d.program_rows);
  EXPECT_GT(d.cause_rows[static_cast<std::size_t>(TimeCause::kFeed)], 800u);
  EXPECT_GT(d.cause_rows[static_cast<std::size_t>(TimeCause::kStartEndStop)], 90u) << "speeding up from the start";
}

TEST(TimeCauseSummary, PlanAndTimesRoundTrip) {
  RunSummary s;
  s.program = "p.ngc";
  LinePlan p;
  p.first = 3;
  p.last = 9;
  p.cruise = TimeCause::kAxisVelocityZ;
  p.accel = TimeCause::kAccelZ;
  p.speed = 12.345678901;
  p.before = JunctionKind::kContouringOff;
  p.after = JunctionKind::kCorner;
  p.angle_before_deg = 90.0;
  p.angle_after_deg = 4.5;
  s.plan = {p};
  s.time_by_cause = {{"feed", 1.5}, {"junction_stop", 0.25}};
  const RunSummary b = run_summary_from_json(to_json(s));
  ASSERT_EQ(b.plan.size(), 1u);
  EXPECT_EQ(b.plan[0].first, 3u);
  EXPECT_EQ(b.plan[0].last, 9u);
  EXPECT_EQ(b.plan[0].cruise, TimeCause::kAxisVelocityZ);
  EXPECT_EQ(b.plan[0].accel, TimeCause::kAccelZ);
  EXPECT_NEAR(b.plan[0].speed, p.speed, 1e-8);
  EXPECT_EQ(b.plan[0].before, JunctionKind::kContouringOff);
  EXPECT_EQ(b.plan[0].after, JunctionKind::kCorner);
  EXPECT_NEAR(b.plan[0].angle_after_deg, 4.5, 1e-9);
  EXPECT_EQ(b.time_by_cause, s.time_by_cause);
  for (int c = 0; c < kTimeCauseCount; ++c) {
    TimeCause back{};
    ASSERT_TRUE(parse_time_cause(time_cause_key(static_cast<TimeCause>(c)), back));
    EXPECT_EQ(static_cast<int>(back), c);
  }
}

// The summary's plan entry (one plan's text is its entries separated by ';') is the text
// "first,last,cruise,accel,speed,before,after,angle_before,angle_after" with printf's %.9g for the speed and %.4g for the angles (the file format; the
// writer uses std::to_chars): the same text for ordinary, tiny, huge and negative values.
TEST(TimeCauseSummary, PlanEntryTextIsPrintfsFormat) {
  const double values[] = {0.0, 12.345678901, 13.3333333333, 1e-7, 123456789012.0, 90.0, 4.5, -0.00012345, 179.99999,
                           5e-324, 1.0 / 3.0, 250.0};
  for (const double v : values) {
    RunSummary s;
    LinePlan p;
    p.first = 4294967295u;
    p.last = 12;
    p.cruise = TimeCause::kFeed;
    p.accel = TimeCause::kAccelY;
    p.speed = v;
    p.before = JunctionKind::kCorner;
    p.after = JunctionKind::kStartEnd;
    p.angle_before_deg = v;
    p.angle_after_deg = -v;
    s.plan = {p};
    char want[256];
    std::snprintf(want, sizeof want, "%u,%u,%s,%s,%.9g,%d,%d,%.4g,%.4g", p.first, p.last, time_cause_key(p.cruise),
                  time_cause_key(p.accel), p.speed, static_cast<int>(p.before), static_cast<int>(p.after),
                  p.angle_before_deg, p.angle_after_deg);
    EXPECT_EQ(to_json(s).at("check").at("plan").get<std::string>(), std::string(want)) << v;
    const double back = run_summary_from_json(to_json(s)).plan.at(0).speed;
    EXPECT_NEAR(back, v, std::abs(v) * 1e-8) << "the speed read back, to its nine digits";
  }
}

// A bin's upper edge may lie above the largest value in it: the quantile must not.
TEST(LatencyQuantiles, NeverAboveTheMaxNorBelowTheMin) {
  LatencyHistogram h;
  h.add(0.3);
  EXPECT_LE(h.quantile(0.99), h.max());
  EXPECT_GE(h.quantile(0.5), h.min());
  for (double v : {1.1, 2.7, 2.8, 15.01, 0.4, 900.3}) h.add(v);
  const double p50 = h.quantile(0.5), p99 = h.quantile(0.99);
  EXPECT_LE(h.min(), p50);
  EXPECT_LE(p50, p99);
  EXPECT_LE(p99, h.max());
  EXPECT_EQ(h.quantile(1.0), h.max());
}

// The rt under the virtual clock times runs of cycles and adds each run's mean once per cycle
// (add(us, n)): the same histogram as n single adds.
TEST(LatencyQuantiles, NSamplesAtOnceAreNSingleSamples) {
  LatencyHistogram once, each;
  const std::pair<double, std::uint32_t> runs[] = {{0.62, 8}, {0.31, 3}, {12.5, 1}, {0.0, 5}, {2.75, 8}, {9.0, 0}};
  for (const auto& [us, n] : runs) {
    once.add(us, n);
    for (std::uint32_t i = 0; i < n; ++i) each.add(us);
  }
  EXPECT_EQ(once.count(), 25u);
  EXPECT_EQ(once.count(), each.count());
  EXPECT_EQ(once.min(), 0.0);
  EXPECT_EQ(once.max(), 12.5) << "a run of no cycles adds nothing";
  EXPECT_NEAR(once.mean(), each.mean(), 1e-12);
  for (double q : {0.1, 0.5, 0.9, 0.99}) EXPECT_EQ(once.quantile(q), each.quantile(q)) << q;
}

}  // namespace
}  // namespace pcnc::test
