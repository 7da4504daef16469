// test_parser.cpp — modal-group sorting: one word per group and per letter, known codes only.
#include <gtest/gtest.h>

#include "gcode/parser.hpp"

namespace pcnc {
namespace {

struct Parsed {
  bool ok;
  ParsedLine line;
  std::vector<Diagnostic> diags;
};

Parsed parse(const std::string& text) {
  DiagnosticSink sink("t.ngc");
  LexedLine lexed;
  Parsed r{};
  r.ok = lex_line(text, 3, lexed, sink) && parse_line(lexed, 3, r.line, sink);
  r.diags = sink.take();
  return r;
}

TEST(Parser, GroupsGAndMWords) {
  const Parsed r = parse("G90 G17 G21 G0 G54 M3 M8 X1 F100");
  ASSERT_TRUE(r.ok);
  EXPECT_EQ(r.line.g[kGDistance], 900);
  EXPECT_EQ(r.line.g[kGPlane], 170);
  EXPECT_EQ(r.line.g[kGUnits], 210);
  EXPECT_EQ(r.line.g[kGMotion], 0);
  EXPECT_EQ(r.line.g[kGCoordSystem], 540);
  EXPECT_EQ(r.line.g[kGNonModal], -1);
  EXPECT_EQ(r.line.m[kMSpindle], 3);
  EXPECT_EQ(r.line.m[kMCoolant], 8);
  EXPECT_TRUE(r.line.has('X'));
  EXPECT_TRUE(r.line.has('F'));
  EXPECT_FALSE(r.line.has('Y'));
  EXPECT_DOUBLE_EQ(r.line.get('F'), 100);
  EXPECT_EQ(r.line.column('X'), 26);
}

TEST(Parser, DecimalGCodes) {
  const Parsed r = parse("G91.1 G5.2 G43 H1");
  ASSERT_TRUE(r.ok);
  EXPECT_EQ(r.line.g[kGArcDistance], 911);
  EXPECT_EQ(r.line.g[kGMotion], 52);
  EXPECT_EQ(r.line.g[kGToolLength], 430);
  EXPECT_EQ(g_name(911), "G91.1");
  EXPECT_EQ(g_name(10), "G1");
}

TEST(Parser, GroupTables) {
  EXPECT_EQ(g_group(40), kGNonModal);
  EXPECT_EQ(g_group(280), kGNonModal);
  EXPECT_EQ(g_group(530), kGNonModal);
  EXPECT_EQ(g_group(830), kGMotion);
  EXPECT_EQ(g_group(62), kGMotion);
  EXPECT_EQ(g_group(640), kGPathControl);
  EXPECT_EQ(g_group(120), -1);
  EXPECT_EQ(m_group(30), kMStop);
  EXPECT_EQ(m_group(21), kMContouring);
  EXPECT_EQ(m_group(150), kMOther);
  EXPECT_EQ(m_group(12), -1);
}

TEST(Parser, G80NextToAMotionCodeKeepsTheMotion) {
  const Parsed r = parse("G80 G0 X1");
  ASSERT_TRUE(r.ok);
  EXPECT_EQ(r.line.g[kGMotion], 0);
  EXPECT_EQ(r.line.g80_col, 1);
}

struct ParseErrorCase {
  const char* text;
  const char* fragment;
  int column;
};

class ParseErrors : public ::testing::TestWithParam<ParseErrorCase> {};

TEST_P(ParseErrors, Reported) {
  const ParseErrorCase& c = GetParam();
  const Parsed r = parse(c.text);
  EXPECT_FALSE(r.ok);
  ASSERT_EQ(r.diags.size(), 1u) << c.text;
  EXPECT_NE(r.diags[0].message.find(c.fragment), std::string::npos) << r.diags[0].message;
  EXPECT_NE(r.diags[0].message.find("expected"), std::string::npos) << r.diags[0].message;
  EXPECT_EQ(r.diags[0].column, c.column) << c.text;
}

INSTANTIATE_TEST_SUITE_P(
    Table, ParseErrors,
    ::testing::Values(ParseErrorCase{"G0 G1", "same modal group", 4}, ParseErrorCase{"G17 G18", "same modal group", 5},
                      ParseErrorCase{"G54 G55", "same modal group", 5}, ParseErrorCase{"G4 G53", "same modal group", 4},
                      ParseErrorCase{"M0 M30", "same modal group", 4}, ParseErrorCase{"M21 M22", "same modal group", 5},
                      ParseErrorCase{"X1 Y2 X3", "second X word", 7}, ParseErrorCase{"F1 F2", "second F word", 4},
                      ParseErrorCase{"G2.5", "unknown G code", 1}, ParseErrorCase{"G-1", "bad G number", 1},
                      ParseErrorCase{"G1.05", "bad G number", 1}, ParseErrorCase{"M3.5", "bad M number", 1},
                      ParseErrorCase{"M999", "unknown M code", 1}, ParseErrorCase{"G99999", "bad G number", 1}));

}  // namespace
}  // namespace pcnc
