// parser.hpp — second stage of the G-code front end: the words of one line grouped by meaning.
//
// G and M words are sorted into their RS274/LinuxCNC modal groups, from the one table of codes
// in words.hpp (two words of one group on a line is an error, as is a G or M number nobody
// defines); every other letter may appear once per line and is kept with its value and
// column. Whether a word is executed, warned about or rejected is the interpreter's decision
// (the same table says which codes it rejects), not the parser's.
#pragma once

#include <array>
#include <cstdint>

#include "gcode/diagnostics.hpp"
#include "gcode/lexer.hpp"
#include "gcode/words.hpp"

namespace pcnc {

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
