// fixed_text.cpp — fixed-decimal text by std::to_chars (see fixed_text.hpp).
#include "report/fixed_text.hpp"

#include <algorithm>
#include <charconv>
#include <cstdio>
#include <system_error>
#include <vector>

namespace pcnc {

namespace {

// The sign of a value that prints as zero ("-0.00"): dropped.
bool negative_zero(const char* first, const char* last) {
  return last - first > 1 && first[0] == '-' && std::all_of(first + 1, last, [](char c) { return c == '0' || c == '.'; });
}

}  // namespace

void append_fixed(std::string& out, double v, int decimals) {
  if (decimals < 0) decimals = 6;  // printf: a negative precision is taken as omitted
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
