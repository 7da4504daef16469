// test_gcode_offsets.cpp — offsets, stored positions, tools and canned cycles from the program
// (issue 12): G10 L1/L2/L10/L20, G52, G92/G92.1/G92.2/G92.3, G28/G30 and their .1 forms,
// G54-G59.3, T/M6/M61/G43/G43.1/G49, G81-G89 in the interpreter; the work state a program
// leaves; LinuxCNC's semantics (machine = program + G5x + G92 + tool length).
#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "gcode_listing.hpp"

namespace pcnc::test {
namespace {

void expect_xyz(const Vec3& p, double x, double y, double z, const std::string& what = "") {
  EXPECT_NEAR(p[0], x, 1e-9) << what;
  EXPECT_NEAR(p[1], y, 1e-9) << what;
  EXPECT_NEAR(p[2], z, 1e-9) << what;
}

TEST(GcodeOffsets, G10L2SetsASystemAndTheActiveOneAppliesAtOnce) {
  const Listing l = list_program("G10 L2 P1 X10 Y20\nG0 X0 Y0\nG10 L2 P2 Z5\nG55 G0 Z1\nG10 L2 P0 Z7\nG0 Z1\nM2\n");
  ASSERT_TRUE(l.result.ok) << l.first_error();
  ASSERT_EQ(l.moves.size(), 3u);
  expect_xyz(l.moves[0].end, 10, 20, 0, "G54 = (10,20,0)");
  expect_xyz(l.moves[1].end, 10, 20, 6, "G55 Z: (0,0,5) + 1; X and Y stay where they are");
  expect_xyz(l.moves[2].end, 10, 20, 8, "P0 is the active system");
  expect_xyz(l.result.work.g5x[0], 10, 20, 0);
  expect_xyz(l.result.work.g5x[1], 0, 0, 7);
}

TEST(GcodeOffsets, G10L20MakesTheCurrentPointReadTheGivenValue) {
  // At machine X=3 (G54 = 0), G10 L20 P1 X5 makes G54's X = -2: the point now reads X5.
  const Listing l = list_program("G0 X3\nG10 L20 P1 X5\n#1=#5420\nG0 Y#1\nG0 X6\nM2\n");
  ASSERT_TRUE(l.result.ok) << l.first_error();
  EXPECT_NEAR(l.result.work.g5x[0][0], -2.0, 1e-12);
  EXPECT_NEAR(l.moves[1].end[1], 5.0, 1e-12) << "#5420 reads 5";
  EXPECT_NEAR(l.moves[2].end[0], 4.0, 1e-12) << "X6 in the new G54 is machine X4";
}

TEST(GcodeOffsets, G92FamilyAndG52) {
  const Listing l = list_program(
      "G0 X3\nG92 X0\nG0 X1\nG92.2\nG0 X1\nG92.3\nG0 X1\nG92.1\nG0 X1\nG52 X5\nG0 X0\nG52 X0\nG0 X0\nM2\n");
  ASSERT_TRUE(l.result.ok) << l.first_error();
  ASSERT_EQ(l.moves.size(), 7u);
  EXPECT_NEAR(l.moves[1].end[0], 4.0, 1e-12) << "G92 X0 at X3: offset 3";
  EXPECT_NEAR(l.moves[2].end[0], 1.0, 1e-12) << "G92.2: offset off";
  EXPECT_NEAR(l.moves[3].end[0], 4.0, 1e-12) << "G92.3: restored from #5211";
  EXPECT_NEAR(l.moves[4].end[0], 1.0, 1e-12) << "G92.1: cleared";
  EXPECT_NEAR(l.moves[5].end[0], 5.0, 1e-12) << "G52 X5: local offset";
  EXPECT_NEAR(l.moves[6].end[0], 0.0, 1e-12);
  expect_xyz(l.result.work.g92, 0, 0, 0);
}

TEST(GcodeOffsets, G92IsInTheProgramUnits) {
  const Listing l = list_program("G20\nG0 X1\nG92 X0\nG0 X1\n#1=#5211\nG21 G0 Y#1\nM2\n");
  ASSERT_TRUE(l.result.ok) << l.first_error();
  EXPECT_NEAR(l.moves[1].end[0], 50.8, 1e-9);
  EXPECT_NEAR(l.moves[2].end[1], 25.4, 1e-9) << "#5211 holds mm, the machine's units (LinuxCNC)";
}

TEST(GcodeOffsets, G28AndG30UseTheirStoredPositions) {
  MachineConfig c = wide_config();
  c.axes[0].home_mm = 0.0;
  c.axes[1].home_mm = 0.0;
  c.axes[2].home_mm = 25.0;
  const Listing l = list_program("G0 X4 Y5 Z6\nG28.1\nG0 X0 Y0 Z0\nG28 Z1\nG28\nG30\nG0 X1\nG30.1\nG0 X2\nG30 X3\nM2\n", c);
  ASSERT_TRUE(l.result.ok) << l.first_error();
  ASSERT_EQ(l.moves.size(), 10u);
  expect_xyz(l.moves[2].end, 0, 0, 1, "G28 Z1: the intermediate point first");
  expect_xyz(l.moves[3].end, 0, 0, 6, "then Z only to the stored Z");
  expect_xyz(l.moves[4].end, 4, 5, 6, "G28 alone: every axis");
  expect_xyz(l.moves[5].end, 0, 0, 25, "G30 defaults to home_mm");
  expect_xyz(l.moves[8].end, 3, 0, 25, "G30 X3: intermediate X3");
  expect_xyz(l.moves[9].end, 1, 0, 25, "then X to the G30.1 position");
  expect_xyz(l.result.work.g28, 4, 5, 6);
  expect_xyz(l.result.work.g30, 1, 0, 25);
}

TEST(GcodeOffsets, ExtraSystemsAndM2BackToG54) {
  const Listing l = list_program("G10 L2 P9 X1\nG59.3 G0 X0\n#1=#5220\nM2\n");
  ASSERT_TRUE(l.result.ok) << l.first_error();
  EXPECT_NEAR(l.moves[0].end[0], 1.0, 1e-12);
  EXPECT_EQ(l.result.work.active, 0) << "M2 selects G54 again";
}

TEST(GcodeOffsets, OffsetIsThisJobsG54OnlyUnlessTheProgramSetsG54) {
  JobOptions o;  // list_program's --offset 0,0,0 over the config's G54 (0,0,0 in wide_config)
  WorkState w = default_work_state(wide_config());
  w.g5x[0] = Vec3{5, 5, 5};
  o.work = w;
  o.offset = Vec3{1, 2, 3};
  const Listing kept = list_program("G0 X0 Y0 Z0\nG10 L2 P2 X9\nM2\n", wide_config(), o);
  ASSERT_TRUE(kept.result.ok) << kept.first_error();
  expect_xyz(kept.moves[0].end, 1, 2, 3, "--offset places this job");
  expect_xyz(kept.result.work.g5x[0], 5, 5, 5, "the state file's G54 stays");
  EXPECT_NEAR(kept.result.work.g5x[1][0], 9.0, 1e-12);
  const Listing set = list_program("G10 L2 P1 X7 Y7 Z7\nM2\n", wide_config(), o);
  expect_xyz(set.result.work.g5x[0], 7, 7, 7, "the program's own G10 L2 P1 is kept");
}

TEST(GcodeOffsets, TheStartingWorkStateIsUsed) {
  JobOptions o;
  WorkState w = default_work_state(wide_config());
  w.g5x[1] = Vec3{1, 2, 3};
  w.g92 = Vec3{10, 0, 0};
  w.g92_applied = true;
  o.work = w;
  const Listing l = list_program("G55 G0 X0 Y0 Z0\nM2\n", wide_config(), o);
  ASSERT_TRUE(l.result.ok) << l.first_error();
  expect_xyz(l.moves[0].end, 11, 2, 3);
}

// A table holding one tool in its own pocket.
std::shared_ptr<ToolTable> one_tool(int number, double length, double diameter = 0.0) {
  auto table = std::make_shared<ToolTable>();
  ToolEntry t;
  t.number = number;
  t.pocket = number;
  t.offset = Vec3{0, 0, length};
  t.diameter = diameter;
  table->set(t);
  return table;
}

TEST(GcodeTools, LengthOffsetsFromTheTable) {
  const auto table = one_tool(1, 10.0, 6.0);
  JobOptions o;
  o.tools = table;
  const Listing l = list_program(
      "T1 M6\nG43\nG0 Z0\n#1=#5400\n#2=#5410\nG49\nG0 Z0\nG43.1 Z2\nG0 Z0\nG10 L1 P2 Z5 R1\nT2 M6 G43 H2\nG0 Z0\n"
      "G0 X#1 Y#2\nM2\n",
      wide_config(), o);
  ASSERT_TRUE(l.result.ok) << l.first_error();
  ASSERT_EQ(l.moves.size(), 5u);
  EXPECT_NEAR(l.moves[0].end[2], 10.0, 1e-12) << "G43 (H = the tool in the spindle)";
  EXPECT_NEAR(l.moves[1].end[2], 0.0, 1e-12) << "G49";
  EXPECT_NEAR(l.moves[2].end[2], 2.0, 1e-12) << "G43.1 Z2";
  EXPECT_NEAR(l.moves[3].end[2], 5.0, 1e-12) << "G10 L1 P2 Z5 then G43 H2";
  EXPECT_NEAR(l.moves[4].end[0], 1.0, 1e-12) << "#5400: the tool";
  EXPECT_NEAR(l.moves[4].end[1], 6.0, 1e-12) << "#5410: its diameter";
  EXPECT_TRUE(list_program("T9\nM2\n", wide_config(), o).has_error("T9 is not in the tool table"));
  EXPECT_TRUE(list_program("G43 H9\nM2\n", wide_config(), o).has_error("not in the tool table"));
}

// G43.2 (LinuxCNC): adds a tool's offset (H) or the axis words to the offset in effect, as
// often as it is given; G43 replaces the sum, G49 clears it.
TEST(GcodeTools, G43_2AddsToTheLengthOffsetInEffect) {
  const auto table = one_tool(1, 10.0, 6.0);
  JobOptions o;
  o.tools = table;
  const Listing l = list_program(
      "G10 L1 P2 Z0.5\nT1 M6 G43\nG43.2 H2\nG0 Z0\nG43.2 Z0.25 X1\nG0 X0 Z0\nG20 G43.2 Z0.1\nG0 Z0\nG21 G43\nG0 Z0\nM2\n",
      wide_config(), o);
  ASSERT_TRUE(l.result.ok) << l.first_error();
  ASSERT_EQ(l.moves.size(), 4u);
  EXPECT_NEAR(l.moves[0].end[2], 10.5, 1e-12) << "T1's 10 + T2's 0.5";
  EXPECT_NEAR(l.moves[1].end[2], 10.75, 1e-12) << "+ Z0.25";
  EXPECT_NEAR(l.moves[1].end[0], 1.0, 1e-12) << "+ X1 on the X offset";
  EXPECT_NEAR(l.moves[2].end[2], 10.75 + 2.54, 1e-12) << "G20: Z0.1 is 2.54 mm";
  EXPECT_NEAR(l.moves[3].end[2], 10.0, 1e-12) << "G43 replaces the sum";
  const Listing both = list_program("G43.2 H1 Z1\nM2\n", wide_config(), o);
  EXPECT_TRUE(both.has_error("G43.2 with both H and axis words")) << both.first_error();
  EXPECT_TRUE(list_program("G43.2\nM2\n", wide_config(), o).has_error("G43.2 without H or axis words"));
  EXPECT_TRUE(list_program("G43.2 H9\nM2\n", wide_config(), o).has_error("G43.2 H9: tool 9 is not in the tool table"));
  EXPECT_TRUE(list_program("G41 D1\nG1 X1 F100\nG43.2 Z1\nM2\n", wide_config(), o).has_error("cannot change the tool length offset (G43.2)"));
}

TEST(GcodeTools, TheToolAndItsLengthOffsetCarryFromOneProgramToTheNext) {
  // As in LinuxCNC: the tool stays in the spindle and M2 does not cancel G43.
  JobOptions o;
  o.tools = one_tool(3, 7.5);
  o.work = default_work_state(wide_config());
  const Listing a = list_program("T3 M6 G43\nG0 Z0\nM2\n", wide_config(), o);
  ASSERT_TRUE(a.result.ok) << a.first_error();
  EXPECT_EQ(a.result.work.tool, 3);
  EXPECT_TRUE(a.result.work.tool_offset_applied);
  EXPECT_NEAR(a.result.work.tool_offset[2], 7.5, 1e-12);
  o.work = a.result.work;
  const Listing b = list_program("G0 Z0\n#1=#5400\nG0 X#1\nG49\nG0 Z0\nM2\n", wide_config(), o);
  ASSERT_TRUE(b.result.ok) << b.first_error();
  ASSERT_EQ(b.moves.size(), 3u);
  EXPECT_NEAR(b.moves[0].end[2], a.moves[0].end[2], 1e-12) << "the next program starts with G43 of T3";
  EXPECT_NEAR(b.moves[1].end[0] - b.moves[0].end[0], 3.0, 1e-12) << "#5400 is still 3";
  EXPECT_NEAR(b.moves[0].end[2] - b.moves[2].end[2], 7.5, 1e-12) << "G49 takes the length off";
  EXPECT_FALSE(b.result.work.tool_offset_applied);
  EXPECT_EQ(b.result.work.tool, 3);
}

TEST(GcodeTools, M6PausesOnlyWhenTheConfigSaysSo) {
  MachineConfig c = wide_config();
  const RunResult no = run_program("T1 M6\nG0 X1\nM2\n", c);
  ASSERT_TRUE(no.check.ok);
  int pauses = 0;
  for (const Block& b : no.blocks) pauses += b.kind == BlockKind::kPause ? 1 : 0;
  EXPECT_EQ(pauses, 0);
  c.gcode.pause_on_tool_change = true;
  const RunResult yes = run_program("T1 M6\nG0 X1\nM2\n", c);
  ASSERT_TRUE(yes.check.ok);
  ASSERT_GE(yes.blocks.size(), 2u);
  EXPECT_EQ(yes.blocks[0].kind, BlockKind::kPause);
  EXPECT_EQ(yes.blocks[0].line, 1u);
}

TEST(GcodeTools, WithoutATableToolsAreAcceptedWithAWarning) {
  const Listing l = list_program("T3 M6\nG43 H3\nG0 Z1\nM2\n");
  ASSERT_TRUE(l.result.ok) << l.first_error();
  EXPECT_TRUE(l.has_warning("no tool table"));
  EXPECT_NEAR(l.moves[0].end[2], 1.0, 1e-12) << "length 0";
}

TEST(GcodeArcs, G90_1MakesTheCenterAbsolute) {
  // With G54 at X10, G90.1 I/J name the center in program coordinates.
  const Listing l = list_program("G10 L2 P1 X10\nG0 X0 Y0\nG90.1 G2 X4 Y0 I2 J0 F60\nG91.1 G2 X8 Y0 I2 J0\nM2\n");
  ASSERT_TRUE(l.result.ok) << l.first_error();
  ASSERT_EQ(l.moves.size(), 3u);
  expect_xyz(l.moves[1].center, 12, 0, 0, "center = (2,0) program = (12,0) machine");
  expect_xyz(l.moves[2].center, 16, 0, 0, "G91.1: relative to the start (14 + 2)");
}

TEST(GcodeCycles, DrillingThroughTheInterpreter) {
  // G81 in G55 with G99 and two holes; then G80 and a straight move.
  const Listing l = list_program(
      "G10 L2 P2 X100\nG55 G0 Z10\nG99 G81 X1 Y1 Z-2 R2 F120\nX3\nG80\nG0 Z10\nM2\n");
  ASSERT_TRUE(l.result.ok) << l.first_error();
  ASSERT_EQ(l.moves.size(), 9u);
  expect_xyz(l.moves[1].end, 101, 1, 10, "to the hole at the initial level");
  expect_xyz(l.moves[2].end, 101, 1, 2, "down to R");
  expect_xyz(l.moves[3].end, 101, 1, -2, "feed to the bottom");
  EXPECT_EQ(l.moves[3].kind, MoveKind::kLine);
  EXPECT_NEAR(l.moves[3].feed_mm_s, 2.0, 1e-12);
  expect_xyz(l.moves[4].end, 101, 1, 2, "G99: back to R");
  expect_xyz(l.moves[5].end, 103, 1, 2, "second hole at R (sticky Z, R)");
  expect_xyz(l.moves[6].end, 103, 1, -2);
  EXPECT_EQ(l.moves[6].line, 4);
}

TEST(GcodeCycles, G98ReturnsToTheInitialLevelAndErrorsNameTheWord) {
  const Listing l = list_program("G0 Z5\nG98 G83 X0 Y0 Z-3 R1 Q2 F60\nM2\n");
  ASSERT_TRUE(l.result.ok) << l.first_error();
  EXPECT_NEAR(l.moves.back().end[2], 5.0, 1e-12);
  const Listing bad = list_program("G0 Z5\nG81 X0 Y0 Z-1 F60\nM2\n");
  EXPECT_TRUE(bad.has_error("without R")) << bad.first_error();
  EXPECT_TRUE(list_program("G0 Z5\nG84 X0 Y0 Z-1 R1 F60\nM2\n").has_error("tapping"));
}

}  // namespace
}  // namespace pcnc::test
