// config_text.hpp — a config file's text as its lines and its `key = value` lines, for the
// config tests that delete, misspell or change each key of a shipped file in turn.
#pragma once

#include <regex>
#include <string>
#include <vector>

namespace pcnc::test {

// One `key = value` line of a config text.
struct KeyLine {
  int line = 0;          // 1-based
  std::string section;   // "axis.x", "" at the top
  int section_line = 0;  // the section header's line
  std::string key;
  std::string value;
};

/// The text's lines without '\n'; a text ending in '\n' ends with an empty line, so that
/// join_config_lines gives the text back exactly.
inline std::vector<std::string> config_lines(const std::string& text) {
  std::vector<std::string> lines;
  std::size_t at = 0;
  for (;;) {
    const std::size_t nl = text.find('\n', at);
    lines.push_back(text.substr(at, nl == std::string::npos ? std::string::npos : nl - at));
    if (nl == std::string::npos) break;
    at = nl + 1;
  }
  return lines;
}

inline std::string join_config_lines(const std::vector<std::string>& lines) {
  std::string text;
  for (std::size_t i = 0; i < lines.size(); ++i) text += lines[i] + (i + 1 < lines.size() ? "\n" : "");
  return text;
}

/// Every `key = value` line of the text, with its section.
inline std::vector<KeyLine> key_lines(const std::string& text) {
  const std::regex header(R"(^\[([a-z._]+)\])");
  const std::regex key(R"(^([a-z_0-9]+) = ([^#]*[^# ]))");
  std::vector<KeyLine> keys;
  std::string section;
  int section_line = 0;
  const auto lines = config_lines(text);
  for (std::size_t i = 0; i < lines.size(); ++i) {
    std::smatch m;
    if (std::regex_search(lines[i], m, header)) {
      section = m[1];
      section_line = static_cast<int>(i) + 1;
    } else if (std::regex_search(lines[i], m, key)) {
      keys.push_back({static_cast<int>(i) + 1, section, section_line, m[1], m[2]});
    }
  }
  return keys;
}

}  // namespace pcnc::test
