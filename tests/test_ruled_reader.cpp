// test_ruled_reader.cpp — the reader of the G5.4 ... G5.5 form (host/gcode/ruled_reader.hpp):
// what the writer (host/gcode/ruled_program.hpp) writes for passes over the seed's example reads
// back as the same pieces within the printed precision (X Y Z 5 decimals, I J K 7), in order,
// with the feed and the lines; a piece read back builds a ruled model and block that the rt's
// follower runs to its last point; every rule of the form is refused at its line and column.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "gcode/ruled_reader.hpp"
#include "geometry/ruled_model.hpp"
#include "geometry/ruled_passes.hpp"
#include "ipc/block_ruled.hpp"
#include "motion/ruled_follower.hpp"
#include "gcode/ruled_program.hpp"

namespace pcnc {
namespace {

std::string join(const std::vector<std::string>& lines) {
  std::string s;
  for (const std::string& l : lines) s += l + "\n";
  return s;
}

std::vector<RuledPiece> example_pieces() {
  PassOptions po;
  po.cusp_height = 0.2;  // a few passes only
  po.point_spacing = 1.5;
  const PassPlan plan = plan_passes(part_surface(example_surface(25.0, {-12.5, -12.5, -4.5})), po);
  EXPECT_EQ(plan.error, "");
  std::vector<RuledPiece> pieces;
  for (std::size_t i = 0; i < plan.passes.size() && i < 4; ++i) {
    RuledPiece p;
    for (const PassPoint& q : plan.passes[i].points) {
      p.points.push_back(q.tip);
      p.axes.push_back(q.axis);
    }
    p.comment = "pass " + std::to_string(i + 1);
    pieces.push_back(p);
  }
  // and a few values the printing must get right: negatives, zeros, tiny components
  pieces.push_back({{{-0.000004, 12.345678, -3.0}, {1e-7, -12.5, 0.0}, {3.25, 0.5, -0.0000051}},
                    {{0.0, 0.0, 1.0}, {-0.6, 0.0, 0.8}, {0.00000004, -0.28, 0.96}},
                    ""});
  return pieces;
}

TEST(RuledReader, ReadsBackWhatTheWriterWrote) {
  const std::vector<RuledPiece> pieces = example_pieces();
  RuledProgramOptions o;
  o.feed_mm_min = 750.0;
  o.header = {"test program"};
  const std::vector<std::string> lines = ruled_program_lines(pieces, o);
  DiagnosticSink sink("rt.ngc");
  const std::vector<RuledGroup> groups = read_ruled_groups(join(lines), sink);
  ASSERT_FALSE(sink.has_errors()) << format_diagnostic(sink.take().front());
  ASSERT_EQ(groups.size(), pieces.size());
  std::size_t line_index = 0;
  for (std::size_t i = 0; i < pieces.size(); ++i) {
    const RuledGroup& g = groups[i];
    EXPECT_EQ(g.feed, 750.0);
    // the G5.4 line is where the writer put it
    while (line_index < lines.size() && lines[line_index].rfind("G5.4", 0) != 0) ++line_index;
    EXPECT_EQ(g.line, static_cast<int>(line_index) + 1);
    ++line_index;
    ASSERT_EQ(g.points.size(), pieces[i].points.size());
    for (std::size_t k = 0; k < g.points.size(); ++k) {
      EXPECT_EQ(g.point_lines[k], g.line + 1 + static_cast<int>(k));
      for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(g.points[k][c], pieces[i].points[k][c], 0.5e-5 + 1e-12) << i << " " << k;
        // the axis: the writer's unit vector to 7 decimals, normalised again here
        EXPECT_NEAR(g.axes[k][c], normalized(pieces[i].axes[k])[c], 1.5e-7) << i << " " << k;
      }
      EXPECT_NEAR(norm(g.axes[k]), 1.0, 1e-15);
    }
  }
}

TEST(RuledReader, APieceReadBackRunsOnTheFollower) {
  const std::vector<RuledPiece> pieces = example_pieces();
  DiagnosticSink sink("rt.ngc");
  const std::vector<RuledGroup> groups = read_ruled_groups(join(ruled_program_lines(pieces, {})), sink);
  ASSERT_FALSE(groups.empty());
  const RuledModelResult m = ruled_model_through(groups[0].points, groups[0].axes, RulingForm::kVector);
  ASSERT_EQ(m.error, "");
  const std::vector<RuledModel> parts = split_for_blocks(m.model);
  Kinematics kin;
  kin.kind = KinematicsKind::kTableTable;
  RuledFollower f;
  Joints q = inverse(kin, {groups[0].points[0], groups[0].axes[0]}, Joints{});
  double carry = 0.0;
  for (std::size_t b = 0; b < parts.size(); ++b) {
    RuledGeometry g;
    ASSERT_EQ(to_geometry(parts[b], groups[0].feed / 60.0, 1000.0, b == 0 ? 0.0 : 10.0,
                          b + 1 == parts.size() ? 0.0 : 10.0, g),
              "");
    f.start(g, kin, RotaryTravel{}, q, carry);
    while (!f.done()) f.step(g, 0.0005);
    q = f.sample().q;
    carry = f.leftover();
  }
  EXPECT_LE(norm(f.sample().motion.position - groups[0].points.back()), 1e-12);
  EXPECT_LE(norm(f.sample().motion.A - groups[0].axes.back()), 1e-12);
}

// The first error of reading `text` as "file:line:col: error: message".
std::string first_error(const std::string& text, std::size_t* groups_read = nullptr) {
  DiagnosticSink sink("p.ngc");
  const std::vector<RuledGroup> g = read_ruled_groups(text, sink);
  if (groups_read) *groups_read = g.size();
  if (!sink.has_errors()) return "";
  return format_diagnostic(sink.take().front());
}

const std::string kHead = "G21 G90 G94\nM428\n";  // lines 1-2
const std::string kP1 = "X0 Y0 Z0 I0 J0 K1\n";
const std::string kP2 = "X1 Y0 Z0 I0 J0.6 K0.8\n";

TEST(RuledReader, RefusesWhatTheFormForbids) {
  struct Case {
    std::string text, want;
  };
  const std::vector<Case> cases = {
      {"G21 G90 G94\nG5.4 F600\n" + kP1 + kP2 + "G5.5\n",
       "p.ngc:2:1: error: G5.4 needs tool-centre-point control (M428 or G43.4)"},
      {kHead + "M429\nG5.4 F600\n" + kP1 + kP2 + "G5.5\n", "p.ngc:4:1: error: G5.4 needs tool-centre-point"},
      {kHead + "G91\nG5.4 F600\n" + kP1 + kP2 + "G5.5\n", "p.ngc:4:1: error: G5.4 under G91"},
      {kHead + "G93\nG5.4 F600\n" + kP1 + kP2 + "G5.5\n", "p.ngc:4:1: error: G5.4 needs G94"},
      {"G21 G90 G94\nM428\nG5.4\n" + kP1 + kP2 + "G5.5\n", "p.ngc:3:1: error: G5.4 without a feed"},
      {kHead + "G5.4 F0\n" + kP1 + kP2 + "G5.5\n", "p.ngc:3:6: error: G5.4 with F0: the feed must be positive"},
      {kHead + "G5.4 F600 X3\n" + kP1 + kP2 + "G5.5\n", "p.ngc:3:11: error: X on the G5.4 line"},
      {kHead + "G5.4 F600\nX0 Y0 Z0 I0 J0\n" + kP2 + "G5.5\n", "p.ngc:4:1: error: set point without K"},
      {kHead + "G5.4 F600\n" + kP1 + "X1 Y0 Z0 I0 J0.5 K0.8\nG5.5\n",
       "p.ngc:5:10: error: tool vector I J K of length 0.9434: expected a unit vector"},
      {kHead + "G5.4 F600\n" + kP1 + "X1 Y0 Z0 I0 J0 K1 A3\nG5.5\n", "p.ngc:5:19: error: A inside a G5.4 group"},
      {kHead + "G5.4 F600\n" + kP1 + "G1 X1 Y0 Z0 I0 J0 K1\nG5.5\n",
       "p.ngc:5:1: error: G1 inside the G5.4 group opened at line 3"},
      {kHead + "G5.4 F600\n" + kP1 + kP2 + "M2\n", "p.ngc:6:1: error: M2 inside the G5.4 group opened at line 3"},
      // a code far beyond any (found by fuzzing: it overflowed the int it was rounded into)
      {kHead + "G5.4 F600\n" + kP1 + "G888888888\n" + kP2 + "G5.5\n",
       "p.ngc:5:1: error: G888888888 inside the G5.4 group opened at line 3"},
      {kHead + "G5.4 F600\n" + kP1 + kP2, "p.ngc:3: error: the G5.4 group opened here is not closed by G5.5"},
      {kHead + "G5.4 F600\n" + kP1 + "G5.5\n", "p.ngc:5:1: error: the G5.4 group opened at line 3 has 1 set point"},
      {kHead + "G5.4 F600\n" + kP1 + "X0 Y0 Z0.0000001 I0 J0 K1\nG5.5\n",
       "p.ngc:5:1: error: set point at the one before (line 4)"},
      {kHead + "G5.5\n", "p.ngc:3:1: error: G5.5 without a G5.4 group to close"},
      {kHead + "G5.2 X0 Y0 P1 L4\nX1 Y1 P1\nG5.4 F600\n" + kP1 + kP2 + "G5.5\n",
       "p.ngc:5:1: error: G5.4 inside a NURBS group (G5.2 ... G5.3)"},
      {kHead + "G5.4 F600\n" + kP1 + "G5.4\n" + kP2 + "G5.5\n",
       "p.ngc:5:1: error: G5.4 inside the G5.4 group opened at line 3"},
      {kHead + "G5.4 F600\n" + kP1 + kP2 + "G5.5 X2\n", "p.ngc:6:6: error: X on the G5.5 line"},
      {kHead + "G5.4 F600\n" + kP1 + "X1 X1 Y0 Z0 I0 J0 K1\nG5.5\n", "p.ngc:5:4: error: two X words on one set point"},
      {kHead + "G5.4 F600\n" + kP1 + "X1 Y0 Z0 I0 J0 K1 F300\nG5.5\n", "p.ngc:5:19: error: F on a set point"},
  };
  for (const Case& c : cases) {
    std::size_t read = 99;
    const std::string got = first_error(c.text, &read);
    EXPECT_EQ(got.substr(0, c.want.size()), c.want) << c.text;
    EXPECT_EQ(read, 0u) << "a group with an error is left out: " << c.text;
  }
}

TEST(RuledReader, AcceptsLineNumbersCommentsAndAModalFeed) {
  const std::string text = "G21 G90 G94 F480\nM428\nN10 G5.4 (first)\nN11 X0 Y0 Z0 I0 J0 K1 (start)\n(a comment)\n"
                           "N12 X1 Y0 Z0 I0 J0.6 K0.8\nN13 G5.5 (end)\nG43.4\nG5.4 F600\n" + kP2 + "X2 Y0 Z0 I0 J0 K1.0005\nG5.5\n";
  DiagnosticSink sink("p.ngc");
  const std::vector<RuledGroup> g = read_ruled_groups(text, sink);
  ASSERT_FALSE(sink.has_errors()) << format_diagnostic(sink.take().front());
  ASSERT_EQ(g.size(), 2u);
  EXPECT_EQ(g[0].feed, 480.0);
  EXPECT_EQ(g[0].line, 3);
  EXPECT_EQ(g[0].point_lines, (std::vector<int>{4, 6}));
  EXPECT_EQ(g[1].feed, 600.0);
  EXPECT_NEAR(g[1].axes[1][2], 1.0, 1e-15);  // within 0.001 of unit: normalised
}

TEST(RuledReader, ABadGroupDoesNotStopTheNextOne) {
  const std::string text = kHead + "G5.4 F600\n" + kP1 + "X1 Y0 Z0 I0 J0 K2\nG5.5\nG5.4 F600\n" + kP1 + kP2 + "G5.5\n";
  DiagnosticSink sink("p.ngc");
  const std::vector<RuledGroup> g = read_ruled_groups(text, sink);
  EXPECT_EQ(sink.error_count(), 1u);
  ASSERT_EQ(g.size(), 1u);
  EXPECT_EQ(g[0].line, 7);
  EXPECT_EQ(g[0].points.size(), 2u);
}

}  // namespace
}  // namespace pcnc
