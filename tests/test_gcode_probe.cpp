// test_gcode_probe.cpp — G38.2-G38.5 in the front end (host/gcode/interpreter_probe.cpp): the
// words checked as LinuxCNC checks them (errors with file:line:col), the probing block, the
// feed capped to the probe's overtravel, #5061-#5070 from a known result or, in a check, from
// the assumed contact at the commanded end, the sync point of a run's stream, the probe log.
#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "gcode_listing.hpp"
#include "gcode_test_util.hpp"
#include "geometry/probe_contact.hpp"

namespace pcnc::test {
namespace {

std::string first_error(const RunResult& r) {
  const Diagnostic* d = r.first_error();
  return d ? format_diagnostic(*d) : "";
}

std::vector<Block> probing(const RunResult& r) {
  std::vector<Block> p;
  for (const Block& b : r.blocks) {
    if (b.probe_rule != 0) p.push_back(b);
  }
  return p;
}

JobOptions with_results(std::vector<ProbeResult> known, bool stop = false) {
  JobOptions o;
  auto r = std::make_shared<ProbeResults>();
  r->known = std::move(known);
  r->stop_at_unknown = stop;
  o.probe = r;
  return o;
}

TEST(GcodeProbe, ACheckAssumesContactAtTheCommandedEnd) {
  // #5063 (Z of the probed point) and #5070 (success) read back by later lines
  const RunResult r = run_program("G21 G90 F60\nG38.2 Z-5\nG0 X#5063 Y#5070\nM2\n", wide_config());
  ASSERT_TRUE(r.check.ok) << first_error(r);
  ASSERT_EQ(r.check.assumed_probe_lines, std::vector<int>{2});
  const auto p = probing(r);
  ASSERT_EQ(p.size(), 1u);
  EXPECT_EQ(p[0].probe_rule, kProbeTowardError);
  EXPECT_EQ(p[0].kind, BlockKind::kLine);
  EXPECT_DOUBLE_EQ(p[0].end[2], -5.0);
  EXPECT_DOUBLE_EQ(p[0].speed, 1.0);  // F60 mm/min
  const auto m = r.motion();
  ASSERT_EQ(m.size(), 2u);
  EXPECT_DOUBLE_EQ(m[1].end[0], -5.0);
  EXPECT_DOUBLE_EQ(m[1].end[1], 1.0);
  EXPECT_NE(format_block(p[0]).find("probe=G38.2"), std::string::npos) << format_block(p[0]);
}

TEST(GcodeProbe, AKnownResultSetsTheParametersAndWhereTheNextMoveStarts) {
  ProbeResult hit;
  hit.outcome = ProbeOutcome::kContact;
  hit.latched = {0.0, 0.0, -3.2};
  hit.stop = {0.0, 0.0, -3.5};
  const std::string text =
      "G21 G90 F60\nG10 L2 P1 X1 Y2 Z3\nG54\nG38.3 Z-8\nG0 X#5063 Y#5061\n"
      "o100 if [#5070 EQ 1]\nG0 Z10\no100 else\nG0 Z20\no100 endif\nM2\n";
  const RunResult r = run_program(text, wide_config(), with_results({hit}));
  ASSERT_TRUE(r.check.ok) << first_error(r);
  EXPECT_TRUE(r.check.assumed_probe_lines.empty());
  const auto m = r.motion();
  ASSERT_EQ(m.size(), 3u);
  EXPECT_DOUBLE_EQ(m[0].end[2], -5.0) << "G38.3 Z-8 in G54 (Z offset 3)";
  // the next move starts where the probe stopped; #5063 is the latched Z in G54: -3.2 - 3
  EXPECT_DOUBLE_EQ(m[1].start[2], -3.5);
  EXPECT_NEAR(m[1].end[0], -6.2 + 1.0, 1e-12);
  EXPECT_NEAR(m[1].end[1], -1.0 + 2.0, 1e-12) << "#5061 = 0 - 1 in G54, back to machine +2 on Y";
  EXPECT_DOUBLE_EQ(m[2].end[2], 13.0) << "#5070 = 1: the if branch";

  ProbeResult miss;
  miss.outcome = ProbeOutcome::kNoContact;
  miss.latched = miss.stop = {0.0, 0.0, -5.0};
  const RunResult n = run_program(text, wide_config(), with_results({miss}));
  ASSERT_TRUE(n.check.ok) << first_error(n);
  EXPECT_DOUBLE_EQ(n.motion()[2].end[2], 23.0) << "#5070 = 0 after G38.3 without contact";
  EXPECT_NEAR(n.motion()[1].end[0], -8.0 + 1.0, 1e-12) << "#5063: the programmed point";
}

TEST(GcodeProbe, ProbeResultsAreInTheProgramsUnits) {
  ProbeResult hit;
  hit.latched = {0.0, 0.0, -12.7};
  hit.stop = {0.0, 0.0, -13.0};
  const RunResult r = run_program("G20 G90 F2\nG38.2 Z-1\n#1=#5063\nG21\nG0 X[#1*25.4]\nM2\n", wide_config(), with_results({hit}));
  ASSERT_TRUE(r.check.ok) << first_error(r);
  EXPECT_NEAR(r.motion()[1].end[0], -12.7, 1e-9) << "#5063 = -0.5 inch";
}

TEST(GcodeProbe, WordsAreCheckedAsLinuxCncChecksThem) {
  const MachineConfig c = wide_config();
  auto error_of = [&](const std::string& text, JobOptions o = {}) { return first_error(run_program(text, c, o)); };
  EXPECT_EQ(error_of("F60\nG38.2\nM2\n"),
            "test.ngc:2:1: error: G38.2 without axis words; expected X, Y or Z: the point to probe toward");
  EXPECT_NE(error_of("G38.2 Z-1\nM2\n").find("test.ngc:1:1: error: feed move with no feed rate"), std::string::npos);
  EXPECT_EQ(error_of("F60\nG38.4 X0\nM2\n"),
            "test.ngc:2:7: error: G38.4 to the point the probe stands on; expected a point to move toward");
  EXPECT_EQ(error_of("F60\nG38.3 X0\nM2\n"), "") << "G38.3/G38.5 may probe the point they stand on";
  EXPECT_NE(error_of("F60 G41.1 D1\nG1 X5\nG38.2 Z-1\nM2\n")
                .find("test.ngc:3:1: error: cannot probe (G38.2) with cutter radius compensation on"),
            std::string::npos);
  EXPECT_EQ(error_of("F60\nG38.2 Z-1 A1\nM2\n"), "test.ngc:2:11: error: the machine has no A axis; expected X, Y or Z");
  MachineConfig none = c;
  none.probe.present = false;
  EXPECT_EQ(first_error(run_program("F60\nG38.2 Z-1\nM2\n", none)),
            "test.ngc:2:1: error: G38.2: the machine has no probe; expected a [probe] section in the machine config");
  ProbeResult miss;
  miss.outcome = ProbeOutcome::kNoContact;
  miss.latched = miss.stop = {0.0, 0.0, -1.0};
  EXPECT_EQ(error_of("F60\nG38.2 Z-1\nM2\n", with_results({miss})),
            "test.ngc:2:1: error: G38.2 reached its end without the probe triggering; expected a point beyond the "
            "surface (or G38.3/G38.5, which do not fail)");
  ProbeResult touching;
  touching.outcome = ProbeOutcome::kAlreadyTriggered;
  EXPECT_EQ(error_of("F60\nG38.3 Z-1\nM2\n", with_results({touching})),
            "test.ngc:2:1: error: the probe was already triggered at the start of G38.3; expected it clear of the workpiece");
}

TEST(GcodeProbe, TheProbingFeedIsCappedToStopWithinTheOvertravel) {
  MachineConfig c = wide_config();
  c.probe.model.overtravel_mm = 0.05;
  const RunResult r = run_program("F6000\nG38.2 Z-20\nM2\n", c);
  ASSERT_TRUE(r.check.ok) << first_error(r);
  const Block b = probing(r).at(0);
  const double v_max = probe_speed_limit(b.accel, c.cycle_period_s(), 0.05);
  EXPECT_LT(v_max, 100.0);
  EXPECT_NEAR(b.speed, v_max, 1e-9);
  EXPECT_LE(b.speed * b.speed / (2 * b.accel) + 2 * b.speed * c.cycle_period_s(), 0.05 + 1e-12);
}

TEST(GcodeProbe, ARunsStreamStopsAtAProbeWithoutAResult) {
  const std::string text = "(PROBEOPEN points.txt)\nF60\nG0 X1\nG38.2 Z-5\nG0 X#5063\nM2\n";
  const MachineConfig c = wide_config();
  JobOptions o = with_results({}, true);
  o.start_position = Vec3{0.0, 0.0, 0.0};
  const CheckResult check = check_program_text(text, "test.ngc", c, JobOptions{});
  ASSERT_TRUE(check.ok);
  BlockStream s(BlockStream::FromText{}, text, "test.ngc", c, o, check.transform);
  std::vector<Block> blocks;
  Block b;
  while (s.next(b)) blocks.push_back(b);
  ASSERT_EQ(blocks.size(), 2u) << "the rapid and the probing move, no End";
  EXPECT_EQ(blocks[1].probe_rule, kProbeTowardError);
  EXPECT_TRUE(s.probe_sync());
  EXPECT_EQ(s.probe_log(), "points.txt");
  EXPECT_DOUBLE_EQ(s.to_program({1.0, 2.0, -3.0})[2], -3.0);

  // with the result the same program streams the same blocks up to the probe, then the rest
  ProbeResult hit;
  hit.latched = {1.0, 0.0, -2.0};
  hit.stop = {1.0, 0.0, -2.25};
  JobOptions o2 = with_results({hit}, true);
  o2.start_position = Vec3{0.0, 0.0, 0.0};
  BlockStream s2(BlockStream::FromText{}, text, "test.ngc", c, o2, check.transform);
  std::vector<Block> all;
  while (s2.next(b)) all.push_back(b);
  EXPECT_FALSE(s2.probe_sync());
  ASSERT_EQ(all.size(), 4u);
  EXPECT_EQ(format_block(all[0]), format_block(blocks[0]));
  EXPECT_EQ(format_block(all[1]), format_block(blocks[1]));
  EXPECT_DOUBLE_EQ(all[2].start[2], -2.25);
  EXPECT_DOUBLE_EQ(all[2].end[0], -2.0);
  EXPECT_EQ(all[3].kind, BlockKind::kEnd);
}


// A streamed program (the grbl port) cannot wait for a probe's result before the lines after it
// are answered: a probing move there is an error at its line, not a move whose end is guessed.
TEST(GcodeProbe, AStreamedProgramRefusesAProbingMove) {
  const std::string text = "F60\nG0 X1\nG38.2 Z-5\nG0 X#5063\nM2\n";
  const MachineConfig c = wide_config();
  JobOptions o;
  auto refuse = std::make_shared<ProbeResults>();
  refuse->refuse_unknown = true;
  o.probe = refuse;
  o.start_position = Vec3{0.0, 0.0, 0.0};
  const CheckResult check = check_program_text(text, "stream", c, o);
  ASSERT_FALSE(check.ok);
  const Diagnostic* d = nullptr;
  for (const Diagnostic& x : check.diagnostics) {
    if (x.severity == Diagnostic::Severity::kError && !d) d = &x;
  }
  ASSERT_NE(d, nullptr);
  EXPECT_EQ(d->line, 3);
  EXPECT_NE(d->message.find("streamed program"), std::string::npos) << d->message;
  // the same program checked as a file assumes contact and passes
  EXPECT_TRUE(check_program_text(text, "test.ngc", c, JobOptions{}).ok);
}

}  // namespace
}  // namespace pcnc::test
