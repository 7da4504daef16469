// test_interpreter.cpp — the modal interpreter word by word: executed, warned, rejected; arcs,
// units, distance modes, work offsets, the G28 idiom, G53, feeds and program end.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "gcode_test_util.hpp"
#include "test_constants.hpp"

namespace pcnc {
namespace {

using test::run_program;
using test::wide_config;


void expect_position(const Vec3& p, double x, double y, double z, double tol = 1e-9) {
  EXPECT_NEAR(p[0], x, tol);
  EXPECT_NEAR(p[1], y, tol);
  EXPECT_NEAR(p[2], z, tol);
}

// ---- words that are executed ----

TEST(Interpreter, RapidAndFeedLinesInMillimetres) {
  const auto r = run_program("G21 G90\nG0 X1 Y2 Z3\nG1 X4 F600\nM2\n", wide_config());
  ASSERT_TRUE(r.check.ok);
  const auto m = r.motion();
  ASSERT_EQ(m.size(), 2u);
  EXPECT_EQ(m[0].kind, BlockKind::kRapid);
  expect_position(m[0].end, 1, 2, 3);
  EXPECT_EQ(m[1].kind, BlockKind::kLine);
  expect_position(m[1].start, 1, 2, 3);
  expect_position(m[1].end, 4, 2, 3);
  EXPECT_NEAR(m[1].speed, 10.0, 1e-12);  // F600 mm/min
  EXPECT_EQ(m[1].line, 3u);
  EXPECT_EQ(r.blocks.back().kind, BlockKind::kEnd);
}

TEST(Interpreter, InchUnitsConvertPositionsAndFeed) {
  const auto r = run_program("G20 G90\nG1 X1 Y-2 F10\nM30\n", wide_config());
  ASSERT_TRUE(r.check.ok);
  const auto m = r.motion();
  ASSERT_EQ(m.size(), 1u);
  expect_position(m[0].end, 25.4, -50.8, 0);
  EXPECT_NEAR(m[0].speed, 10 * 25.4 / 60.0, 1e-12);
}

TEST(Interpreter, IncrementalMoves) {
  const auto r = run_program("G91\nG0 X1\nX1 Y1\nG90 X0\nM2\n", wide_config());
  ASSERT_TRUE(r.check.ok);
  const auto m = r.motion();
  ASSERT_EQ(m.size(), 3u);
  expect_position(m[0].end, 1, 0, 0);
  expect_position(m[1].end, 2, 1, 0);
  expect_position(m[2].end, 0, 1, 0);
}

TEST(Interpreter, SpacesInsideWordsAndLowerCase) {
  const auto r = run_program("g 01 x 1 .5 f 6 0\nM 2\n", wide_config());
  ASSERT_TRUE(r.check.ok);
  const auto m = r.motion();
  ASSERT_EQ(m.size(), 1u);
  EXPECT_NEAR(m[0].end[0], 1.5, 1e-12);
  EXPECT_NEAR(m[0].speed, 1.0, 1e-12);
}

TEST(Interpreter, WorkOffsetsFromConfig) {
  MachineConfig c = wide_config();
  c.gcode.work_offsets[0] = {10, 20, 30};
  c.gcode.work_offsets[1] = {-5, 0, 1};
  const auto r = run_program("G54 G0 X1 Y1 Z1\nG55 X1 Y1 Z1\nM2\n", c);
  ASSERT_TRUE(r.check.ok);
  const auto m = r.motion();
  ASSERT_EQ(m.size(), 2u);
  expect_position(m[0].end, 11, 21, 31);
  expect_position(m[1].end, -4, 1, 2);
  expect_position(r.check.transform.offset, 10, 20, 30);
}

TEST(Interpreter, OffsetOptionReplacesG54) {
  MachineConfig c = wide_config();
  JobOptions o;
  o.offset = Vec3{1, 2, 3};
  const auto r = run_program("G0 X1 Y1 Z1\nM2\n", c, o);
  ASSERT_TRUE(r.check.ok);
  expect_position(r.motion().at(0).end, 2, 3, 4);
}

TEST(Interpreter, ArcCenterFormQuarterCircle) {
  const auto r = run_program("G17 G0 X10 Y0\nG3 X0 Y10 I-10 J0 F600\nM2\n", wide_config());
  ASSERT_TRUE(r.check.ok);
  const auto m = r.motion();
  ASSERT_EQ(m.size(), 2u);
  const Block& a = m[1];
  EXPECT_EQ(a.kind, BlockKind::kArc);
  expect_position(a.arc.center, 0, 0, 0);
  EXPECT_NEAR(a.arc.radius, 10, 1e-12);
  EXPECT_NEAR(a.arc.start_angle, 0, 1e-12);
  EXPECT_NEAR(a.arc.sweep, kPi / 2, 1e-12);
  EXPECT_NEAR(a.length, 10 * kPi / 2, 1e-9);
  EXPECT_EQ(a.arc.normal_axis, 2);
}

TEST(Interpreter, ArcClockwiseHasNegativeSweep) {
  const auto r = run_program("G0 X10 Y0\nG2 X0 Y-10 I-10 F600\nM2\n", wide_config());
  ASSERT_TRUE(r.check.ok);
  EXPECT_NEAR(r.motion().at(1).arc.sweep, -kPi / 2, 1e-12);
}

TEST(Interpreter, FullCircleWhenEndEqualsStart) {
  const auto r = run_program("G0 X10 Y0\nG2 X10 Y0 I-10 F600\nG3 I-10\nM2\n", wide_config());
  ASSERT_TRUE(r.check.ok);
  const auto m = r.motion();
  ASSERT_EQ(m.size(), 3u);
  EXPECT_NEAR(m[1].arc.sweep, -2 * kPi, 1e-12);
  EXPECT_NEAR(m[2].arc.sweep, 2 * kPi, 1e-12);
}

TEST(Interpreter, HelixCarriesTheThirdAxis) {
  const auto r = run_program("G0 X10 Y0 Z0\nG3 X10 Y0 Z-2 I-10 F600\nM2\n", wide_config());
  ASSERT_TRUE(r.check.ok);
  const Block a = r.motion().at(1);
  EXPECT_NEAR(a.arc.helix, -2, 1e-12);
  EXPECT_EQ(a.motion_class, MotionClass::kSpace);
  EXPECT_NEAR(a.length, std::hypot(20 * kPi, 2.0), 1e-9);
}

// P on G2/G3 (LinuxCNC): P - 1 full circles, then the programmed arc; a helix's travel is shared
// in proportion to the angle, and each piece's center lies on its own start level.
TEST(Interpreter, ArcTurnsAddFullCirclesBeforeTheArc) {
  const auto r = run_program("G0 X10 Y0 Z0\nG3 X0 Y10 Z-3 I-10 P3 F600\nG1 X1\nM2\n", wide_config());
  ASSERT_TRUE(r.check.ok);
  const auto m = r.motion();
  ASSERT_EQ(m.size(), 5u);
  const double total = 2 * 2 * kPi + kPi / 2;  // two full turns and the quarter
  double z = 0.0;
  for (int k = 1; k <= 3; ++k) {
    const Block& a = m[static_cast<std::size_t>(k)];
    ASSERT_EQ(a.kind, BlockKind::kArc) << k;
    EXPECT_EQ(a.line, 2u);
    const double sweep = k < 3 ? 2 * kPi : kPi / 2;
    EXPECT_NEAR(a.arc.sweep, sweep, 1e-12) << k;
    EXPECT_NEAR(a.arc.radius, 10, 1e-12);
    expect_position(a.arc.center, 0, 0, z, 1e-12);
    expect_position(a.start, 10, 0, z, 1e-12);
    const double z_end = z - 3.0 * sweep / total;
    EXPECT_NEAR(a.arc.helix, z_end - z, 1e-12) << k;
    if (k < 3) expect_position(a.end, 10, 0, z_end, 1e-12);
    z = z_end;
  }
  expect_position(m[3].end, 0, 10, -3, 1e-12);
  expect_position(m[4].start, 0, 10, -3, 1e-12);

  // R form and clockwise: a half circle with P2 is one and a half turns
  const auto h = run_program("G0 X0 Y1\nG2 X10 Y1 R5 P2 F600\nM2\n", wide_config());
  ASSERT_TRUE(h.check.ok);
  ASSERT_EQ(h.motion().size(), 3u);
  EXPECT_NEAR(h.motion()[1].arc.sweep, -2 * kPi, 1e-12);
  EXPECT_NEAR(h.motion()[2].arc.sweep, -kPi, 1e-12);
  expect_position(h.motion()[1].arc.center, 5, 1, 0, 1e-9);
  // P1 is the arc alone
  EXPECT_EQ(run_program("G0 X10 Y0\nG3 X0 Y10 I-10 P1 F600\nM2\n", wide_config()).motion().size(), 2u);
}

// G93 with turns: F is the time of the whole line, shared by the pieces in proportion to length.
TEST(Interpreter, ArcTurnsUnderInverseTimeTakeTheLinesTime) {
  const auto r = run_program("G0 X10 Y0 Z0\nG93 G2 X10 Y0 Z-1 I-10 P2 F6\nG94\nM2\n", wide_config());
  ASSERT_TRUE(r.check.ok);
  const auto m = r.motion();
  ASSERT_EQ(m.size(), 3u);
  double t = 0.0;
  for (std::size_t k = 1; k < 3; ++k) t += m[k].length / m[k].speed;
  EXPECT_NEAR(t, 10.0, 1e-9) << "F6 in G93: the line takes 10 s";
  EXPECT_NEAR(m[1].speed, m[2].speed, 1e-12);
}

TEST(Interpreter, ArcTurnsMustBeAPositiveInteger) {
  for (const char* p : {"P0", "P1.5", "P-2"}) {
    const auto r = run_program(std::string("G0 X10 Y0\nG3 X0 Y10 I-10 ") + p + " F600\nM2\n", wide_config());
    EXPECT_FALSE(r.check.ok) << p;
    ASSERT_TRUE(r.has_error("is not a number of turns; expected a positive integer")) << p;
    const auto d = std::find_if(r.check.diagnostics.begin(), r.check.diagnostics.end(),
                                [](const Diagnostic& x) { return x.severity == Diagnostic::Severity::kError; });
    EXPECT_EQ(d->line, 2);
    EXPECT_EQ(d->column, 16) << p;
  }
  EXPECT_TRUE(run_program("G0 X10 Y0\nG3 X0 Y10 I-10 P100001 F600\nM2\n", wide_config()).has_error("more than 10000 turns"));
  EXPECT_TRUE(run_program("G0 X10 Y0\nG1 X0 P2 F600\nM2\n", wide_config()).has_error("P word with no G code that uses it"));
}

TEST(Interpreter, RFormPicksTheShortOrLongArc) {
  // G2 from (0,0) to (10,0) with R5: half circle, center (5,0).
  auto r = run_program("G0 X0 Y0\nG2 X10 Y0 R5 F600\nM2\n", wide_config());
  ASSERT_TRUE(r.check.ok);
  expect_position(r.motion().at(0).arc.center, 5, 0, 0, 1e-9);
  // G3 R10 from (0,0) to (10,0): minor arc, center left of the chord (+Y side for travel +X).
  r = run_program("G0 X0 Y0\nG3 X10 Y0 R10 F600\nM2\n", wide_config());
  ASSERT_TRUE(r.check.ok);
  const Block minor = r.motion().at(0);
  EXPECT_NEAR(minor.arc.center[0], 5, 1e-9);
  EXPECT_NEAR(minor.arc.center[1], std::sqrt(75.0), 1e-9);
  EXPECT_GT(minor.arc.sweep, 0);
  EXPECT_LT(minor.arc.sweep, kPi);
  // Negative R: the long way round.
  r = run_program("G0 X0 Y0\nG3 X10 Y0 R-10 F600\nM2\n", wide_config());
  ASSERT_TRUE(r.check.ok);
  EXPECT_GT(r.motion().at(0).arc.sweep, kPi);
  EXPECT_NEAR(r.motion().at(0).arc.center[1], -std::sqrt(75.0), 1e-9);
}

TEST(Interpreter, ArcPlanesG18AndG19) {
  // G18: angles from Z toward X, normal Y. Start (0,0,10) about center (0,0,0).
  auto r = run_program("G18 G0 X0 Y0 Z10\nG3 X10 Z0 K-10 F600\nM2\n", wide_config());
  ASSERT_TRUE(r.check.ok);
  const Block a = r.motion().at(1);
  EXPECT_EQ(a.arc.normal_axis, 1);
  EXPECT_NEAR(a.arc.start_angle, 0, 1e-12);  // on the +Z axis
  EXPECT_NEAR(a.arc.sweep, kPi / 2, 1e-12);  // Z -> X is counter-clockwise in G18
  r = run_program("G19 G0 X0 Y10 Z0\nG3 Y0 Z10 J-10 F600\nM2\n", wide_config());
  ASSERT_TRUE(r.check.ok);
  EXPECT_EQ(r.motion().at(1).arc.normal_axis, 0);
  EXPECT_NEAR(r.motion().at(1).arc.sweep, kPi / 2, 1e-12);
}

TEST(Interpreter, DwellInSeconds) {
  const auto r = run_program("G4 P1.5\nM2\n", wide_config());
  ASSERT_TRUE(r.check.ok);
  ASSERT_EQ(r.blocks.size(), 2u);
  EXPECT_EQ(r.blocks[0].kind, BlockKind::kDwell);
  EXPECT_DOUBLE_EQ(r.blocks[0].dwell_s, 1.5);
}

TEST(Interpreter, PauseAndOptionalStop) {
  const auto r = run_program("M0\nM1\nM2\n", wide_config());
  ASSERT_TRUE(r.check.ok);
  ASSERT_EQ(r.blocks.size(), 3u);
  EXPECT_EQ(r.blocks[0].kind, BlockKind::kPause);
  EXPECT_EQ(r.blocks[0].optional_stop, 0);
  EXPECT_EQ(r.blocks[1].optional_stop, 1);
}

TEST(Interpreter, ContouringModalState) {
  JobOptions o;
  o.contouring = false;
  MachineConfig c = wide_config();
  c.motion.path_tolerance_mm = 0.0;  // no smoothing: one block per move
  const auto r = run_program("G1 X1 F60\nM21 X2\nX3\nM22 X4\nG64 X5\nG61 X6\nM2\n", c, o);
  ASSERT_TRUE(r.check.ok);
  const auto m = r.motion();
  ASSERT_EQ(m.size(), 6u);
  const int expected[] = {0, 1, 1, 0, 1, 0};
  for (int i = 0; i < 6; ++i) EXPECT_EQ(m[static_cast<std::size_t>(i)].contouring, expected[i]) << i;
  EXPECT_TRUE(r.has_warning("G64 maps to M21"));
  EXPECT_TRUE(r.has_warning("G61 maps to M22"));
}

TEST(Interpreter, EndOfFileWithoutM2EndsWithWarning) {
  const auto r = run_program("G0 X1\n", wide_config());
  ASSERT_TRUE(r.check.ok);
  EXPECT_TRUE(r.has_warning("no M2/M30"));
  ASSERT_FALSE(r.blocks.empty());
  EXPECT_EQ(r.blocks.back().kind, BlockKind::kEnd);
}

TEST(Interpreter, TextAfterM30IsNotExecuted) {
  const auto r = run_program("G0 X1\nM30\nG0 X5\n", wide_config());
  ASSERT_TRUE(r.check.ok);
  EXPECT_TRUE(r.has_warning("after the program end"));
  EXPECT_EQ(r.motion().size(), 1u);
}

TEST(Interpreter, PercentDelimitsTheProgram) {
  const auto r = run_program("%\nG0 X1\n%\nG0 X9\n", wide_config());
  ASSERT_TRUE(r.check.ok);
  EXPECT_EQ(r.motion().size(), 1u);
}

TEST(Interpreter, G28RetractIdiomGoesHome) {
  // G28 goes to the stored G28 position, by default the config's home_mm; with axis words
  // it passes the intermediate point first and moves only those axes.
  MachineConfig c = wide_config();
  c.axes[2].travel_max_mm = 30.0;
  c.axes[0].home_mm = 1.0;
  c.axes[1].home_mm = 2.0;
  c.axes[2].home_mm = 30.0;
  const auto r = run_program("G0 X5 Y5 Z1\nG28 G91 Z0\nG90\nG28 G91 X0 Y0\nG90 G28 X7\nM30\n", c);
  ASSERT_TRUE(r.check.ok) << (r.first_error() ? r.first_error()->message : "");
  const auto m = r.motion();
  ASSERT_EQ(m.size(), 5u);
  expect_position(m[1].end, 5, 5, 30);
  expect_position(m[2].end, 1, 2, 30);
  expect_position(m[3].end, 7, 2, 30);  // the intermediate point in G90
  expect_position(m[4].end, 1, 2, 30);
}

TEST(Interpreter, G53MovesInMachineCoordinates) {
  MachineConfig c = wide_config();
  c.gcode.work_offsets[0] = {10, 10, 10};
  const auto r = run_program("G0 X0 Y0 Z0\nG53 G0 Z-5\nM2\n", c);
  ASSERT_TRUE(r.check.ok);
  expect_position(r.motion().at(1).end, 10, 10, -5);
}

TEST(Interpreter, FeedAboveMaximumIsClampedWithWarning) {
  const auto r = run_program("G1 X10 F9991300\nM2\n", wide_config());
  ASSERT_TRUE(r.check.ok);
  EXPECT_TRUE(r.has_warning("clamped"));
  EXPECT_LE(r.motion().at(0).speed, 100.0 + 1e-9);
}

TEST(Interpreter, FeedAboveMaximumRejectedWhenConfigSaysSo) {
  MachineConfig c = wide_config();
  c.gcode.clamp_excess_feed = false;
  const auto r = run_program("G1 X10 F9991300\nM2\n", c);
  EXPECT_FALSE(r.check.ok);
  EXPECT_TRUE(r.has_error("exceeds the machine maximum"));
}

// ---- words accepted with a warning ----

struct WarnCase {
  const char* program;
  const char* warning;
};

class WarnedWords : public ::testing::TestWithParam<WarnCase> {};

TEST_P(WarnedWords, AcceptedWithWarning) {
  const auto r = run_program(std::string(GetParam().program) + "\nM2\n", wide_config());
  EXPECT_TRUE(r.check.ok) << GetParam().program;
  EXPECT_TRUE(r.has_warning(GetParam().warning)) << GetParam().program;
}

INSTANTIATE_TEST_SUITE_P(Table, WarnedWords,
                         ::testing::Values(WarnCase{"S1000", "no spindle"}, WarnCase{"M3 S100", "no spindle"},
                                           WarnCase{"M4", "no spindle"}, WarnCase{"M5", "no spindle"},
                                           WarnCase{"M7", "no coolant"}, WarnCase{"M8", "no coolant"},
                                           WarnCase{"M9", "no coolant"}, WarnCase{"T2 M6", "tool change to T2"},
                                           WarnCase{"T1", "no tool table"}, WarnCase{"G41", "path is not offset"},
                                           WarnCase{"G43 H1", "no tool table"}, WarnCase{"G61", "contouring off"},
                                           WarnCase{"G61.1", "contouring off"},
                                           WarnCase{"G64 P0.01 Q0.01", "contouring on"}, WarnCase{"G97", "no spindle"},
                                           WarnCase{"/G0 X1", "block delete"}, WarnCase{"G80 G0 X1", "motion code applies"},
                                           WarnCase{"G0 X10\nG2 X0 Y10 I-10 K0 F60", "normal axis"}));

// ---- words and programs rejected ----

struct RejectCase {
  const char* program;
  const char* error;  // fragment of the message
  int line;
  const char* at;  // the error's column is where this text starts on that line
};

class RejectedWords : public ::testing::TestWithParam<RejectCase> {};

int column_of(const std::string& program, int line, const std::string& at) {
  std::size_t begin = 0;
  for (int i = 1; i < line; ++i) begin = program.find('\n', begin) + 1;
  const std::size_t end = program.find('\n', begin);
  const std::string text = program.substr(begin, end == std::string::npos ? std::string::npos : end - begin);
  if (at == "$END") return static_cast<int>(text.size()) + 1;
  const std::size_t pos = text.find(at);
  return pos == std::string::npos ? -1 : static_cast<int>(pos) + 1;
}

TEST_P(RejectedWords, RejectedWithLineColumnAndReason) {
  const RejectCase& c = GetParam();
  const auto r = run_program(std::string(c.program) + "\nM2\n", wide_config());
  EXPECT_FALSE(r.check.ok) << c.program;
  const Diagnostic* d = r.first_error();
  ASSERT_NE(d, nullptr) << c.program;
  EXPECT_NE(d->message.find(c.error), std::string::npos) << c.program << " -> " << d->message;
  EXPECT_NE(d->message.find("expected"), std::string::npos) << "messages say what was expected: " << d->message;
  EXPECT_EQ(d->line, c.line) << c.program;
  EXPECT_EQ(d->column, column_of(c.program, c.line, c.at)) << c.program << " -> " << d->message;
  EXPECT_TRUE(r.blocks.empty()) << "nothing half executed";
}

INSTANTIATE_TEST_SUITE_P(
    Table, RejectedWords,
    ::testing::Values(
        RejectCase{"G84 X0 Y0 Z-1 R1 F10", "tapping", 1, "G84"},
        RejectCase{"G83 X0 Y0 Z-1 R1 F10", "Q", 1, "G83"},
        RejectCase{"G41.1 D1\nG18", "cannot change the plane", 2, "G18"},
        RejectCase{"G42.1", "with no D word", 1, "G42"}, RejectCase{"G93 G1 X1", "F word missing with inverse time G1 move", 1, "G1 "},
        RejectCase{"G95", "feed per revolution", 1, "G95"}, RejectCase{"G10 L3 P1 X0", "L3 is not supported", 1, "L3"},
        RejectCase{"G92", "without axis words", 1, "G92"}, RejectCase{"G38.2 F1", "without axis words", 1, "G38"},
        RejectCase{"G33 Z-1 K1", "spindle-synchronized", 1, "G33"}, RejectCase{"G10 L2 P1 R30 X0", "rotation", 1, "R30"},
        RejectCase{"G43.2", "G43.2 without H or axis words", 1, "G43"}, RejectCase{"G43.2 H1 Z1", "both H and axis words", 1, "H1"},
        RejectCase{"G96 S100", "constant surface speed", 1, "G96"}, RejectCase{"G7", "lathe", 1, "G7"},
        RejectCase{"G5 X1 Y1 I1 J1 P1 Q1", "no feed rate", 1, "G5 "},
        RejectCase{"G5.2 X0 Y0 P1 L3", "no feed rate", 1, "G5."},
        RejectCase{"G6.2 P1 K0 R1 F10", "NURBS order must be a whole number from 2 to 6", 1, "P1"},
        RejectCase{"G6.2 P4 K0 L3 F10", "L word with no G code", 1, "L3"}, RejectCase{"M60", "pallet", 1, "M60"},
        RejectCase{"M19", "spindle orientation", 1, "M19"}, RejectCase{"M48", "override", 1, "M48"},
        RejectCase{"M62 P1", "I/O", 1, "M62"}, RejectCase{"M100", "user M codes", 1, "M10"},
        RejectCase{"G12", "unknown G code G12", 1, "G12"}, RejectCase{"M12", "unknown M code M12", 1, "M12"},
        RejectCase{"G0 A10", "no A axis", 1, "A10"}, RejectCase{"G0 X1 X2", "second X word", 1, "X2"},
        RejectCase{"G0 G1 X1", "same modal group", 1, "G1 "}, RejectCase{"G20 G21", "same modal group", 1, "G21"},
        RejectCase{"M3 M5", "same modal group", 1, "M5"}, RejectCase{"G1 X1", "no feed rate", 1, "G1 "},
        RejectCase{"G1 X1 F0", "no feed rate", 1, "G1 "}, RejectCase{"X1", "no motion mode", 1, "X1"},
        RejectCase{"G61 R0.5", "R word with no G code", 1, "R0."},
        RejectCase{"G0 X1 I1", "I word with no G2/G3", 1, "I1"}, RejectCase{"G1 X1 F10 P2", "P word", 1, "P2"},
        RejectCase{"G2 X1 F1", "I, J, K and R words all missing", 1, "G2 "},
        RejectCase{"G2 X1 Y0 I0.5 R0.5 F1", "R and I/J/K", 1, "R0.5"},
        RejectCase{"G0 X0 Y0\nG2 X0 Y0 R5 F100", "end point equals its start", 2, "R5"},
        RejectCase{"G0 X0 Y0\nG2 X10 Y0 R2 F100", "too small", 2, "R2"},
        RejectCase{"G0 X0 Y0\nG2 X10 Y0 I4 F100", "radius to end of arc differs", 2, "G2 "},
        RejectCase{"G17 G2 X1 Y1 K1 F1", "not an offset in the G17 plane", 1, "K1"},
        RejectCase{"G4", "G4 without P", 1, "G4"}, RejectCase{"G4 P-1", "negative dwell", 1, "P-1"},
        RejectCase{"G10 L2 P10 X1", "P0 (the active system) to P9", 1, "P10"},
        RejectCase{"G53 G2 X1 I1 F1", "G53 needs G0 or G1", 1, "G53"},
        RejectCase{"G91 G53 G0 X1", "G53 in incremental", 1, "G53"}, RejectCase{"#1=[1/0]", "division by zero", 1, "/0]"},
        RejectCase{"G0 X#<nowhere>", "not defined", 1, "#<n"}, RejectCase{"#5420=1", "read-only", 1, "#54"},
        RejectCase{"o<foo> call", "unknown subroutine", 1, "o<f"}, RejectCase{"M99", "M99 outside", 1, "M99"},
        RejectCase{"O100 endif", "without a matching if", 1, "O10"},
        RejectCase{"G0 X1 (unclosed", "comment not closed", 1, "(un"},
        RejectCase{"G0 Xm", "expected a number after X", 1, "m"},
        RejectCase{"G0 X1.2.3", "two decimal points", 1, ".3"}, RejectCase{"G0 X[1/0]", "division by zero", 1, "/0]"},
        RejectCase{"G0 X[1+2", "expected ']'", 1, "$END"}, RejectCase{"G0 X1 $", "unexpected '$'", 1, "$"},
        RejectCase{"G0 X1 E5", "E word", 1, "E5"}, RejectCase{"G0 X1e5", "E word", 1, "e5"},
        RejectCase{"G1 X1 F-5", "negative F", 1, "F-5"}, RejectCase{"G0 X99999999999", "out of range", 1, "X99"},
        RejectCase{"G0 X1 %", "'%'", 1, "%"}, RejectCase{"G1.5 X1", "unknown G code G1.5", 1, "G1."},
        RejectCase{"G1.25 X1", "bad G number", 1, "G1."}));

TEST(Interpreter, ErrorMessageFormatNamesFileLineColumn) {
  const auto r = run_program("G0 X0\nG84 X1\n", wide_config());
  ASSERT_FALSE(r.check.ok);
  const std::string text = format_diagnostic(*r.first_error());
  EXPECT_EQ(text.rfind("test.ngc:2:1: error: G84: tapping", 0), 0u) << text;
}

TEST(Interpreter, AnyErrorMeansNoBlocksAtAll) {
  // A valid first half and an error at the very end: nothing may be produced.
  std::string program;
  for (int i = 0; i < 100; ++i) program += "G0 X" + std::to_string(i) + "\n";
  program += "G84\nM2\n";
  const auto r = run_program(program, wide_config());
  EXPECT_FALSE(r.check.ok);
  EXPECT_TRUE(r.blocks.empty());
}

TEST(Interpreter, ErrorsKeepFollowingTheProgramPosition) {
  // An arc error must not make the next arc look wrong too.
  const auto r = run_program("G0 X0 Y0\nG2 X10 Y0 I4 F100\nG2 X0 Y0 I-5\nM2\n", wide_config());
  EXPECT_FALSE(r.check.ok);
  int errors = 0;
  for (const Diagnostic& d : r.check.diagnostics) errors += d.severity == Diagnostic::Severity::kError;
  EXPECT_EQ(errors, 1);
}

TEST(Interpreter, ArcToleranceRuleFollowsLinuxCnc) {
  MachineConfig c = wide_config();
  c.gcode.arc_radius_tolerance_mm = 0.01;
  c.gcode.arc_radius_tolerance_rel = 0.001;
  // r = 100: a 0.05 mm difference is 0.05% -> accepted (relative part small enough).
  EXPECT_TRUE(run_program("G0 X0 Y0\nG2 X200.05 Y0 I100 F100\nM2\n", c).check.ok);
  // r = 5: 0.05 mm is 1% and above 0.01 mm -> rejected.
  EXPECT_FALSE(run_program("G0 X0 Y0\nG2 X10.05 Y0 I5 F100\nM2\n", c).check.ok);
  // Above 100 x the absolute tolerance: rejected whatever the radius.
  EXPECT_FALSE(run_program("G0 X0 Y0\nG2 X20002 Y0 I10000 F100\nM2\n", c).check.ok);
  // Inch programs: the interpreter's absolute threshold is 2.54 times the metric one (as in
  // LinuxCNC). The rt's block check knows no units and holds the metric one against the
  // block's radius, which is the mean of the start and end radii (issue 14): each is within
  // half the difference of it, so the block the interpreter accepts passes the rt's check.
  const auto inch = run_program("G20 G0 X0 Y0\nG2 X0.2009 Y0 I0.1 F10\nM2\n", c);  // 0.0229 mm
  EXPECT_FALSE(inch.has_error("radius to end of arc differs"));
  EXPECT_TRUE(inch.check.ok);
  EXPECT_FALSE(run_program("G21 G0 X0 Y0\nG2 X5.1029 Y0 I2.54 F10\nM2\n", c).check.ok);  // same in mm
}

TEST(Interpreter, ExpressionsAreEvaluated) {
  const auto r = run_program("G0 X[1 + 2 * 3] Y[SQRT[16] - ABS[-1]] Z[2 ** 3 / 4]\nG0 X[ATAN[1]/[1]] Y[COS[60]]\nM2\n",
                             wide_config());
  ASSERT_TRUE(r.check.ok);
  expect_position(r.motion().at(0).end, 7, 3, 2, 1e-12);
  EXPECT_NEAR(r.motion().at(1).end[0], 45, 1e-12);
  EXPECT_NEAR(r.motion().at(1).end[1], 0.5, 1e-12);
}

TEST(Interpreter, ProgramNumberAndLineNumbersAccepted) {
  const auto r = run_program("O1234\nN10 G0 X1\nN20 G1 X2 F60 (comment) ; trailing\nM2\n", wide_config());
  ASSERT_TRUE(r.check.ok);
  EXPECT_EQ(r.motion().size(), 2u);
}

}  // namespace
}  // namespace pcnc
