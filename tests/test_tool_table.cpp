// test_tool_table.cpp — LinuxCNC-format tool tables (gcode/tool_table.hpp): LinuxCNC's own
// sample tables (mill, lathe, as its tool editor writes them), comments and blank lines,
// every kind of error with its line and column, lookups and changes, the written form read
// back, and the shipped sample table.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <unistd.h>

#include "gcode/tool_table.hpp"
#include "test_paths.hpp"

namespace pcnc {
namespace {

ToolTable parsed(const std::string& text) {
  ToolTable t;
  std::vector<std::string> errors;
  EXPECT_TRUE(parse_tool_table(text, "t.tbl", t, errors));
  for (const auto& e : errors) ADD_FAILURE() << e;
  return t;
}

std::vector<std::string> errors_of(const std::string& text) {
  ToolTable t;
  std::vector<std::string> errors;
  EXPECT_FALSE(parse_tool_table(text, "t.tbl", t, errors)) << text;
  return errors;
}

// One error whose text starts with `where` ("t.tbl:line:col: error: ") and holds `what`.
void expect_one_error(const std::string& text, const std::string& where, const std::string& what) {
  const auto e = errors_of(text);
  ASSERT_EQ(e.size(), 1u) << text;
  EXPECT_EQ(e[0].rfind("t.tbl:" + where + ": error: ", 0), 0u) << e[0];
  EXPECT_NE(e[0].find(what), std::string::npos) << e[0];
}

TEST(ToolTable, LinuxCncSimMillTable) {
  // LinuxCNC's configs/sim tool.tbl (inch values there; this table's numbers are read as mm).
  const ToolTable t = parsed(
      "T1 P1 D0.125000 Z+0.511000 ;1/8 end mill\n"
      "T2 P2 D0.062500 Z+0.100000 ;1/16 end mill\n"
      "T3 P3 D0.201000 Z+1.273000 ;#7 tap drill\n"
      "T99999 P99999 Z+0.100000 ;big tool number\n");
  ASSERT_EQ(t.size(), 4u);
  const ToolEntry* t3 = t.find(3);
  ASSERT_NE(t3, nullptr);
  EXPECT_EQ(t3->pocket, 3);
  EXPECT_DOUBLE_EQ(t3->diameter, 0.201);
  EXPECT_EQ(t3->offset, (Vec3{0.0, 0.0, 1.273}));
  EXPECT_EQ(t3->comment, "#7 tap drill");
  EXPECT_EQ(t3->line, 3);
  EXPECT_EQ(t.find(99999)->pocket, 99999);
  EXPECT_EQ(t.find(99999)->diameter, 0.0);
  EXPECT_EQ(t.find(4), nullptr);
  EXPECT_EQ(t.tools().front().number, 1) << "file order";
}

TEST(ToolTable, LinuxCncLatheTableKeepsTheLatheWords) {
  const ToolTable t = parsed(
      "T1 P1 X0 Z0 D0.1 I95 J155 Q9 ;right hand turning\n"
      "T2 P2 X-0.5 Z+1.25 D0.4 I-85 J-5 Q2\n");
  const ToolEntry* t1 = t.find(1);
  ASSERT_NE(t1, nullptr);
  EXPECT_EQ(t1->front_angle, 95.0);
  EXPECT_EQ(t1->back_angle, 155.0);
  EXPECT_EQ(t1->orientation, 9);
  EXPECT_EQ(t.find(2)->offset, (Vec3{-0.5, 0.0, 1.25}));
  EXPECT_EQ(t.find(2)->front_angle, -85.0);
  EXPECT_EQ(t.find(2)->comment, "");
}

TEST(ToolTable, AsLinuxCncWritesIt) {
  // tooldata_format_toolline: "T%-3d P%-3d", then signed %f words, then " ;comment"; every
  // axis word when zero values are not left out; lower-case letters are read too.
  const ToolTable t = parsed(
      "T1   P1   D+3.175000 X0 Y0 Z+12.700000 A0 B0 C0 U0 V0 W+0.500000 I0 J0 Q0 ;flat\n"
      "t2 p5 z-1.5 d6 a+1 b+2 c+3 u+4 v+5\n");
  EXPECT_EQ(t.find(1)->offset[2], 12.7);
  EXPECT_EQ(t.find(1)->abcuvw, (std::array<double, 6>{0, 0, 0, 0, 0, 0.5}));
  EXPECT_EQ(t.find(2)->pocket, 5);
  EXPECT_EQ(t.find(2)->diameter, 6.0);
  EXPECT_EQ(t.find(2)->abcuvw, (std::array<double, 6>{1, 2, 3, 4, 5, 0}));
}

TEST(ToolTable, CommentsBlankLinesAndLineEndings) {
  const ToolTable t = parsed(
      "; a tool table\n"
      "\n"
      "   \t \n"
      "  ;indented comment\n"
      "T7\tP2\tZ1 D2;no blank before the comment ; a second ';' stays in it\r\n"
      "T8 P3 ;\n"
      "T9");  // no newline at the end
  ASSERT_EQ(t.size(), 3u);
  EXPECT_EQ(t.find(7)->comment, "no blank before the comment ; a second ';' stays in it");
  EXPECT_EQ(t.find(7)->line, 5);
  EXPECT_EQ(t.find(7)->diameter, 2.0);
  EXPECT_EQ(t.find(8)->comment, "");
  EXPECT_EQ(t.find(9)->line, 7);
  EXPECT_EQ(t.find(9)->pocket, 0) << "P is optional";
  EXPECT_TRUE(parsed("").empty());
  EXPECT_TRUE(parsed("\n;only comments\n").empty());
}

TEST(ToolTable, ErrorsSayWhereAndWhatWasExpected) {
  expect_one_error("T1 P1\nP2 Z3 ;no tool number\n", "2:1", "missing T: expected the tool number");
  expect_one_error("T1 P1 Z1\nT2 P2\nT1 P3 D4\n", "3:1", "tool T1 is already defined at line 1");
  expect_one_error("P3 T1 Z1\nP4  T1\n", "2:5", "tool T1 is already defined at line 1");
  expect_one_error("T1 P1 K5\n", "1:7", "unknown word 'K5'; expected one of T P X Y Z A B C U V W D I J Q");
  expect_one_error("T1 12.5\n", "1:4", "unexpected '12.5'");
  expect_one_error("T1 (comment)\n", "1:4", "unexpected '(comment)'");
  expect_one_error("T1.5 P1\n", "1:1", "bad number 'T1.5': T takes a whole number");
  expect_one_error("T1 Pfour\n", "1:4", "bad number 'Pfour'");
  expect_one_error("T1 Z1..2\n", "1:4", "bad number 'Z1..2': expected a decimal number");
  expect_one_error("T1 Z 12.7\n", "1:4", "'Z' and its number '12.7' are apart; expected them together (Z12.7)");
  expect_one_error("T1 Z ;c\n", "1:4", "'Z' without a number");
  expect_one_error("T1 Znan\n", "1:4", "bad number 'Znan'");
  expect_one_error("T1 Z1e999\n", "1:4", "bad number 'Z1e999'");
  expect_one_error("T1 Z2e6\n", "1:4", "within ±1e6");
  expect_one_error("T1 D-3\n", "1:4", "diameter 'D-3' is negative");
  expect_one_error("T-1\n", "1:1", "tool number 'T-1' out of range");
  expect_one_error("T1 P-2\n", "1:4", "pocket 'P-2' out of range");
  expect_one_error("T1 Q10\n", "1:4", "expected Q0..Q9");
  expect_one_error("T1 T2\n", "1:4", "T given twice on one line (first at column 1)");
  expect_one_error("T99999999999999999999\n", "1:1", "bad number");
  EXPECT_EQ(parsed("T1 Z1.5e1").find(1)->offset[2], 15.0) << "an exponent is a decimal number too";
}

TEST(ToolTable, EveryErrorIsReportedAndNothingIsChangedOnFailure) {
  ToolTable t = parsed("T5 P5 D1\n");
  std::vector<std::string> errors{"earlier message"};
  EXPECT_FALSE(parse_tool_table("T1 P1\nX1\nT2 K3 Z?\nT1\n", "tools.tbl", t, errors));
  ASSERT_EQ(errors.size(), 5u);
  EXPECT_EQ(errors[0], "earlier message") << "appended, not replaced";
  EXPECT_EQ(errors[1], "tools.tbl:2:1: error: missing T: expected the tool number (e.g. T1) on every tool line");
  EXPECT_EQ(errors[2].rfind("tools.tbl:3:4: error: unknown word 'K3'", 0), 0u) << errors[2];
  EXPECT_EQ(errors[3].rfind("tools.tbl:3:7: error: bad number 'Z?'", 0), 0u) << errors[3];
  EXPECT_EQ(errors[4].rfind("tools.tbl:4:1: error: tool T1 is already defined at line 1", 0), 0u) << errors[4];
  ASSERT_EQ(t.size(), 1u) << "the table is left as it was";
  EXPECT_NE(t.find(5), nullptr);
}

TEST(ToolTable, ManyErrorsAreCapped) {
  std::string text;
  for (int i = 0; i < 500; ++i) text += "K1\n";
  const auto e = errors_of(text);
  EXPECT_LT(e.size(), 60u);
  EXPECT_NE(e.back().find("more errors not shown"), std::string::npos) << e.back();
}

TEST(ToolTable, SetReplacesInPlaceOrAppendsAndRemoveDeletes) {
  ToolTable t = parsed("T1 P1 D1\nT2 P2 D2\n");
  ToolEntry t1 = *t.find(1);
  t1.diameter = 1.5;
  t1.line = 0;
  t.set(t1);
  ASSERT_EQ(t.size(), 2u);
  EXPECT_EQ(t.tools()[0].diameter, 1.5);
  ToolEntry t9;
  t9.number = 9;
  t9.offset = {0, 0, 3};
  t.set(t9);
  ASSERT_EQ(t.size(), 3u);
  EXPECT_EQ(t.tools().back().number, 9);
  EXPECT_EQ(t.find(9)->offset[2], 3.0);
  EXPECT_TRUE(t.remove(2));
  EXPECT_FALSE(t.remove(2));
  EXPECT_EQ(t.find(2), nullptr);
  EXPECT_EQ(t.size(), 2u);
}

TEST(ToolTable, FormattedTableReadsBackTheSame) {
  const std::string text =
      "T1 P1 D6.35 Z+12.7 ;6.35 mm end mill\n"
      "T2 P7 X-0.1 Y0.2 Z-33.3333333333333 A1 B2 C3 U4 V5 W6 I95 J155 Q9\n"
      "T3 P3\n";
  const ToolTable t = parsed(text);
  const std::string out = format_tool_table(t);
  EXPECT_EQ(out.substr(0, out.find('\n')), "T1 P1 D+6.35 Z+12.7 ;6.35 mm end mill");
  ToolTable back = parsed(out);
  ASSERT_EQ(back.size(), t.size());
  for (std::size_t i = 0; i < t.size(); ++i) {
    ToolEntry a = t.tools()[i], b = back.tools()[i];
    a.line = b.line = 0;
    EXPECT_EQ(a, b) << i;
  }
}

TEST(ToolTable, LoadReadsAFileAndThrowsWithAllMessages) {
  const std::string sample = test::source_dir() + "/configs/desktop-mill.tbl";
  const ToolTable t = load_tool_table(sample);
  ASSERT_GE(t.size(), 3u);
  EXPECT_EQ(t.find(2)->diameter, 6.0);

  const std::string bad = (std::filesystem::temp_directory_path() / ("pcnc-bad-" + std::to_string(::getpid()) + ".tbl")).string();
  std::ofstream(bad) << "T1 P1\nT1 P2\nT3 Z\n";
  try {
    load_tool_table(bad);
    ADD_FAILURE() << "no exception";
  } catch (const std::runtime_error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find(bad + ":2:1: error: tool T1 is already defined"), std::string::npos) << m;
    EXPECT_NE(m.find("\n" + bad + ":3:4: error: 'Z' without a number"), std::string::npos) << m;
  }
  std::filesystem::remove(bad);
  try {
    load_tool_table(bad);
    ADD_FAILURE() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("cannot read the tool table '" + bad + "'"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace pcnc
