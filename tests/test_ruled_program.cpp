// test_ruled_program.cpp — the G5.4 ... G5.5 writer and the JSON form (tools/ruled_program.hpp):
// the program's order of lines, every set point read back within its printed precision, axes
// written normalised, no "-0" words, and the JSON form read back exactly.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "ruled_program.hpp"

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

TEST(RuledProgram, JsonFileFormRefusesWhatTheGcodeFormRefuses) {
  const std::string head = R"({"format": "pcnc-ruled-program", "version": 1, "units": "mm", "feed_mm_min": 600, "pieces": )";
  const std::string ok_piece = R"({"points": [[0, 0, 0], [1, 0, 0]], "axes": [[0, 0, 1], [0, 0, 1]]})";
  ASSERT_EQ(read_ruled_program_json(head + "[" + ok_piece + "]}", "p.json").error, "");
  const std::pair<std::string, std::string> cases[] = {
      {"{", "p.json: not JSON"},
      {head + "[" + ok_piece + "], \"extra\": 1}", "p.json: the file: unknown key 'extra'"},
      {R"({"format": "x", "version": 1, "units": "mm", "feed_mm_min": 600, "pieces": []})", "p.json: format \"x\""},
      {R"({"format": "pcnc-ruled-program", "version": 2, "units": "mm", "feed_mm_min": 600, "pieces": []})", "p.json: version 2"},
      {R"({"format": "pcnc-ruled-program", "version": 1, "units": "in", "feed_mm_min": 600, "pieces": []})", "p.json: units \"in\""},
      {R"({"format": "pcnc-ruled-program", "version": 1, "units": "mm", "feed_mm_min": 0, "pieces": []})", "p.json: feed_mm_min 0"},
      {head + "[]}", "p.json: pieces: expected a non-empty array"},
      {head + R"([{"points": [[0, 0, 0]], "axes": [[0, 0, 1]]}]})", "p.json: piece 1: expected at least 2 set points"},
      {head + R"([{"points": [[0, 0, 0], [1, 0, 0]], "axes": [[0, 0, 1]]}]})", "p.json: piece 1: expected arrays"},
      {head + R"([{"points": [[0, 0, 0], [1, 0]], "axes": [[0, 0, 1], [0, 0, 1]]}]})", "p.json: piece 1, set point 2: expected three numbers"},
      {head + R"([{"points": [[0, 0, 0], [1, 0, 0]], "axes": [[0, 0, 1], [0, 0, 0.9]]}]})",
       "p.json: piece 1, set point 2: tool vector of length 0.9: expected a unit vector"},
      {head + R"([{"points": [[0, 0, 0], [0, 0, 1e-7]], "axes": [[0, 0, 1], [0, 0, 1]]}]})",
       "p.json: piece 1, set point 2: less than 1e-6 mm"},
      {head + R"([{"points": [[0, 0, 0], [1, 0, 0]], "axes": [[0, 0, 1], [0, 0, 1]], "comment": "x"}]})",
       "p.json: piece 1: unknown key 'comment'"},
      {head + "[" + ok_piece + R"(, {"points": [[2, 0, 0], [3, 0, 0]], "axes": [[0, 0, 1], [0, 0, 1]]}]})",
       "p.json: piece 2: does not start where piece 1 ended"},
  };
  for (const auto& [text, want] : cases) {
    const RuledJsonProgram r = read_ruled_program_json(text, "p.json");
    EXPECT_EQ(r.error.rfind(want, 0), 0u) << r.error << " | want: " << want;
    EXPECT_TRUE(r.pieces.empty());
  }
}

}  // namespace
}  // namespace pcnc
