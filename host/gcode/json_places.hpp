// json_places.hpp — where values stand in a JSON text (byte offsets, line:column), so that the
// front end can name the place inside a JSON program file (gcode/ruled_json_input.hpp) as it
// names a G-code file's line and column. nlohmann's parser keeps no positions; this scanner
// walks text that has already parsed, one pass per container, without building anything.
// Pure functions.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace pcnc {

inline constexpr std::size_t kNoJsonPlace = static_cast<std::size_t>(-1);

/// The offset of the first value in `text` (the document), or kNoJsonPlace.
std::size_t json_root(std::string_view text);
/// In the object whose '{' is at `object`: the offset of member `key`'s value, or kNoJsonPlace.
std::size_t json_member(std::string_view text, std::size_t object, std::string_view key);
/// In the array whose '[' is at `array`: the offsets of its elements (empty if not an array).
std::vector<std::size_t> json_elements(std::string_view text, std::size_t array);

/// Line and column (both from 1; the column in bytes) of offsets in one text.
class TextLines {
 public:
  explicit TextLines(std::string_view text);
  int line(std::size_t offset) const;
  int column(std::size_t offset) const;
  std::size_t count() const { return starts_.size(); }  // lines in the text

 private:
  std::vector<std::size_t> starts_;  // offset of each line's first byte
};

}  // namespace pcnc
