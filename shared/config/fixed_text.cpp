// fixed_text.cpp — fixed-decimal text by std::to_chars (see fixed_text.hpp).
#include "config/fixed_text.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <system_error>
#include <vector>

namespace pcnc {

namespace {

// The sign of a value that prints as zero ("-0.00"): dropped.
bool negative_zero(const char* first, const char* last) {
  return last - first > 1 && first[0] == '-' && std::all_of(first + 1, last, [](char c) { return c == '0' || c == '.'; });
}

constexpr double kPow10[] = {1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9};
constexpr std::uint64_t kPow10Int[] = {1, 10, 100, 1000, 10000, 100000, 1000000, 10000000, 100000000, 1000000000};

// The common case, without to_chars: v scaled by 10^decimals to under 1e9 in magnitude, where
// the product's rounding error (under 1e-7) cannot move it across a rounding step unless it
// lies within 1e-5 of a half; then the digits are those of the nearest integer. False (and
// nothing appended) otherwise: ties, near-ties, large values, NaN and infinities go to to_chars.
bool append_fixed_small(std::string& out, double v, int decimals) {
  if (decimals > 9) return false;
  const double scaled = std::fabs(v) * kPow10[decimals];
  if (!(scaled < 1e9)) return false;
  const double whole = std::floor(scaled);
  const double frac = scaled - whole;
  if (std::fabs(frac - 0.5) < 1e-5) return false;
  const auto n = static_cast<std::uint64_t>(whole) + (frac > 0.5 ? 1u : 0u);
  char buf[32];
  char* p = buf;
  if (std::signbit(v) && n != 0) *p++ = '-';  // "-0.0" is written "0.0" (the header)
  const std::uint64_t unit = kPow10Int[decimals];
  p = std::to_chars(p, buf + sizeof buf, n / unit).ptr;
  if (decimals > 0) {
    *p++ = '.';
    std::uint64_t f = n % unit;
    for (int k = decimals - 1; k >= 0; --k, f /= 10) p[k] = static_cast<char>('0' + f % 10);
    p += decimals;
  }
  out.append(buf, static_cast<std::size_t>(p - buf));
  return true;
}

}  // namespace

void append_fixed(std::string& out, double v, int decimals) {
  if (decimals < 0) decimals = 6;  // printf: a negative precision is taken as omitted
  if (append_fixed_small(out, v, decimals)) return;
  // the largest double has 309 integer digits: with the sign, the point and up to 150
  // decimals it fits; more decimals take the heap
  char buf[512];
  if (decimals <= 150) {
    const std::to_chars_result r = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::fixed, decimals);
    if (r.ec == std::errc()) {
      const char* first = negative_zero(buf, r.ptr) ? buf + 1 : buf;
      out.append(first, static_cast<std::size_t>(r.ptr - first));
      return;
    }
  }
  // many decimals (or to_chars failing): printf itself, into a buffer large enough
  std::vector<char> big(static_cast<std::size_t>(decimals) + 320);
  const int n = std::snprintf(big.data(), big.size(), "%.*f", decimals, v);
  const char* last = big.data() + std::clamp(n, 0, static_cast<int>(big.size()) - 1);
  const char* first = negative_zero(big.data(), last) ? big.data() + 1 : big.data();
  out.append(first, static_cast<std::size_t>(last - first));
}

std::string fixed(double v, int decimals) {
  std::string s;
  append_fixed(s, v, decimals);
  return s;
}

}  // namespace pcnc
