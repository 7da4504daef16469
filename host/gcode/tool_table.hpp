// tool_table.hpp — the tool table in LinuxCNC's format (its tool.tbl): one tool per line,
//
//   T1 P1 Z12.7 D6.35 ;comment
//
// words T (tool number, required), P (pocket), X Y Z A B C U V W (offsets; Z is the tool
// length offset), D (diameter), I J Q (a lathe tool's front angle, back angle and
// orientation: accepted and kept), ';' starting a comment to the end of the line, blank
// lines and comment-only lines. A word is its letter (either case) and its number with no
// space between; words are separated by blanks. Values are in the machine's units: mm.
//
// Stricter than LinuxCNC, which skips a line it cannot read: every problem is an error with
// its place ("file:line:col: error: ...") and what was expected, and a table with any error
// is not used. A tool number defined twice is an error.
//
// May include: the standard library, shared/geometry, diagnostics.hpp.
#pragma once

#include <array>
#include <string>
#include <string_view>
#include <vector>

#include "geometry/vec3.hpp"

namespace pcnc {

struct ToolEntry {
  int number = 0;                 // T, >= 0
  int pocket = 0;                 // P, >= 0 (0 when not given)
  Vec3 offset{};                  // X Y Z, mm; offset[2] is the tool length offset
  double diameter = 0;            // D, mm, >= 0
  std::array<double, 6> abcuvw{}; // A B C U V W offsets (kept; this machine has no such axes)
  double front_angle = 0;         // I, degrees (lathe)
  double back_angle = 0;          // J, degrees (lathe)
  int orientation = 0;            // Q, 0..9 (lathe)
  std::string comment;            // after ';', blanks at both ends removed
  int line = 0;                   // line in the file it came from (0: set otherwise)

  bool operator==(const ToolEntry&) const = default;
};

class ToolTable {
 public:
  /// The tool with this number, or nullptr.
  const ToolEntry* find(int number) const;
  /// Replaces the tool with the same number (in its place) or appends a new one.
  void set(const ToolEntry& tool);
  /// Removes the tool with this number; false when there was none.
  bool remove(int number);
  /// In file order (tools added by set() at the end).
  const std::vector<ToolEntry>& tools() const { return tools_; }
  std::size_t size() const { return tools_.size(); }
  bool empty() const { return tools_.empty(); }

 private:
  std::vector<ToolEntry> tools_;
};

/// Parses a tool table. On success fills `out` (replacing what it held) and returns true; else
/// returns false, leaves `out` as it was and appends messages "origin:line:col: error: ..." to
/// `errors` (at most DiagnosticSink::kMaxErrors, then a count of the rest).
bool parse_tool_table(std::string_view text, const std::string& origin, ToolTable& out, std::vector<std::string>& errors);

/// Reads and parses the file at `path`; throws std::runtime_error with every message (one a
/// line) when it cannot be read or has errors.
ToolTable load_tool_table(const std::string& path);

/// The table in the same format, one line per tool in table order (zero values left out
/// except T and P, numbers with enough digits to read back the same double).
std::string format_tool_table(const ToolTable& table);

}  // namespace pcnc
