// test_ruled_program.cpp — the G5.4 ... G5.5 writer and the JSON form (host/gcode/ruled_program.hpp):
// the program's order of lines, every set point read back within its printed precision, axes
// written normalised, no "-0" words, and the JSON form read back exactly.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "gcode/ruled_program.hpp"

namespace pcnc {
namespace {

std::vector<RuledPiece> sample_pieces() {
  RuledPiece a{{{1, 2, 5}, {1, 2, -3.25}}, {{0, 0, 1}, {0.1, -0.2, 2.0}}, "approach"};  // second axis not unit
  RuledPiece b{{{1, 2, -3.25}, {1.123456789, 3, -3.5}, {1.2, 4, -3.6}},
               {{0.1, -0.2, 2.0}, {-1e-9, 0.05, 0.99875}, {0, 0.1, 0.99498743710662}},
               ""};
  return {a, b};
}

TEST(RuledProgram, LinesInOrderAndReadBack) {
  RuledProgramOptions o;
  o.feed_mm_min = 450.0;
  o.clearance_z = 5.0;
  o.header = {"first", "second"};
  const std::vector<RuledPiece> pieces = sample_pieces();
  const std::vector<std::string> l = ruled_program_lines(pieces, o);
  ASSERT_EQ(l.size(), 2u + 4u + (2 + 2) + (2 + 3) + 3u);
  EXPECT_EQ(l[0], "(first)");
  EXPECT_EQ(l[1], "(second)");
  EXPECT_EQ(l[2], "G21 G90 G17 G94");
  EXPECT_EQ(l[3].rfind("M428", 0), 0u);
  EXPECT_EQ(l[4], "G0 Z5.00000");
  EXPECT_EQ(l[5], "G0 X1.00000 Y2.00000");
  EXPECT_EQ(l[6], "G5.4 F450.000 (approach)");
  EXPECT_EQ(l[9], "G5.5");
  EXPECT_EQ(l[10], "G5.4 F450.000");
  EXPECT_EQ(l[14], "G5.5");
  EXPECT_EQ(l[15], "G0 Z5.00000");
  EXPECT_EQ(l[16].rfind("M429", 0), 0u);
  EXPECT_EQ(l[17], "M2");
  // every set point read back
  const int at[2] = {7, 11};
  for (int p = 0; p < 2; ++p)
    for (std::size_t i = 0; i < pieces[p].points.size(); ++i) {
      const std::string& line = l[at[p] + i];
      double x, y, z, a, b, c;
      ASSERT_EQ(std::sscanf(line.c_str(), "X%lf Y%lf Z%lf I%lf J%lf K%lf", &x, &y, &z, &a, &b, &c), 6) << line;
      const Vec3 pt = pieces[p].points[i];
      const Vec3 ax = normalized(pieces[p].axes[i]);
      EXPECT_NEAR(x, pt[0], 5e-6);
      EXPECT_NEAR(y, pt[1], 5e-6);
      EXPECT_NEAR(z, pt[2], 5e-6);
      EXPECT_NEAR(a, ax[0], 5e-8);
      EXPECT_NEAR(b, ax[1], 5e-8);
      EXPECT_NEAR(c, ax[2], 5e-8);
      EXPECT_NEAR(std::sqrt(a * a + b * b + c * c), 1.0, 1e-7);
      EXPECT_EQ(line.find("-0.0000000 "), std::string::npos) << line;
      EXPECT_EQ(line.find("I-0.0000000"), std::string::npos) << line;
    }
  EXPECT_EQ(l[12], "X1.12346 Y3.00000 Z-3.50000 I0.0000000 J0.0500000 K0.9987492");  // -1e-9 is not "-0"
}


TEST(RuledProgram, TurnsTheJointsWithTcpOffBeforeM428AndBackAfterM429) {
  RuledProgramOptions o;
  o.clearance_z = 5.0;
  o.header = {"a (nested) comment"};
  o.turn_joints = "A4.5 C90";
  o.turn_back = "A0 C0";
  const std::vector<std::string> l = ruled_program_lines(sample_pieces(), o);
  ASSERT_EQ(l.size(), 1u + 5u + (2 + 2) + (2 + 3) + 4u);
  EXPECT_EQ(l[0], "(a [nested] comment)");
  EXPECT_EQ(l[1], "G21 G90 G17 G94");
  EXPECT_EQ(l[2], "G0 A4.5 C90 (the tool axis of the first set point, TCP off)");
  EXPECT_EQ(l[3].rfind("M428", 0), 0u);
  EXPECT_EQ(l[4], "G0 Z5.00000");
  EXPECT_EQ(l[5], "G0 X1.00000 Y2.00000");
  EXPECT_EQ(l[6], "G5.4 F600.000 (approach)");
  EXPECT_EQ(l[15], "G0 Z5.00000");
  EXPECT_EQ(l[16].rfind("M429", 0), 0u);
  EXPECT_EQ(l[17], "G0 A0 C0");
  EXPECT_EQ(l[18], "M2");
}

TEST(RuledProgram, JsonReadsBackExactly) {
  const std::vector<RuledPiece> pieces = sample_pieces();
  const nlohmann::json j = nlohmann::json::parse(ruled_program_json(pieces, 450.0));
  EXPECT_EQ(j.at("format"), "pcnc-ruled-program");
  EXPECT_EQ(j.at("version"), 1);
  EXPECT_EQ(j.at("units"), "mm");
  EXPECT_EQ(j.at("feed_mm_min").get<double>(), 450.0);
  ASSERT_EQ(j.at("pieces").size(), 2u);
  for (std::size_t p = 0; p < 2; ++p)
    for (std::size_t i = 0; i < pieces[p].points.size(); ++i) {
      const Vec3 ax = normalized(pieces[p].axes[i]);
      for (int k = 0; k < 3; ++k) {
        EXPECT_EQ(j["pieces"][p]["points"][i][k].get<double>(), pieces[p].points[i][k]);
        EXPECT_EQ(j["pieces"][p]["axes"][i][k].get<double>(), ax[k]);
      }
    }
}

TEST(RuledProgram, JsonFileFormReadsBackAsThePieces) {
  // pieces that join (the reader asks for it): the second starts where the first ends
  std::vector<RuledPiece> pieces = sample_pieces();
  pieces[1].points.front() = pieces[0].points.back();
  pieces[1].axes.front() = pieces[0].axes.back();
  const RuledJsonProgram r = read_ruled_program_json(ruled_program_json(pieces, 450.0), "p.json");
  ASSERT_EQ(r.error, "");
  EXPECT_EQ(r.feed_mm_min, 450.0);
  ASSERT_EQ(r.pieces.size(), 2u);
  for (std::size_t p = 0; p < 2; ++p) {
    ASSERT_EQ(r.pieces[p].points.size(), pieces[p].points.size());
    for (std::size_t i = 0; i < pieces[p].points.size(); ++i) {
      EXPECT_EQ(r.pieces[p].points[i], pieces[p].points[i]);
      EXPECT_LT(norm(r.pieces[p].axes[i] - normalized(pieces[p].axes[i])), 1e-15);
    }
  }
}

// Each refusal names the file, the line and column where the value at fault starts, and its
// key path; nothing is read then.
TEST(RuledProgram, JsonFileFormRefusesWhatTheGcodeFormRefusesAtThePlace) {
  const std::string head = R"({"format": "pcnc-ruled-program", "version": 1, "units": "mm", "feed_mm_min": 600, "pieces": )";
  const std::string ok_piece = R"({"points": [[0, 0, 0], [1, 0, 0]], "axes": [[0, 0, 1], [0, 0, 1]]})";
  ASSERT_EQ(read_ruled_program_json(head + "[" + ok_piece + "]}", "p.json").error, "");
  struct Case {
    std::string text;
    std::string anchor;  // the value at fault: its last occurrence in the text (empty: column 1)
    std::string want;    // after "p.json:1:<col>: error: "
  };
  const Case cases[] = {
      {head + "[" + ok_piece + "], \"extra\": 1}", "", "the file: unknown key 'extra'"},
      {R"({"format": "x", "version": 1, "units": "mm", "feed_mm_min": 600, "pieces": []})", R"("x")", "format: \"x\": expected"},
      {R"({"format": "pcnc-ruled-program", "version": 2, "units": "mm", "feed_mm_min": 600, "pieces": []})", "2,", "version: 2: expected 1"},
      {R"({"format": "pcnc-ruled-program", "version": 1, "units": "in", "feed_mm_min": 600, "pieces": []})", R"("in")", "units: \"in\""},
      {R"({"format": "pcnc-ruled-program", "version": 1, "units": "mm", "feed_mm_min": 0, "pieces": []})", "0,", "feed_mm_min: 0: expected a number > 0"},
      {head + "[]}", "[]", "pieces: expected a non-empty array"},
      {head + R"([{"points": [[0, 0, 0]], "axes": [[0, 0, 1]]}]})", "[[0, 0, 0]]", "pieces[0].points: expected at least 2 set points"},
      {head + R"([{"points": [[0, 0, 0], [1, 0, 0]], "axes": [[0, 0, 1]]}]})", R"({"points")",
       "pieces[0]: expected arrays 'points' and 'axes' of the same length (2 and 1)"},
      {head + R"([{"points": [[0, 0, 0], [1, 0]], "axes": [[0, 0, 1], [0, 0, 1]]}]})", "[1, 0]",
       "pieces[0].points[1]: expected three numbers"},
      {head + R"([{"points": [[0, 0, 0], [1, 0, 0]], "axes": [[0, 0, 1], [0, 0, 0.9]]}]})", "[0, 0, 0.9]",
       "pieces[0].axes[1]: tool vector of length 0.9: expected a unit vector"},
      {head + R"([{"points": [[0, 0, 0], [0, 0, 1e-7]], "axes": [[0, 0, 1], [0, 0, 1]]}]})", "[0, 0, 1e-7]",
       "pieces[0].points[1]: less than 1e-6 mm"},
      {head + R"([{"points": [[0, 0, 0], [1, 0, 0]], "axes": [[0, 0, 1], [0, 0, 1]], "comment": "x"}]})", R"({"points")",
       "pieces[0]: unknown key 'comment'"},
      {head + "[" + ok_piece + R"(, {"points": [[2, 0, 0], [3, 0, 0]], "axes": [[0, 0, 1], [0, 0, 1]]}]})",
       R"({"points": [[2)", "pieces[1]: does not start where pieces[0] ended"},
  };
  for (const Case& c : cases) {
    const RuledJsonProgram r = read_ruled_program_json(c.text, "p.json");
    const std::size_t col = c.anchor.empty() ? 1 : c.text.rfind(c.anchor) + 1;
    const std::string want = "p.json:1:" + std::to_string(col) + ": error: " + c.want;
    EXPECT_EQ(r.error.rfind(want, 0), 0u) << r.error << " | want: " << want;
    EXPECT_EQ(r.refusal.line, 1);
    EXPECT_EQ(r.refusal.column, static_cast<int>(col));
    EXPECT_TRUE(r.pieces.empty());
  }
  // over several lines: the line and column of the value; a text that is not JSON: where the parser stopped
  const std::string multi = head + "[\n" + ok_piece + ",\n  {\"points\": [[1, 0, 0],\n     [1, 0]], \"axes\": [[0, 0, 1], [0, 0, 1]]}]}";
  EXPECT_EQ(read_ruled_program_json(multi, "p.json").error.rfind("p.json:4:6: error: pieces[1].points[1]: expected three numbers", 0), 0u)
      << read_ruled_program_json(multi, "p.json").error;
  const RuledJsonProgram bad = read_ruled_program_json("{\"format\": \"pcnc-ruled-program\",\n \"version\" 1}", "p.json");
  EXPECT_EQ(bad.error.rfind("p.json:2:", 0), 0u) << bad.error;
  EXPECT_NE(bad.error.find("the file: not JSON: syntax error"), std::string::npos) << bad.error;
}

// Where each piece, set point and first tool vector stands, for the front end's messages.
TEST(RuledProgram, JsonFileFormKnowsWhereEachValueStands) {
  const std::string text = "{\"format\": \"pcnc-ruled-program\", \"version\": 1, \"units\": \"mm\", \"feed_mm_min\": 600,\n"
                           " \"pieces\": [\n"
                           "  {\"axes\": [[0, 0, 1], [0, 0, 1]],\n"
                           "   \"points\": [[0, 0, 0], [1, 0, 0]]},\n"
                           "  {\"points\": [[1, 0, 0],\n"
                           "              [2, 0, 0]], \"axes\": [[0, 0, 1], [0, 0, 1]]}]}\n";
  const RuledJsonProgram r = read_ruled_program_json(text, "p.json");
  ASSERT_EQ(r.error, "");
  ASSERT_EQ(r.places.size(), 2u);
  auto is = [](const JsonPlace& p, const char* path, int line, int column) {
    return p.path == path && p.line == line && p.column == column;
  };
  EXPECT_TRUE(is(r.places[0].piece, "pieces[0]", 3, 3));
  EXPECT_TRUE(is(r.places[0].first_axis, "pieces[0].axes[0]", 3, 13));
  EXPECT_TRUE(is(r.places[0].points[1], "pieces[0].points[1]", 4, 26));
  EXPECT_TRUE(is(r.places[1].piece, "pieces[1]", 5, 3));
  EXPECT_TRUE(is(r.places[1].points[0], "pieces[1].points[0]", 5, 15));
  EXPECT_TRUE(is(r.places[1].points[1], "pieces[1].points[1]", 6, 15));
  EXPECT_TRUE(is(r.places[1].first_axis, "pieces[1].axes[0]", 6, 36));
  EXPECT_EQ(r.text_lines, 7u);
}

}  // namespace
}  // namespace pcnc
