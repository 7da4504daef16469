// test_lexer.cpp — the line lexer: words, numbers, comments, spaces, expressions, errors.
#include <gtest/gtest.h>

#include <charconv>
#include <cmath>
#include <random>
#include <string>

#include "gcode/expression.hpp"
#include "gcode/lexer.hpp"

namespace pcnc {
namespace {

struct Lexed {
  bool ok;
  LexedLine line;
  std::vector<Diagnostic> diags;
};

Lexed lex(const std::string& text) {
  DiagnosticSink sink("t.ngc");
  Lexed r{};
  r.ok = lex_line(text, 7, r.line, sink);
  r.diags = sink.take();
  return r;
}

struct WordCase {
  const char* text;
  const char* letters;  // expected letters in order
  std::vector<double> values;
};

class LexWords : public ::testing::TestWithParam<WordCase> {};

TEST_P(LexWords, Words) {
  const WordCase& c = GetParam();
  const Lexed r = lex(c.text);
  ASSERT_TRUE(r.ok) << c.text << ": " << (r.diags.empty() ? "" : r.diags[0].message);
  const std::string letters = c.letters;
  ASSERT_EQ(r.line.count, static_cast<int>(letters.size())) << c.text;
  for (std::size_t i = 0; i < letters.size(); ++i) {
    EXPECT_EQ(r.line.words[i].letter, letters[i]) << c.text;
    EXPECT_DOUBLE_EQ(r.line.words[i].value, c.values[i]) << c.text << " word " << i;
  }
}

INSTANTIATE_TEST_SUITE_P(
    Table, LexWords,
    ::testing::Values(WordCase{"G1 X10 Y-2.5", "GXY", {1, 10, -2.5}}, WordCase{"g01x1y2", "GXY", {1, 1, 2}},
                      WordCase{"G 01 X 1 .5", "GX", {1, 1.5}}, WordCase{"X+.5 Y-.25 Z1.", "XYZ", {0.5, -0.25, 1}},
                      WordCase{"X007.0100", "X", {7.01}}, WordCase{"G1 (comment X5) X3", "GX", {1, 3}},
                      WordCase{"G1 X3 ; Y4", "GX", {1, 3}}, WordCase{"(only a comment)", "", {}},
                      WordCase{"   ", "", {}}, WordCase{"\tG0\tX1\r", "GX", {0, 1}},
                      WordCase{"N10 G5.2", "NG", {10, 5.2}}, WordCase{"X[1+2*3-4/2]", "X", {5}},
                      WordCase{"X[2**3**1]", "X", {8}}, WordCase{"X[-[1]]", "X", {-1}},
                      WordCase{"X sqrt[4] Y abs[-3]", "XY", {2, 3}}, WordCase{"X[7 MOD 3]", "X", {1}},
                      WordCase{"X[ROUND[2.5]] Y[FIX[-1.5]] Z[FUP[1.2]]", "XYZ", {3, -2, 2}},
                      WordCase{"X[ATAN[1]/[0]]", "X", {90}}, WordCase{"X[SIN[90]]", "X", {1}},
                      WordCase{"X12345678.123456789", "X", {12345678.123456789}}));

TEST(Lexer, ColumnsAreOneBasedAtTheLetter) {
  const Lexed r = lex("  G1  X5");
  ASSERT_TRUE(r.ok);
  EXPECT_EQ(r.line.words[0].column, 3);
  EXPECT_EQ(r.line.words[1].column, 7);
}

TEST(Lexer, BlockDeletePercentAndProgramNumber) {
  EXPECT_TRUE(lex("/G0 X1").line.block_delete);
  EXPECT_TRUE(lex(" % ").line.percent);
  const Lexed o = lex("O1234 (name)");
  EXPECT_TRUE(o.ok);
  EXPECT_TRUE(o.line.program_number);
  EXPECT_EQ(o.line.count, 0);
}

struct ErrorCase {
  const char* text;
  const char* fragment;
  int column;
};

class LexErrors : public ::testing::TestWithParam<ErrorCase> {};

TEST_P(LexErrors, ReportedWithColumn) {
  const ErrorCase& c = GetParam();
  const Lexed r = lex(c.text);
  EXPECT_FALSE(r.ok) << c.text;
  ASSERT_EQ(r.diags.size(), 1u) << c.text;
  EXPECT_NE(r.diags[0].message.find(c.fragment), std::string::npos) << c.text << ": " << r.diags[0].message;
  EXPECT_NE(r.diags[0].message.find("expected"), std::string::npos) << r.diags[0].message;
  EXPECT_EQ(r.diags[0].line, 7);
  EXPECT_EQ(r.diags[0].column, c.column) << c.text;
}

INSTANTIATE_TEST_SUITE_P(
    Table, LexErrors,
    ::testing::Values(ErrorCase{"G1 X", "without a value", 4}, ErrorCase{"G1 X-", "without a value", 5},
                      ErrorCase{"X.", "without a value", 2}, ErrorCase{"X1..2", "two decimal points", 4},
                      ErrorCase{"X#0", "out of range", 2}, ErrorCase{"#<a>", "without '='", 1},
                      ErrorCase{"G1 (open", "not closed", 4}, ErrorCase{"X#<nobody>", "not defined", 2},
                      ErrorCase{"G1 *", "unexpected '*'", 4}, ErrorCase{"G1 \x01", "byte 0x01", 4},
                      ErrorCase{"X[1", "expected ']'", 4}, ErrorCase{"X[1/0]", "division by zero", 4},
                      ErrorCase{"X[SQRT[-1]]", "SQRT of a negative", 3}, ErrorCase{"X[1 FOO 1]", "operator 'FOO'", 5},
                      ErrorCase{"X[FOO[1]]", "unknown function", 3}, ErrorCase{"X[EXISTS[#foo]]", "EXISTS", 10},
                      ErrorCase{"X[ATAN[1]]", "ATAN needs two arguments", 10}, ErrorCase{"O1 frob", "keyword", 4},
                      ErrorCase{"G1 O1", "O word after other words", 4}, ErrorCase{"[1]", "without a word letter", 1},
                      ErrorCase{"G1 % ", "unexpected '%'", 4}, ErrorCase{"G1 X1 Y", "without a value", 7},
                      ErrorCase{"X1000000000.5", "out of range", 1}, ErrorCase{"X[10**400]", "no finite number", 5},
                      ErrorCase{"X[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[1]]]]]]]]]]]]]]"
                                "]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]",
                                "nested too deeply", 35}));

TEST(Lexer, TooManyWordsOnALine) {
  std::string text;
  for (int i = 0; i < 65; ++i) text += "G0 ";
  const Lexed r = lex(text);
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.diags.at(0).message.find("too many words"), std::string::npos);
}

// The fast number path must agree bit for bit with the standard library.
TEST(Lexer, ParseDecimalMatchesFromChars) {
  std::mt19937_64 rng(12345);
  std::uniform_int_distribution<int> digits(1, 20), frac(0, 25), dig(0, 9), sign(0, 2);
  for (int n = 0; n < 200000; ++n) {
    std::string s;
    const int sg = sign(rng);
    if (sg == 1) s += '-';
    const int a = digits(rng), b = frac(rng);
    for (int i = 0; i < a; ++i) s += static_cast<char>('0' + dig(rng));
    if (b > 0 || n % 3 == 0) s += '.';
    for (int i = 0; i < b; ++i) s += static_cast<char>('0' + dig(rng));
    double fast = 0.0, ref = 0.0;
    const std::size_t used = parse_decimal(s.data(), s.data() + s.size(), fast);
    ASSERT_EQ(used, s.size()) << s;
    const auto res = std::from_chars(s.data(), s.data() + s.size(), ref);
    ASSERT_EQ(res.ec, std::errc()) << s;
    ASSERT_EQ(fast, ref) << s;
  }
}

}  // namespace
}  // namespace pcnc
