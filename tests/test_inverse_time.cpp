// test_inverse_time.cpp — G93 inverse time feed in the front end (LinuxCNC's semantics): the
// feed each move gets (its length over 1/F minutes, capped by the machine), the errors, the
// switch back to G94 (which sets the feed to 0), and the tool's moves under cutter compensation,
// each taking the programmed move's time. Every expected speed is worked out by hand below.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "gcode_test_util.hpp"
#include "test_constants.hpp"

namespace pcnc {
namespace {

using test::run_program;
using test::wide_config;


// The time a block takes at its planned speed (its programmed time when no cap applies).
double block_time(const Block& b) { return b.length / b.speed; }

TEST(InverseTime, LineTakesOneOverFMinutes) {
  // 3-4-5: 50 mm in 60/6 = 10 s -> 5 mm/s
  const auto r = run_program("G0 X-30 Y-40\nG93 G1 X0 Y0 F6\nM2\n", wide_config());
  ASSERT_TRUE(r.check.ok);
  const auto m = r.motion();
  ASSERT_EQ(m.size(), 2u);
  EXPECT_NEAR(m[1].length, 50.0, 1e-12);
  EXPECT_NEAR(m[1].speed, 5.0, 1e-12);
  EXPECT_NEAR(block_time(m[1]), 10.0, 1e-9);
}

TEST(InverseTime, ArcAndHelixTakeOneOverFMinutes) {
  // quarter circle of radius 10: 5*pi mm in 1 s (F60)
  auto r = run_program("G0 X10 Y0\nG93 G3 X0 Y10 I-10 F60\nM2\n", wide_config());
  ASSERT_TRUE(r.check.ok);
  EXPECT_NEAR(r.motion().at(1).speed, 5.0 * kPi, 1e-9);
  // full turn of radius 5 dropping 3 mm: hypot(10*pi, 3) mm in 60/20 = 3 s
  r = run_program("G0 X5 Y0 Z0\nG93 G2 X5 Y0 Z-3 I-5 F20\nM2\n", wide_config());
  ASSERT_TRUE(r.check.ok);
  const Block a = r.motion().at(1);
  EXPECT_NEAR(a.speed, std::hypot(10.0 * kPi, 3.0) / 3.0, 1e-9);
  EXPECT_NEAR(block_time(a), 3.0, 1e-9);
}

TEST(InverseTime, EachLineHasItsOwnTimeAndInchesConvertTheLength) {
  // G20: X1 is 25.4 mm; F60 -> 1 s; the next line 2 in in 60/30 = 2 s -> 25.4 mm/s again
  const auto r = run_program("G20 G0 X-1\nG93 G1 X0 F60\nX2 F30\nY1 F120\nM2\n", wide_config());
  ASSERT_TRUE(r.check.ok);
  const auto m = r.motion();
  ASSERT_EQ(m.size(), 4u);
  EXPECT_NEAR(m[1].speed, 25.4, 1e-9);
  EXPECT_NEAR(m[2].speed, 25.4, 1e-9);
  EXPECT_NEAR(m[3].speed, 25.4 * 2.0, 1e-9);  // 1 in in 0.5 s
}

TEST(InverseTime, RapidsAreUnaffectedAndAnFWithoutAMoveIsIgnored) {
  // F on a line without G1/G2/G3 is ignored in G93 (LinuxCNC); G0 needs no F.
  const auto r = run_program("G93 F1\nG0 X10\nG1 X20 F60\nM2\n", wide_config());
  ASSERT_TRUE(r.check.ok);
  const auto m = r.motion();
  ASSERT_EQ(m.size(), 2u);
  EXPECT_EQ(m[0].kind, BlockKind::kRapid);
  EXPECT_NEAR(m[1].speed, 10.0, 1e-12);  // 10 mm in 1 s, not F1's 1 minute
}

TEST(InverseTime, FeedAboveTheMachineMaximumIsClampedWithAWarning) {
  // 100 mm in 60/600 = 0.1 s would be 1000 mm/s; the desktop mill's maximum is 100 mm/s.
  auto r = run_program("G0 X-50\nG93 G1 X50 F600\nM2\n", wide_config());
  ASSERT_TRUE(r.check.ok);
  EXPECT_TRUE(r.has_warning("G93 F600: 100 mm in 0.1 s needs 1000 mm/s"));
  EXPECT_NEAR(r.motion().at(1).speed, 100.0, 1e-12);
  MachineConfig strict = wide_config();
  strict.gcode.clamp_excess_feed = false;
  r = run_program("G0 X-50\nG93 G1 X50 F600\nM2\n", strict);
  EXPECT_FALSE(r.check.ok);
  EXPECT_TRUE(r.has_error("expected F <= 60 for this move"));
}

TEST(InverseTime, G94SetsTheFeedToZeroAsLinuxCnc) {
  // back in G94 a G1 needs a new F; an F on the G94 line itself is read after the mode
  auto r = run_program("G1 X1 F600\nG94\nG1 X2\nM2\n", wide_config());
  EXPECT_FALSE(r.check.ok);
  const Diagnostic* d = r.first_error();
  ASSERT_NE(d, nullptr);
  EXPECT_EQ(d->line, 3);
  EXPECT_NE(d->message.find("G94 on line 2 set it to 0"), std::string::npos) << d->message;
  r = run_program("G93 G1 X1 F60\nG94 F600\nG1 X2\nM2\n", wide_config());
  ASSERT_TRUE(r.check.ok);
  EXPECT_NEAR(r.motion().at(1).speed, 10.0, 1e-12);
  // G93 F on the same line: the mode first, then F (the move takes 1/F minutes)
  r = run_program("G1 X1 F600\nG93 G1 X4 F20\nM2\n", wide_config());
  ASSERT_TRUE(r.check.ok);
  EXPECT_NEAR(r.motion().at(1).speed, 1.0, 1e-12);  // 3 mm in 3 s
}

TEST(InverseTime, ParametersReportTheMode) {
  const auto r = run_program("G0 X[#<_inverse_time>] Y[#<_units_per_minute>]\nG93\nG0 X[#<_inverse_time>+1] "
                             "Y[#<_units_per_minute>+1]\nM2\n",
                             wide_config());
  ASSERT_TRUE(r.check.ok);
  const auto m = r.motion();
  ASSERT_EQ(m.size(), 2u);
  EXPECT_NEAR(m[0].end[0], 0.0, 1e-12);
  EXPECT_NEAR(m[0].end[1], 1.0, 1e-12);
  EXPECT_NEAR(m[1].end[0], 2.0, 1e-12);
  EXPECT_NEAR(m[1].end[1], 1.0, 1e-12);
}

struct G93Error {
  const char* program;
  const char* error;
  int line;
  const char* at;  // the text the column points at, on that line
};

class InverseTimeErrors : public ::testing::TestWithParam<G93Error> {};

TEST_P(InverseTimeErrors, NamedWithLineAndColumn) {
  const G93Error& c = GetParam();
  const std::string text = std::string(c.program) + "\nM2\n";
  const auto r = run_program(text, wide_config());
  EXPECT_FALSE(r.check.ok);
  const Diagnostic* d = r.first_error();
  ASSERT_NE(d, nullptr) << c.program;
  EXPECT_NE(d->message.find(c.error), std::string::npos) << d->message;
  EXPECT_NE(d->message.find("expected"), std::string::npos) << d->message;
  EXPECT_EQ(d->line, c.line);
  std::istringstream in(text);
  std::string line;
  for (int i = 0; i < c.line; ++i) std::getline(in, line);
  EXPECT_EQ(d->column, static_cast<int>(line.find(c.at)) + 1) << d->message;
  EXPECT_TRUE(r.blocks.empty());
}

INSTANTIATE_TEST_SUITE_P(
    Table, InverseTimeErrors,
    ::testing::Values(G93Error{"G93 G1 X1", "F word missing with inverse time G1 move", 1, "G1"},
                      G93Error{"G93 G1 X1 F10\nX2", "F word missing with inverse time G1 move", 2, "X2"},
                      G93Error{"G93 G2 X2 I1", "F word missing with inverse time arc move", 1, "G2"},
                      G93Error{"G93 G1 X1 F0", "F0 in inverse time feed mode", 1, "F0"},
                      G93Error{"G93 G81 X0 Y0 Z-1 R1", "cannot use inverse time feed with canned cycles", 1, "G81"},
                      G93Error{"G93 G5.2 X0 Y0 P1 L3 F1", "G5.2 NURBS curve in inverse time", 1, "G5.2"},
                      G93Error{"G95", "feed per revolution", 1, "G95"}));

// G42.1 with a 4 mm tool: the entry line, each offset line and the corner arcs. LinuxCNC's rule
// (its test inverse-time-with-comp: "the feeds should be the same whether or not compensation is
// on"): each tool move takes 1/F minutes of its line; a corner arc runs at the feed of the
// programmed move it leads into.
TEST(InverseTime, CutterCompensationKeepsEachMovesTime) {
  MachineConfig c = wide_config();
  c.motion.path_tolerance_mm = 0.0;  // one block per move
  const auto r =
      run_program("G0 X0 Y0 Z1\nG42.1 D4\nG93 G1 X10 F30\nY10 F20\nX0 F40\nG40 G94 G1 Y20 F600\nM2\n", c);
  ASSERT_TRUE(r.check.ok);
  const auto m = r.motion();
  // rapid, entry line (0,0)-(10,-2), arc about (10,0), line x=12, arc about (10,10), line y=12,
  // the line after G40
  ASSERT_EQ(m.size(), 7u);
  EXPECT_EQ(m[1].kind, BlockKind::kLine);
  EXPECT_NEAR(m[1].end[1], -2.0, 1e-9);
  EXPECT_NEAR(m[1].speed, std::sqrt(104.0) / 2.0, 1e-9);  // its own length in 60/30 s
  EXPECT_NEAR(block_time(m[1]), 2.0, 1e-9);
  EXPECT_EQ(m[2].kind, BlockKind::kArc);
  EXPECT_NEAR(m[2].speed, 10.0 / 3.0, 1e-9);  // line 4's programmed 10 mm in 3 s
  EXPECT_EQ(m[3].kind, BlockKind::kLine);
  EXPECT_NEAR(block_time(m[3]), 3.0, 1e-9);
  EXPECT_EQ(m[4].kind, BlockKind::kArc);
  EXPECT_NEAR(m[4].speed, 10.0 / 1.5, 1e-9);
  EXPECT_EQ(m[5].kind, BlockKind::kLine);
  EXPECT_NEAR(block_time(m[5]), 1.5, 1e-9);
  EXPECT_NEAR(m[6].speed, 10.0, 1e-12);  // G94 F600
}

// The corpus: the opcode test written for G93 (a 141.5 mm move in 15 s) is accepted now, at 15 s
// also under --fit (a smaller move in the same time); its negative twin is refused for the
// missing F.
TEST(InverseTime, CorpusOpcodePrograms) {
  auto read = [](const std::string& name) {
    std::ifstream in(test::shared_dir() + "/gcode/opcodes/" + name);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
  };
  const std::string good = read("G93.nc");
  ASSERT_FALSE(good.empty());
  JobOptions o;
  o.fit = true;
  test::RunResult r;
  r.check = check_program_text(good, "G93.nc", test::mill_config(), o);
  ASSERT_TRUE(r.check.ok);
  BlockStream s(BlockStream::FromText{}, good, "G93.nc", test::mill_config(), o, r.check.transform);
  Block b;
  double feed_time = -1.0;
  while (s.next(b)) {
    if (b.kind == BlockKind::kLine) feed_time = block_time(b);
  }
  EXPECT_LT(r.check.transform.scale, 1.0);
  EXPECT_NEAR(feed_time, 15.0, 1e-9);
  const std::string bad = read("negative/G93_negative.nc");
  ASSERT_FALSE(bad.empty());
  const CheckResult rb = check_program_text(bad, "G93_negative.nc", test::mill_config(), o);
  EXPECT_FALSE(rb.ok);
  EXPECT_TRUE(test::has_diagnostic(rb.diagnostics, Diagnostic::Severity::kError,
                                   "F word missing with inverse time G1 move"));
}

}  // namespace
}  // namespace pcnc
