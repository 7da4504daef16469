// json_places.cpp — offsets and line:column of values in JSON text. See json_places.hpp.
#include "gcode/json_places.hpp"

#include <algorithm>

namespace pcnc {
namespace {

bool blank(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }

std::size_t skip_blanks(std::string_view t, std::size_t i) {
  while (i < t.size() && blank(t[i])) ++i;
  return i;
}

// From the opening quote at i: past the closing quote.
std::size_t skip_string(std::string_view t, std::size_t i) {
  for (++i; i < t.size(); ++i) {
    if (t[i] == '\\') {
      ++i;
    } else if (t[i] == '"') {
      return i + 1;
    }
  }
  return t.size();
}

// From a value's first byte: past the value.
std::size_t skip_value(std::string_view t, std::size_t i) {
  if (i >= t.size()) return i;
  if (t[i] == '"') return skip_string(t, i);
  if (t[i] == '{' || t[i] == '[') {
    int depth = 0;
    while (i < t.size()) {
      const char c = t[i];
      if (c == '"') {
        i = skip_string(t, i);
        continue;
      }
      if (c == '{' || c == '[') ++depth;
      if ((c == '}' || c == ']') && --depth == 0) return i + 1;
      ++i;
    }
    return i;
  }
  while (i < t.size() && !blank(t[i]) && t[i] != ',' && t[i] != ']' && t[i] != '}') ++i;
  return i;
}

}  // namespace

std::size_t json_root(std::string_view text) {
  const std::size_t i = skip_blanks(text, 0);
  return i < text.size() ? i : kNoJsonPlace;
}

std::size_t json_member(std::string_view t, std::size_t object, std::string_view key) {
  if (object >= t.size() || t[object] != '{') return kNoJsonPlace;
  std::size_t i = skip_blanks(t, object + 1);
  while (i < t.size() && t[i] == '"') {
    const std::size_t end = skip_string(t, i);
    const std::string_view name = t.substr(i + 1, end - i - 2);  // raw (keys here have no escapes)
    i = skip_blanks(t, end);
    if (i >= t.size() || t[i] != ':') return kNoJsonPlace;
    i = skip_blanks(t, i + 1);
    if (name == key) return i;
    i = skip_blanks(t, skip_value(t, i));
    if (i < t.size() && t[i] == ',') i = skip_blanks(t, i + 1);
  }
  return kNoJsonPlace;
}

std::vector<std::size_t> json_elements(std::string_view t, std::size_t array) {
  std::vector<std::size_t> out;
  if (array >= t.size() || t[array] != '[') return out;
  std::size_t i = skip_blanks(t, array + 1);
  while (i < t.size() && t[i] != ']') {
    out.push_back(i);
    i = skip_blanks(t, skip_value(t, i));
    if (i < t.size() && t[i] == ',') i = skip_blanks(t, i + 1);
  }
  return out;
}

TextLines::TextLines(std::string_view text) {
  starts_.push_back(0);
  for (std::size_t i = 0; i < text.size(); ++i)
    if (text[i] == '\n') starts_.push_back(i + 1);
}

int TextLines::line(std::size_t offset) const {
  return static_cast<int>(std::upper_bound(starts_.begin(), starts_.end(), offset) - starts_.begin());
}

int TextLines::column(std::size_t offset) const {
  return static_cast<int>(offset - starts_[static_cast<std::size_t>(line(offset) - 1)]) + 1;
}

}  // namespace pcnc
