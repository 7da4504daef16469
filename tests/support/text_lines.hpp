// text_lines.hpp — a text as its lines (without '\n'; a '\r' stays), for tests that compare
// programs line by line; and whether a text has a part (messages, reports).
#pragma once

#include <string>
#include <vector>

namespace pcnc::test {

inline bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

inline std::vector<std::string> split_lines(const std::string& s) {
  std::vector<std::string> out;
  std::size_t at = 0;
  while (at < s.size()) {
    std::size_t nl = s.find('\n', at);
    if (nl == std::string::npos) nl = s.size();
    out.push_back(s.substr(at, nl - at));
    at = nl + 1;
  }
  return out;
}

}  // namespace pcnc::test
