// test_fixed_text.cpp — the reports' fixed-decimal formatter (config/fixed_text.hpp) against
// printf: chosen values (ties to even, negatives, -0.0, large values, NaN and infinities) and a
// broad sweep of values and decimal counts, each compared with snprintf("%.*f") under the
// formatter's one rule ("-0.00" written "0.00").
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "config/fixed_text.hpp"

namespace pcnc {
namespace {

// What the report's formatter printed before it used std::to_chars: snprintf (into a buffer
// large enough for any double), then a "-" dropped when only zeros follow it.
std::string printf_fixed(double v, int decimals) {
  std::vector<char> buf(1024);
  std::snprintf(buf.data(), buf.size(), "%.*f", decimals, v);
  std::string s(buf.data());
  if (s.size() > 1 && s[0] == '-' && s.find_first_not_of("-0.") == std::string::npos) s.erase(0, 1);
  return s;
}

TEST(FixedText, ChosenValues) {
  EXPECT_EQ(fixed(0.0, 0), "0");
  EXPECT_EQ(fixed(0.0, 3), "0.000");
  EXPECT_EQ(fixed(1.0, 3), "1.000");
  EXPECT_EQ(fixed(123.456, 1), "123.5");
  EXPECT_EQ(fixed(-123.456, 2), "-123.46");
  EXPECT_EQ(fixed(80.467, 3), "80.467");
  EXPECT_EQ(fixed(0.585864, 6), "0.585864");
  EXPECT_EQ(fixed(1234567.0, 0), "1234567");
  EXPECT_EQ(fixed(1.0e20, 2), "100000000000000000000.00");
  EXPECT_EQ(fixed(0.5, 6), "0.500000");
  // a negative count is printf's default precision
  EXPECT_EQ(fixed(1.25, -1), "1.250000");
}

TEST(FixedText, TiesRoundToEvenOnTheExactBinaryValue) {
  // exact ties (binary fractions) go to the even digit, as printf
  EXPECT_EQ(fixed(0.5, 0), "0");
  EXPECT_EQ(fixed(1.5, 0), "2");
  EXPECT_EQ(fixed(2.5, 0), "2");
  EXPECT_EQ(fixed(-2.5, 0), "-2");
  EXPECT_EQ(fixed(0.125, 2), "0.12");
  EXPECT_EQ(fixed(0.375, 2), "0.38");
  EXPECT_EQ(fixed(-0.125, 2), "-0.12");
  EXPECT_EQ(fixed(10.25, 1), "10.2");
  EXPECT_EQ(fixed(10.75, 1), "10.8");
  // decimal "ties" are not exact in binary: 0.15 is 0.1499999..., 0.35 is 0.3499999..., 0.45 is 0.4500000...1
  EXPECT_EQ(fixed(0.15, 1), "0.1");
  EXPECT_EQ(fixed(0.35, 1), "0.3");
  EXPECT_EQ(fixed(2.675, 2), "2.67");
  EXPECT_EQ(fixed(1.005, 2), "1.00");
  EXPECT_EQ(fixed(0.45, 1), printf_fixed(0.45, 1));
}

TEST(FixedText, NoMinusOnZero) {
  EXPECT_EQ(fixed(-0.0, 0), "0");
  EXPECT_EQ(fixed(-0.0, 3), "0.000");
  EXPECT_EQ(fixed(-0.0004, 3), "0.000");
  EXPECT_EQ(fixed(-0.0006, 3), "-0.001");
  EXPECT_EQ(fixed(-1e-300, 2), "0.00");
  EXPECT_EQ(fixed(-0.5, 0), "0");  // a tie to the even digit 0
  EXPECT_EQ(fixed(-1.5, 0), "-2");
}

TEST(FixedText, NanAndInfinityAsPrintfWritesThem) {
  const double inf = std::numeric_limits<double>::infinity();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(fixed(inf, 2), "inf");
  EXPECT_EQ(fixed(-inf, 2), "-inf");
  EXPECT_EQ(fixed(nan, 2), printf_fixed(nan, 2));
  EXPECT_EQ(fixed(-nan, 2), printf_fixed(-nan, 2));
  EXPECT_EQ(fixed(nan, 1), "nan");
  EXPECT_EQ(fixed(std::copysign(nan, -1.0), 1), "-nan");
}

TEST(FixedText, LargeValuesAndManyDecimals) {
  const double big = std::numeric_limits<double>::max();
  EXPECT_EQ(fixed(big, 0), printf_fixed(big, 0));
  EXPECT_EQ(fixed(-big, 3), printf_fixed(-big, 3));
  EXPECT_EQ(fixed(big, 0).size(), 309u);
  EXPECT_EQ(fixed(1e300, 1), printf_fixed(1e300, 1));
  const double tiny = std::numeric_limits<double>::denorm_min();
  EXPECT_EQ(fixed(tiny, 200), printf_fixed(tiny, 200));  // past to_chars's buffer: the printf path
  EXPECT_EQ(fixed(0.1, 60), printf_fixed(0.1, 60));
  EXPECT_EQ(fixed(1.0 / 3.0, 17), "0.33333333333333331");
}

TEST(FixedText, AppendsToWhatIsThere) {
  std::string s = "x=";
  append_fixed(s, 1.25, 1);
  s += ',';
  append_fixed(s, -0.01, 1);
  EXPECT_EQ(s, "x=1.2,0.0");
}

// The broad sweep: the formatter against snprintf over values of every magnitude the reports
// meet (and well beyond), halves and decimal ties near each rounding step, and random bit
// patterns (any finite double), for 0 to 9 decimals.
TEST(FixedText, SameAsPrintfOverASweep) {
  std::mt19937_64 rng(20261127);
  std::vector<double> values = {0.0, -0.0, 1.0, -1.0, 0.05, 0.95, 9.95, 99.95, 999.5, 0.0005, -0.0005};
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (int e = -12; e <= 22; ++e) {
    for (int k = 0; k < 400; ++k) values.push_back(unit(rng) * std::pow(10.0, e));
  }
  for (int k = -20000; k <= 20000; ++k) {
    values.push_back(k / 64.0);      // exact binary ties at 1 to 6 decimals
    values.push_back(k * 0.005);     // decimal ties, not exact in binary
    values.push_back(k * 0.05 + 0.0000001);
  }
  std::uniform_int_distribution<std::uint64_t> bits;
  for (int k = 0; k < 20000; ++k) {
    const double v = std::bit_cast<double>(bits(rng));
    if (std::isfinite(v)) values.push_back(v);
  }
  std::size_t compared = 0, differ = 0;
  for (const double v : values) {
    for (int d = 0; d <= 9; ++d) {
      const std::string want = printf_fixed(v, d), got = fixed(v, d);
      ++compared;
      if (got != want && ++differ <= 10) ADD_FAILURE() << "value " << std::hexfloat << v << " decimals " << d << ": " << got << " != " << want;
    }
  }
  EXPECT_EQ(differ, 0u) << "of " << compared;
  EXPECT_GT(compared, 1000000u);
}

}  // namespace
}  // namespace pcnc
