// tool_table.cpp — reading and writing LinuxCNC-format tool tables (see tool_table.hpp).
#include "gcode/tool_table.hpp"

#include <algorithm>
#include <charconv>
#include <cctype>
#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "gcode/diagnostics.hpp"

namespace pcnc {

namespace {

constexpr double kMaxValue = 1e6;                  // |offset|, diameter, angle
constexpr const char* kLetters = "TPXYZABCUVWDIJQ";  // the words of a tool line
constexpr const char* kExpectedWords = "one of T P X Y Z A B C U V W D I J Q (e.g. T1 P1 Z12.7 D6.35)";

bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }

std::string trim(std::string_view s) {
  std::size_t a = 0, b = s.size();
  while (a < b && is_blank(s[a])) ++a;
  while (b > a && is_blank(s[b - 1])) --b;
  return std::string(s.substr(a, b - a));
}

// A plain decimal: [+-] digits [. digits] or [+-] . digits, with an optional exponent.
bool is_decimal(std::string_view s) {
  std::size_t i = 0;
  if (i < s.size() && (s[i] == '+' || s[i] == '-')) ++i;
  std::size_t digits = 0;
  while (i < s.size() && std::isdigit(static_cast<unsigned char>(s[i]))) ++i, ++digits;
  if (i < s.size() && s[i] == '.') {
    ++i;
    while (i < s.size() && std::isdigit(static_cast<unsigned char>(s[i]))) ++i, ++digits;
  }
  if (digits == 0) return false;
  if (i < s.size() && (s[i] == 'e' || s[i] == 'E')) {
    ++i;
    if (i < s.size() && (s[i] == '+' || s[i] == '-')) ++i;
    std::size_t exp_digits = 0;
    while (i < s.size() && std::isdigit(static_cast<unsigned char>(s[i]))) ++i, ++exp_digits;
    if (exp_digits == 0) return false;
  }
  return i == s.size();
}

bool is_integer(std::string_view s) {
  std::size_t i = (!s.empty() && (s[0] == '+' || s[0] == '-')) ? 1 : 0;
  if (i == s.size()) return false;
  return std::all_of(s.begin() + static_cast<std::ptrdiff_t>(i), s.end(),
                     [](char c) { return std::isdigit(static_cast<unsigned char>(c)) != 0; });
}

// One line's words into `tool`; errors to `sink`. Returns whether the line holds a tool
// (false for blank and comment-only lines).
bool parse_line(std::string_view text, int line, ToolEntry& tool, int& t_column, DiagnosticSink& sink) {
  const std::size_t semi = text.find(';');
  const std::string_view words = text.substr(0, semi);
  if (semi != std::string_view::npos) tool.comment = trim(text.substr(semi + 1));
  tool.line = line;
  int seen_at[128] = {};  // column where each letter was first given on this line
  bool any = false;
  std::size_t i = 0;
  while (i < words.size()) {
    if (is_blank(words[i])) {
      ++i;
      continue;
    }
    any = true;
    const int col = static_cast<int>(i) + 1;
    std::size_t end = i;
    while (end < words.size() && !is_blank(words[end])) ++end;
    const std::string_view token = words.substr(i, end - i);
    i = end;
    const unsigned char raw = static_cast<unsigned char>(token[0]);
    const char letter = static_cast<char>(std::toupper(raw));
    if (!std::isalpha(raw) || std::string_view(kLetters).find(letter) == std::string_view::npos) {
      sink.error(line, col, std::string(std::isalpha(raw) ? "unknown word '" : "unexpected '") + std::string(token) + "'; expected " +
                                kExpectedWords + ", or ';' before a comment");
      continue;
    }
    if (seen_at[static_cast<int>(letter)] != 0) {
      sink.error(line, col, std::string(1, letter) + " given twice on one line (first at column " +
                                std::to_string(seen_at[static_cast<int>(letter)]) + ")");
      continue;
    }
    seen_at[static_cast<int>(letter)] = col;
    const std::string_view num = token.substr(1);
    const bool integral = letter == 'T' || letter == 'P' || letter == 'Q';
    if (num.empty()) {
      // "Z 12.7": one error saying so, not a second one for the stray number.
      std::size_t next = i;
      while (next < words.size() && is_blank(words[next])) ++next;
      std::size_t next_end = next;
      while (next_end < words.size() && !is_blank(words[next_end])) ++next_end;
      const std::string_view apart = words.substr(next, next_end - next);
      if (!apart.empty() && is_decimal(apart)) {
        i = next_end;
        sink.error(line, col, std::string("'") + letter + "' and its number '" + std::string(apart) +
                                  "' are apart; expected them together (" + letter + std::string(apart) + ")");
        continue;
      }
      sink.error(line, col, std::string("'") + letter + "' without a number; expected " +
                                (integral ? "an integer right after it (e.g. " : "a number right after it (e.g. ") + letter +
                                (integral ? "1)" : "12.7)"));
      continue;
    }
    if (integral) {
      long long v = 0;
      const std::string_view digits = num[0] == '+' ? num.substr(1) : num;
      const auto r = std::from_chars(digits.data(), digits.data() + digits.size(), v);
      if (!is_integer(num) || r.ec != std::errc() || r.ptr != digits.data() + digits.size()) {
        sink.error(line, col, "bad number '" + std::string(token) + "': " + letter + " takes a whole number (e.g. " + letter + "3)");
        continue;
      }
      if (letter == 'Q' && (v < 0 || v > 9)) {
        sink.error(line, col, "orientation '" + std::string(token) + "' out of range: expected Q0..Q9");
        continue;
      }
      if (v < 0 || v > 99999999) {
        sink.error(line, col, std::string(letter == 'T' ? "tool number '" : "pocket '") + std::string(token) +
                                  "' out of range: expected 0.." + "99999999");
        continue;
      }
      (letter == 'T' ? tool.number : letter == 'P' ? tool.pocket : tool.orientation) = static_cast<int>(v);
      continue;
    }
    double v = 0;
    const std::string_view digits = num[0] == '+' ? num.substr(1) : num;
    const auto r = std::from_chars(digits.data(), digits.data() + digits.size(), v);
    if (!is_decimal(num) || r.ec != std::errc() || r.ptr != digits.data() + digits.size() || !std::isfinite(v) ||
        std::fabs(v) > kMaxValue) {
      sink.error(line, col, "bad number '" + std::string(token) + "': expected a decimal number of mm (or degrees) within ±1e6, e.g. " +
                                letter + "6.35");
      continue;
    }
    if (letter == 'D' && v < 0) {
      sink.error(line, col, "diameter '" + std::string(token) + "' is negative; expected D >= 0");
      continue;
    }
    switch (letter) {
      case 'X': tool.offset[0] = v; break;
      case 'Y': tool.offset[1] = v; break;
      case 'Z': tool.offset[2] = v; break;
      case 'A': tool.abcuvw[0] = v; break;
      case 'B': tool.abcuvw[1] = v; break;
      case 'C': tool.abcuvw[2] = v; break;
      case 'U': tool.abcuvw[3] = v; break;
      case 'V': tool.abcuvw[4] = v; break;
      case 'W': tool.abcuvw[5] = v; break;
      case 'D': tool.diameter = v; break;
      case 'I': tool.front_angle = v; break;
      case 'J': tool.back_angle = v; break;
      default: break;
    }
  }
  t_column = seen_at[static_cast<int>('T')];
  if (any && t_column == 0) {
    sink.error(line, 1, "missing T: expected the tool number (e.g. T1) on every tool line");
  }
  return any;
}

std::string number_text(double v) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);  // shortest text that reads back the same
  return std::string(buf, r.ptr);
}

}  // namespace

const ToolEntry* ToolTable::find(int number) const {
  const auto it = std::find_if(tools_.begin(), tools_.end(), [&](const ToolEntry& t) { return t.number == number; });
  return it == tools_.end() ? nullptr : &*it;
}

void ToolTable::set(const ToolEntry& tool) {
  const auto it = std::find_if(tools_.begin(), tools_.end(), [&](const ToolEntry& t) { return t.number == tool.number; });
  if (it == tools_.end()) {
    tools_.push_back(tool);
  } else {
    *it = tool;
  }
}

bool ToolTable::remove(int number) {
  const auto it = std::find_if(tools_.begin(), tools_.end(), [&](const ToolEntry& t) { return t.number == number; });
  if (it == tools_.end()) return false;
  tools_.erase(it);
  return true;
}

bool parse_tool_table(std::string_view text, const std::string& origin, ToolTable& out, std::vector<std::string>& errors) {
  DiagnosticSink sink(origin);
  ToolTable table;
  int line = 0;
  std::size_t at = 0;
  while (at < text.size()) {
    ++line;
    std::size_t nl = text.find('\n', at);
    if (nl == std::string_view::npos) nl = text.size();
    const std::string_view row = text.substr(at, nl - at);
    at = nl + 1;
    ToolEntry tool;
    int t_column = 0;
    const std::uint64_t errors_before = sink.error_count();
    if (!parse_line(row, line, tool, t_column, sink) || sink.error_count() != errors_before) continue;
    if (const ToolEntry* first = table.find(tool.number)) {
      sink.error(line, t_column, "tool T" + std::to_string(tool.number) + " is already defined at line " + std::to_string(first->line) +
                                "; expected each tool number once");
      continue;
    }
    table.set(tool);
  }
  if (sink.has_errors()) {
    for (const Diagnostic& d : sink.take()) errors.push_back(format_diagnostic(d));
    return false;
  }
  out = std::move(table);
  return true;
}

ToolTable load_tool_table(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read the tool table '" + path + "'");
  std::stringstream ss;
  ss << in.rdbuf();
  if (in.bad()) throw std::runtime_error("cannot read the tool table '" + path + "'");
  ToolTable table;
  std::vector<std::string> errors;
  if (!parse_tool_table(ss.str(), path, table, errors)) {
    std::string all;
    for (const std::string& e : errors) all += (all.empty() ? "" : "\n") + e;
    throw std::runtime_error(all);
  }
  return table;
}

std::string format_tool_table(const ToolTable& table) {
  std::string s;
  for (const ToolEntry& t : table.tools()) {
    s += "T" + std::to_string(t.number) + " P" + std::to_string(t.pocket);
    auto word = [&](char letter, double v) {
      if (v != 0.0) s += std::string(" ") + letter + (v > 0 ? "+" : "") + number_text(v);
    };
    word('D', t.diameter);
    for (int a = 0; a < 3; ++a) word("XYZ"[a], t.offset[static_cast<std::size_t>(a)]);
    for (int a = 0; a < 6; ++a) word("ABCUVW"[a], t.abcuvw[static_cast<std::size_t>(a)]);
    word('I', t.front_angle);
    word('J', t.back_angle);
    if (t.orientation != 0) s += " Q" + std::to_string(t.orientation);
    if (!t.comment.empty()) s += " ;" + t.comment;
    s += "\n";
  }
  return s;
}

}  // namespace pcnc
