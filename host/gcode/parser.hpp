// parser.hpp — second stage of the G-code front end: the words of one line grouped by meaning.
//
// G and M words are sorted into their RS274/LinuxCNC modal groups (two words of one group on a
// line is an error, as is a G or M number nobody defines); every other letter may appear once
// per line and is kept with its value and column. Whether a word is executed, warned about or
// rejected is the interpreter's decision, not the parser's.
#pragma once

#include <array>
#include <cstdint>

#include "gcode/diagnostics.hpp"
#include "gcode/lexer.hpp"

namespace pcnc {

/// G and M numbers are kept as ten times their value: G1 -> 10, G5.2 -> 52, G91.1 -> 911.
enum GGroup : int {
  kGNonModal = 0,        // G4 G10 G28 G28.1 G30 G30.1 G52 G53 G92 G92.x
  kGMotion = 1,          // G0 G1 G2 G3 G5.x G6.2 G33 G38.x G73 G76 G80-G89
  kGPlane = 2,           // G17 G18 G19 (and .1)
  kGDistance = 3,        // G90 G91
  kGArcDistance = 4,     // G90.1 G91.1
  kGFeedMode = 5,        // G93 G94 G95
  kGUnits = 6,           // G20 G21
  kGCutterComp = 7,      // G40 G41 G42 (and .1)
  kGToolLength = 8,      // G43 G43.1 G43.2 G49
  kGCannedReturn = 10,   // G98 G99
  kGCoordSystem = 12,    // G54-G59, G59.1-G59.3
  kGPathControl = 13,    // G61 G61.1 G64
  kGSpindleMode = 14,    // G96 G97
  kGLatheDiameter = 15,  // G7 G8
  kGGroupCount = 16
};

enum MGroup : int {
  kMStop = 0,        // M0 M1 M2 M30 M60
  kMToolChange = 1,  // M6 M61
  kMSpindle = 2,     // M3 M4 M5 M19
  kMCoolant = 3,     // M7 M8 M9
  kMOverride = 4,    // M48-M53
  kMContouring = 5,  // M21 M22 (pcnc: contouring on/off)
  kMOther = 6,       // M62-M68, M70-M73, M100-M199 (known, never executed here)
  kMGroupCount = 7
};

/// Modal group of a G number (x10), or -1 when no RS274 dialect defines it.
int g_group(int code10);
/// Modal group of an M number, or -1 when undefined.
int m_group(int code);

template <std::size_t N>
constexpr std::array<std::int16_t, N> all_none() {
  std::array<std::int16_t, N> a{};
  for (auto& v : a) v = -1;
  return a;
}

struct ParsedLine {
  int line = 0;
  std::array<std::int16_t, kGGroupCount> g = all_none<kGGroupCount>();  // code x10, -1 = none
  std::array<std::int16_t, kGGroupCount> g_col{};
  std::array<std::int16_t, kMGroupCount> m = all_none<kMGroupCount>();  // M number, -1 = none
  std::array<std::int16_t, kMGroupCount> m_col{};
  std::uint32_t present = 0;  // bit (letter - 'A') for letters other than G/M
  std::array<double, 26> value{};
  std::array<std::int32_t, 26> col{};
  std::uint32_t g_groups = 0;  // bit per G group present on the line
  std::uint32_t m_groups = 0;  // bit per M group present on the line
  bool empty = true;           // no words at all (blank, comment, '%', O number)
  int g80_col = 0;             // G80 written next to another motion code ("G80 G0", as some posts do)

  bool has(char letter) const { return (present >> (letter - 'A')) & 1u; }
  double get(char letter) const { return value[static_cast<std::size_t>(letter - 'A')]; }
  int column(char letter) const { return col[static_cast<std::size_t>(letter - 'A')]; }
};

/// Groups the words of `lexed` into `out`. Returns false after reporting the first error.
bool parse_line(const LexedLine& lexed, int line_no, ParsedLine& out, DiagnosticSink& sink);

/// "G5.2", "G1", "M30": a G (x10) or M number as a user writes it.
std::string g_name(int code10);

}  // namespace pcnc
