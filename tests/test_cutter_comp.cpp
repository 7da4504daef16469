// test_cutter_comp.cpp — cutter radius compensation (host/gcode/cutter_comp.hpp) through the
// front end: the moves `pcnc check --print-moves` prints, against values worked out by hand
// from LinuxCNC's rules (entry, convex and concave corners, arcs inside and outside, Z moves,
// G91, G40, G18/G19, tool table and negative D), LinuxCNC's own output for one of its test
// programs, LinuxCNC's errors, the exact gouge test, and --fit.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "gcode/tool_table.hpp"
#include "gcode_listing.hpp"
#include "test_constants.hpp"

namespace pcnc::test {
namespace {


void expect_end(const Move& m, double x, double y, double z = 0.0, double tol = 1e-9) {
  EXPECT_NEAR(m.end[0], x, tol) << "line " << m.line;
  EXPECT_NEAR(m.end[1], y, tol) << "line " << m.line;
  EXPECT_NEAR(m.end[2], z, tol) << "line " << m.line;
}

// Every move starts where the one before it ended: the tool path is continuous.
void expect_continuous(const Listing& l) {
  for (std::size_t i = 1; i < l.moves.size(); ++i) {
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(l.moves[i].start[k], l.moves[i - 1].end[k], 1e-12) << "move " << i;
  }
}

TEST(CutterComp, EntryAndConcaveCornersLeft) {
  const Listing l = list_program("G0 X0 Y0\nG41.1 D2\nG1 X10 Y0 F100\nG1 X10 Y10\nG1 X0 Y10\nG40\nG0 X0 Y20\nM2\n");
  ASSERT_TRUE(l.result.ok) << l.first_error();
  ASSERT_EQ(l.moves.size(), 5u);
  expect_end(l.moves[1], 9, 1);   // the entry ends at its offset end point, cut back at the concave corner
  expect_end(l.moves[2], 9, 9);   // ... each wall 1 mm inside
  expect_end(l.moves[3], 0, 9);   // G40 leaves the last move where it is
  expect_end(l.moves[4], 0, 20);  // the move after G40 goes to the programmed point
  EXPECT_EQ(l.moves[4].start[1], 9.0);
  expect_continuous(l);
}

TEST(CutterComp, ConvexCornersGetArcsAboutTheCorner) {
  const Listing l = list_program("G0 X0 Y0\nG42.1 D2\nG1 X10 Y0 F100\nG1 X10 Y10\nG1 X0 Y10\nG40\nG0 X0 Y20\nM2\n");
  ASSERT_TRUE(l.result.ok) << l.first_error();
  ASSERT_EQ(l.moves.size(), 7u);
  expect_end(l.moves[1], 10, -1);
  ASSERT_EQ(l.moves[2].kind, MoveKind::kArc);
  expect_end(l.moves[2], 11, 0);
  EXPECT_NEAR(l.moves[2].center[0], 10, 1e-12);
  EXPECT_NEAR(l.moves[2].center[1], 0, 1e-12);
  EXPECT_NEAR(l.moves[2].radius, 1, 1e-12);
  EXPECT_NEAR(l.moves[2].sweep, kPi / 2, 1e-12);
  EXPECT_EQ(l.moves[2].line, 4);  // the corner belongs to the move that turns
  expect_end(l.moves[3], 11, 10);
  ASSERT_EQ(l.moves[4].kind, MoveKind::kArc);
  expect_end(l.moves[4], 10, 11);
  expect_end(l.moves[5], 0, 11);
  expect_continuous(l);
}

TEST(CutterComp, ArcsShrinkInsideAndGrowOutside) {
  const Listing l =
      list_program("G0 X0 Y0\nG41.1 D2\nG1 X10 Y0 F100\nG3 X20 Y10 I0 J10\nG2 X30 Y20 I10 J0\nG40\nG1 X30 Y30\nM2\n");
  ASSERT_TRUE(l.result.ok) << l.first_error();
  ASSERT_EQ(l.moves.size(), 5u);
  expect_end(l.moves[1], 10, 1);
  ASSERT_EQ(l.moves[2].kind, MoveKind::kArc);  // G3 with the tool inside: radius 10 - 1
  EXPECT_NEAR(l.moves[2].radius, 9, 1e-12);
  EXPECT_NEAR(l.moves[2].sweep, kPi / 2, 1e-12);
  expect_end(l.moves[2], 19, 10);
  ASSERT_EQ(l.moves[3].kind, MoveKind::kArc);  // G2 with the tool outside: 10 + 1
  EXPECT_NEAR(l.moves[3].radius, 11, 1e-12);
  EXPECT_NEAR(l.moves[3].sweep, -kPi / 2, 1e-12);
  expect_end(l.moves[3], 30, 21);
  expect_end(l.moves[4], 30, 30);
  expect_continuous(l);
}

TEST(CutterComp, ZMovesKeepTheToolsPlaceAndG91Works) {
  const Listing l = list_program("G0 X0 Y0\nG41.1 D2\nG1 X10 F100\nG1 Z-1\nG1 X20\nG40\nG0 Z5\nM2\n");
  ASSERT_TRUE(l.result.ok) << l.first_error();
  ASSERT_EQ(l.moves.size(), 5u);
  expect_end(l.moves[1], 10, 1, 0);
  expect_end(l.moves[2], 10, 1, -1);  // straight down at the offset point
  expect_end(l.moves[3], 20, 1, -1);
  expect_end(l.moves[4], 20, 0, 5);  // after G40, to the programmed point (LinuxCNC)

  const Listing g91 = list_program("G0 X0 Y0\nG91 G41.1 D2\nG1 X10 F100\nG1 Y10\nG40\nG90 G0 X0\nM2\n");
  ASSERT_TRUE(g91.result.ok) << g91.first_error();
  ASSERT_EQ(g91.moves.size(), 4u);
  expect_end(g91.moves[1], 9, 1);
  expect_end(g91.moves[2], 9, 10);
}

TEST(CutterComp, ToolTableDiameterAndNegativeDiameterSwapsTheSide) {
  auto table = std::make_shared<ToolTable>();
  std::vector<std::string> errors;
  ASSERT_TRUE(parse_tool_table("T1 P1 D4\nT2 P2 D1\n", "tools.tbl", *table, errors));
  JobOptions o;
  o.tools = table;
  const Listing d1 = list_program("T2 M6\nG41 D1\nG1 X10 F100\nG40\nG1 Y-5\nM2\n", wide_config(), o);
  ASSERT_TRUE(d1.result.ok) << d1.first_error();
  expect_end(d1.moves[0], 10, 2);  // D1: tool 1's diameter 4, not the spindle's tool 2
  const Listing spindle = list_program("T2 M6\nG42\nG1 X10 F100\nG40\nG1 Y-5\nM2\n", wide_config(), o);
  ASSERT_TRUE(spindle.result.ok) << spindle.first_error();
  expect_end(spindle.moves[0], 10, -0.5);  // no D: the tool in the spindle
  const Listing missing = list_program("G41 D7\nG1 X10 F100\nM2\n", wide_config(), o);
  EXPECT_TRUE(missing.has_error("tool 7 is not in the tool table")) << missing.first_error();

  const Listing neg = list_program("G41.1 D-2\nG1 X10 F100\nG40\nG1 Y5\nM2\n");
  ASSERT_TRUE(neg.result.ok) << neg.first_error();
  expect_end(neg.moves[0], 10, -1);  // left with a negative diameter: right
}

TEST(CutterComp, G18AndG19Planes) {
  // G18 works in (Z, X), normal +Y: moving +X with the tool on the left puts it at -Z.
  const Listing xz = list_program("G18 G41.1 D2\nG1 X10 F100\nG40\nG1 X20\nM2\n");
  ASSERT_TRUE(xz.result.ok) << xz.first_error();
  expect_end(xz.moves[0], 10, 0, -1);
  // G19 works in (Y, Z), normal +X: moving +Y with the tool on the left puts it at +Z.
  const Listing yz = list_program("G19 G41.1 D2\nG1 Y10 F100\nG40\nG1 Y20\nM2\n");
  ASSERT_TRUE(yz.result.ok) << yz.first_error();
  expect_end(yz.moves[0], 0, 10, 1);
}

// LinuxCNC's rs274 output (tests/interp/crazy-paths, the first subroutine called with D-.5),
// printed to 4 decimals: the moves must agree to within that rounding.
TEST(CutterComp, MatchesLinuxCncCrazyPathsFirstContour) {
  const Listing l = list_program(
      "G21 F100\nG0 X-100 Y-100\nG41.1 D-.5\ng90 g1 y-102\n"
      "G2 I1.095697 J-0.097206 X-99.562609 Y-102.978473\nG1 X-97.562609 Y-99.978473\n"
      "G1 X-91.562609 Y-97.978473\nG3 I-1.365837 J-2.212349 X-90.369054 Y-100.648542\nG40\n"
      "G1 X-80.369054 Y-95.648542\nM2\n");
  ASSERT_TRUE(l.result.ok) << l.first_error();
  const double want[][2] = {{-100.0000, -100.0000}, {-100.2500, -102.0000}, {-99.7510, -102.0221},
                            {-99.2047, -102.8923},  {-97.4022, -100.1885},  {-91.4836, -98.2156},
                            {-91.4313, -97.7657},   {-90.1230, -100.6926},  {-80.3691, -95.6485}};
  const MoveKind kinds[] = {MoveKind::kRapid, MoveKind::kLine, MoveKind::kArc, MoveKind::kArc, MoveKind::kLine,
                            MoveKind::kLine,  MoveKind::kArc,  MoveKind::kArc, MoveKind::kLine};
  ASSERT_EQ(l.moves.size(), std::size(want));
  for (std::size_t i = 0; i < std::size(want); ++i) {
    EXPECT_EQ(l.moves[i].kind, kinds[i]) << i;
    expect_end(l.moves[i], want[i][0], want[i][1], 0.0, 5e-5 + 1e-9);
  }
  expect_continuous(l);
}

struct CompError {
  const char* program;
  const char* error;
  int line;
};

class CutterCompErrors : public ::testing::TestWithParam<CompError> {};

TEST_P(CutterCompErrors, RefusedWithTheLine) {
  const CompError& c = GetParam();
  const Listing l = list_program(c.program);
  EXPECT_FALSE(l.result.ok) << c.program;
  const Diagnostic* first = nullptr;
  for (const Diagnostic& d : l.result.diagnostics) {
    if (d.severity == Diagnostic::Severity::kError && first == nullptr) first = &d;
  }
  ASSERT_NE(first, nullptr) << c.program;
  EXPECT_NE(first->message.find(c.error), std::string::npos) << first->message;
  EXPECT_EQ(first->line, c.line) << first->message;
}

INSTANTIATE_TEST_SUITE_P(
    LinuxCncRules, CutterCompErrors,
    ::testing::Values(
        CompError{"G41.1 D4\nG1 X1.5 F100\nM2\n", "entry move (1.5000 mm) is not greater than the tool radius", 2},
        CompError{"G41.1 D4\nG1 X10 F100\nG3 X10 Y2 I0 J1\nM2\n", "gouge by 1.0000 mm", 3},
        CompError{"G0 X0 Y0\nG41.1 D.5\nG1 X1 F1\nG1 X2\nG40\nG2 I1\nM2\n", "must be straight, not an arc", 6},
        CompError{"G41.1 D2\nG18\nM2\n", "cannot change the plane (G18) with cutter radius compensation on", 2},
        CompError{"G41.1 D2\nT1 M6\nM2\n", "cannot change tools (M6)", 2},
        CompError{"G41.1 D2\nG43 H1\nM2\n", "cannot change the tool length offset", 2},
        CompError{"G41.1 D2\nG55\nM2\n", "cannot change coordinate systems", 2},
        CompError{"G41.1 D2\nG28\nM2\n", "cannot use G28", 2},
        CompError{"G41.1 D2\nG92 X0\nM2\n", "cannot change axis offsets", 2},
        CompError{"G41.1 D2\nG81 X0 Y0 Z-1 R1 F10\nM2\n", "cannot use canned cycles", 2},
        CompError{"G41.1 D2\nG41.1 D2\nM2\n", "already on", 2},
        CompError{"G41.1\nM2\n", "with no D word", 1},
        CompError{"G41 D1.5\nM2\n", "whole number", 1},
        CompError{"G1 X1 D2 F100\nM2\n", "D word with no G code that uses it", 1},
        // LinuxCNC's ccomp-gouging: a notch 0.1 high for a 0.25 tool. The exact test finds it
        // at the move whose tool path cuts into the notch's far wall, with the depth.
        CompError{"G0 X0 Y0 Z0\nG41.1 D.25\nG1 X1 F1\nG1 X2\nG1 Y.1\nG1 X1\nG40\nG1 X2\nM2\n",
                  "comes 0.1000 mm into the contour of line 6", 4}));

std::string bottle(const char* neck_right_x) {
  const std::string x = neck_right_x;
  return "G0 X0 Y20\nG41.1 D2\nG1 X0 Y15 F100\nG1 X0 Y2\nG1 X-5 Y2\nG1 X-5 Y-5\nG1 X6.5 Y-5\nG1 X6.5 Y2\nG1 X" + x +
         " Y2\nG1 X" + x + " Y10\nG40\nG0 X20\nM2\n";
}

TEST(CutterComp, BottleNeckNarrowerThanTheToolIsAGougeLinuxCncCannotSee) {
  // A bottle whose neck is 1.5 wide, for a 2 mm tool: every corner on its own fits the tool
  // (LinuxCNC's one-move tests pass it), the neck's walls six moves apart do not.
  const Listing gouge = list_program(bottle("1.5"));
  EXPECT_FALSE(gouge.result.ok);
  const Diagnostic* first = nullptr;
  for (const Diagnostic& d : gouge.result.diagnostics) {
    if (d.severity == Diagnostic::Severity::kError && first == nullptr) first = &d;
  }
  ASSERT_NE(first, nullptr);
  EXPECT_EQ(first->line, 4);  // the neck's left wall, whose tool path reaches into the right one
  EXPECT_NE(first->message.find("comes 0.5000 mm into the contour of line"), std::string::npos) << first->message;
  MachineConfig loose = wide_config();
  loose.cutter_comp.gouge_check = false;  // LinuxCNC's local tests alone: accepted
  const Listing local = list_program(bottle("1.5"), loose);
  EXPECT_TRUE(local.result.ok) << local.first_error();
  // The gouge is an error (nothing would move), but the listing goes on through it with
  // LinuxCNC's moves, as LinuxCNC's interpreter would: the same moves as without the test.
  ASSERT_EQ(gouge.moves.size(), local.moves.size());
  for (std::size_t i = 0; i < local.moves.size(); ++i) {
    EXPECT_EQ(norm(gouge.moves[i].end - local.moves[i].end), 0.0) << "move " << i;
  }
  // A neck 2.5 wide fits the same tool.
  const Listing fits = list_program(bottle("2.5"));
  EXPECT_TRUE(fits.result.ok) << fits.first_error();
}

TEST(CutterComp, FitScalesThePathNotTheTool) {
  const std::string square = "G0 X0 Y0\nG41.1 D2\nG1 X100 Y0 F100\nG1 X100 Y100\nG1 X0 Y100\nG40\nG0 X0 Y120\nM2\n";
  JobOptions o;
  o.fit = true;
  const RunResult r = run_program(square, mill_config(), o);
  ASSERT_TRUE(r.check.ok);
  const double s = r.check.transform.scale;
  const Vec3 off = r.check.transform.offset;
  ASSERT_LT(s, 0.5);  // the 100 mm square is scaled into the 25 mm travel
  std::vector<Block> feeds;
  for (const Block& b : r.motion()) {
    if (b.kind == BlockKind::kLine) feeds.push_back(b);
  }
  ASSERT_EQ(feeds.size(), 3u);
  // The walls sit 1 mm (the real radius) inside the scaled square.
  EXPECT_NEAR(feeds[0].end[0], off[0] + s * 100 - 1, 1e-9);
  EXPECT_NEAR(feeds[0].end[1], off[1] + 1, 1e-9);
  EXPECT_NEAR(feeds[1].end[0], off[0] + s * 100 - 1, 1e-9);
  EXPECT_NEAR(feeds[1].end[1], off[1] + s * 100 - 1, 1e-9);
}

TEST(CutterComp, CheckCountsMovesAndKeepsTheProgrammedContour) {
  const RunResult r = run_program("G0 X0 Y0\nG42.1 D2\nG1 X10 Y0 F100\nG1 X10 Y10\nG3 X0 Y10 I-5 J0\nG40\nG0 X0 Y20\nM2\n",
                                  wide_config());
  ASSERT_TRUE(r.check.ok);
  const CompFigures& c = r.check.comp;
  EXPECT_EQ(c.sessions, 1u);
  EXPECT_EQ(c.moves_in, 3u);
  EXPECT_EQ(c.corner_arcs, 1u);  // at (10,0); the arc at (10,10) turns the same way (tangent)
  EXPECT_EQ(c.moves_out, 4u);
  EXPECT_DOUBLE_EQ(c.max_radius_mm, 1.0);
  ASSERT_EQ(c.contour.size(), 1u);
  // (0,0), (10,0), (10,10), then the half circle in chords of at most 3 degrees: 60 more.
  ASSERT_EQ(c.contour[0].size(), 3u + 60u);
  EXPECT_NEAR(c.contour[0].back()[0], 0.0, 1e-12);
  EXPECT_NEAR(c.contour[0].back()[1], 10.0, 1e-12);
  EXPECT_NEAR(c.contour[0][32][1], 15.0, 1e-9);  // the half circle's top, 5 above its center
}


// A circle of radius 5 about (0,0) written as CAM writes it: chords of about 0.2 mm, end
// points rounded to 0.001 mm, from angle a0 for n chords, counter-clockwise.
std::string cam_arc(double a0, int n, double step = 0.04) {
  std::string s;
  char buf[64];
  for (int i = 1; i <= n; ++i) {
    const double a = a0 + i * step;
    std::snprintf(buf, sizeof buf, "G1 X%.3f Y%.3f\n", 5.0 * std::cos(a), 5.0 * std::sin(a));
    s += buf;
  }
  return s;
}

TEST(CutterCompFit, ShortG1RunBecomesBiarcsOffsetExactly) {
  // Entry to (5,0), then 60 chords of 0.2 mm along the circle, the tool (r 1) on the right:
  // outside, on the circle of radius 6.
  const std::string prog = "G0 X8 Y-3\nG42.1 D2\nG1 X5 Y0 F100\n" + cam_arc(0.0, 60) + "G40\nG1 X0 Y8\nM2\n";
  const RunResult r = run_program(prog, wide_config());
  ASSERT_TRUE(r.check.ok) << (r.first_error() ? r.first_error()->message : "");
  EXPECT_EQ(r.check.comp.fitted_runs, 1u);
  EXPECT_EQ(r.check.comp.moves_replaced, 60u);
  EXPECT_GT(r.check.comp.biarcs, 0u);
  EXPECT_LT(r.check.comp.fit_arcs, 60u) << "fewer, longer arcs than chords";
  EXPECT_LE(r.check.comp.max_fit_deviation_mm, 0.001 + 1e-12);
  // Every tool move made for the run ends on the offset circle within the tolerance plus the
  // programmed points' rounding (0.5 um).
  const Listing l = list_program(prog);
  ASSERT_TRUE(l.result.ok);
  int on_circle = 0;
  for (const Move& m : l.moves) {
    if (m.line < 4 || m.line > 63) continue;
    EXPECT_NEAR(std::hypot(m.end[0], m.end[1]), 6.0, 0.0015) << format_move(m);
    ++on_circle;
  }
  EXPECT_GT(on_circle, 2);

  // The same chords one by one (LinuxCNC's way; fitting off by a tiny segment limit): a
  // tool move per chord, each offset along its own rounded chord's normal.
  MachineConfig one_by_one = wide_config();
  one_by_one.cutter_comp.fit_segment_max_mm = 0.01;
  const Listing raw = list_program(prog, one_by_one);
  ASSERT_TRUE(raw.result.ok) << raw.first_error();
  int raw_moves = 0;
  for (const Move& m : raw.moves) raw_moves += m.line >= 4 && m.line <= 63 ? 1 : 0;
  EXPECT_GE(raw_moves, 60);
  EXPECT_LT(on_circle, raw_moves);
}

TEST(CutterCompFit, ShortRunsAndCornersAreOffsetOneByOne) {
  // 7 chords: below the run length of 8, offset as LinuxCNC does.
  const RunResult seven = run_program("G0 X8 Y-3\nG42.1 D2\nG1 X5 Y0 F100\n" + cam_arc(0.0, 7) + "G40\nG1 X0 Y8\nM2\n", wide_config());
  ASSERT_TRUE(seven.check.ok);
  EXPECT_EQ(seven.check.comp.fitted_runs, 0u);
  // Two runs of 10 with a corner of 30 degrees (more than the 10 degree contouring angle)
  // between them: two fits, never one across the corner.
  const std::string two = "G0 X8 Y-3\nG42.1 D2\nG1 X5 Y0 F100\n" + cam_arc(0.0, 10) + cam_arc(0.4 + 0.52, 10) + "G40\nG1 X0 Y8\nM2\n";
  const RunResult r = run_program(two, wide_config());
  ASSERT_TRUE(r.check.ok) << (r.first_error() ? r.first_error()->message : "");
  EXPECT_EQ(r.check.comp.fitted_runs, 2u);
  EXPECT_EQ(r.check.comp.moves_replaced, 19u) << "the first chord of the second run turns the corner";
}

TEST(CutterCompFit, NurbsUnderCompensationIsFitted) {
  const std::string prog =
      "G0 X-9 Y-9\nG41.1 D2\nG1 X-6 Y-6 F300\nG5.2 X-2 Y0 P1 L4\nX2 Y-6 P1\nX6 Y0 P1\nX6 Y6 P1\nG5.3\nG1 X8 Y8\nG40\nG1 X10 Y10\nM2\n";
  const RunResult r = run_program(prog, wide_config());
  ASSERT_TRUE(r.check.ok) << (r.first_error() ? r.first_error()->message : "");
  EXPECT_EQ(r.check.comp.fitted_nurbs, 1u);
  EXPECT_EQ(r.check.comp.moves_replaced, 1u);
  EXPECT_GT(r.check.comp.fit_arcs, 4u);
  EXPECT_LE(r.check.comp.max_fit_deviation_mm, 0.001);
  // A NURBS cannot be the entry move.
  const Listing entry = list_program("F300 G41.1 D2\nG5.2 X-2 Y0 P1 L4\nX2 Y-6 P1\nX6 Y0 P1\nG5.3\nM2\n");
  EXPECT_TRUE(entry.has_error("cannot be the entry move")) << entry.first_error();
}

TEST(CutterComp, ArcEntryKeepsItsEndOffsetAndMovesItsCentre) {
  // G41 with r 1 on a G3 half circle about (5,0) from (0,0) to (10,0): the tool is inside, the
  // arc ends 1 mm inside at (9,0), and its centre moves to (4.5,0) so that it starts at the tool.
  const Listing l = list_program("G0 X0 Y0\nG41.1 D2\nG3 X10 Y0 I5 J0 F100\nG40\nG1 X10 Y-5\nM2\n");
  ASSERT_TRUE(l.result.ok) << l.first_error();
  ASSERT_EQ(l.moves.size(), 3u);
  ASSERT_EQ(l.moves[1].kind, MoveKind::kArc);
  expect_end(l.moves[1], 9, 0);
  EXPECT_NEAR(l.moves[1].center[0], 4.5, 1e-12);
  EXPECT_NEAR(l.moves[1].center[1], 0.0, 1e-12);
  EXPECT_NEAR(l.moves[1].radius, 4.5, 1e-12);
  EXPECT_NEAR(l.moves[1].sweep, kPi, 1e-12);
  const Listing short_entry = list_program("G0 X0 Y0\nG41.1 D2\nG3 X0.8 Y0 I0.4 J0 F100\nM2\n");
  EXPECT_TRUE(short_entry.has_error("entry arc")) << short_entry.first_error();
}

TEST(CutterComp, FitLeavesRoomForTheUnscaledTool) {
  // A 120 mm plate cut outside with a 3 mm tool: --fit scales the plate, the tool stays 3 mm,
  // and the scale leaves room for it (without that room the tool path left the travel).
  const std::string plate =
      "G0 X-80 Y-100 Z0\nG1 Z-1 F600\nG41.1 D3\nG1 X-60 Y-60\nG1 X-60 Y60\nG1 X20 Y60\nG2 X60 Y20 I0 J-40\n"
      "G1 X60 Y-60\nG1 X-60 Y-60\nG40\nG1 X-100 Y-100\nG0 Z0\nM2\n";
  JobOptions o;
  o.fit = true;
  const MachineConfig c = mill_config();
  const RunResult r = run_program(plate, c, o);
  ASSERT_TRUE(r.check.ok) << (r.first_error() ? r.first_error()->message : "");
  EXPECT_LE(r.check.max_point[0], c.axes[0].travel_max_mm + 1e-9);
  EXPECT_NEAR(r.check.max_point[0], c.axes[0].travel_max_mm, 1e-6) << "the tool path spans the travel";
  EXPECT_LT(r.check.transform.scale, 0.2);
}


// LinuxCNC's sample programs with compensation (shared corpus), with a tool table giving their
// tools a diameter: each is offset (entries made, tool moves at least as many as moves offset)
// and accepted to the blocks.
TEST(CutterComp, LinuxCncSampleProgramsRun) {
  auto table = std::make_shared<ToolTable>();
  std::vector<std::string> errors;
  ASSERT_TRUE(parse_tool_table("T1 P1 D2\nT4 P4 D3\n", "tools.tbl", *table, errors));
  JobOptions o;
  o.tools = table;
  o.offset = Vec3{0, 0, 0};
  for (const char* name : {"comp.ngc", "comp311.ngc", "comp-g1.ngc"}) {
    const std::string path = std::string(PCNC_SHARED_DIR) + "/gcode/linuxcnc/nc_files/" + name;
    const CheckResult r = check_program(path, wide_config(), o);
    ASSERT_TRUE(r.ok) << name << ": " << (r.diagnostics.empty() ? "" : format_diagnostic(r.diagnostics.front()));
    EXPECT_GE(r.comp.sessions, 1u) << name;
    EXPECT_GE(r.comp.moves_out, r.comp.moves_in) << name;
    EXPECT_GT(r.comp.max_radius_mm, 0.0) << name;
  }
}

TEST(CutterComp, OffsetMoveThatRunsBackwardsIsAGougeLinuxCncMisses) {
  // Straight onto a circle of 0.31 mm chords with a 2 mm tool inside it: the entry is cut back
  // 1 mm at the concave corner, so the first chord's offset runs backwards; the next corners
  // are within LinuxCNC's 0.05 rad, so its own test never looks at it.
  std::string prog = "G21 G90 F600\nG0 X-12 Y0\nG41.1 D2\n";
  char buf[64];
  for (int i = 0; i < 12; ++i) {
    const double a = 2.0 * kPi * i / 200.0;
    std::snprintf(buf, sizeof buf, "G1 X%.4f Y%.4f\n", 10.0 * std::cos(a), 10.0 * std::sin(a));
    prog += buf;
  }
  prog += "G40\nG1 X0 Y0\nM2\n";
  MachineConfig one_by_one = wide_config();
  one_by_one.cutter_comp.fit_segment_max_mm = 0.01;  // the chords one by one, as LinuxCNC
  const Listing l = list_program(prog, one_by_one);
  EXPECT_TRUE(l.has_error("cutter compensation would gouge")) << l.first_error();
  MachineConfig local = one_by_one;
  local.cutter_comp.gouge_check = false;
  EXPECT_TRUE(list_program(prog, local).result.ok);
}

}  // namespace
}  // namespace pcnc::test
