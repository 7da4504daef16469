// parser.hpp — second stage of the G-code front end: the words of one line grouped by meaning.
//
// G and M words are sorted into their RS274/LinuxCNC modal groups, from the one table of codes
// in words.hpp (two words of one group on a line is an error, as is a G or M number nobody
// defines); every other letter may appear once per line and is kept with its value and
// column; LinuxCNC's polar coordinate words @ (radius) and ^ (angle) are kept the same way,
// in the two slots after Z. Whether a word is executed, warned about or rejected is the interpreter's decision
// (the same table says which codes it rejects), not the parser's.
#pragma once

#include <array>
#include <cstdint>

#include "gcode/diagnostics.hpp"
#include "gcode/lexer.hpp"
#include "gcode/words.hpp"

namespace pcnc {

/// The slot of a word letter in ParsedLine: 'A'..'Z' are 0..25, the polar words '@' 26, '^' 27.
constexpr int kWordSlots = 28;
constexpr int word_slot(char letter) { return letter == '@' ? 26 : letter == '^' ? 27 : letter - 'A'; }

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
  std::uint32_t present = 0;  // bit word_slot(letter) for letters other than G/M
  std::array<double, kWordSlots> value{};
  std::array<std::int32_t, kWordSlots> col{};
  std::uint32_t g_groups = 0;  // bit per G group present on the line
  std::uint32_t m_groups = 0;  // bit per M group present on the line
  bool empty = true;           // no words at all (blank, comment, '%', O number)
  int g80_col = 0;             // G80 written next to another motion code ("G80 G0", as some posts do)

  bool has(char letter) const { return (present >> word_slot(letter)) & 1u; }
  double get(char letter) const { return value[static_cast<std::size_t>(word_slot(letter))]; }
  int column(char letter) const { return col[static_cast<std::size_t>(word_slot(letter))]; }
};

/// Groups the words of `lexed` into `out`. Returns false after reporting the first error.
bool parse_line(const LexedLine& lexed, int line_no, ParsedLine& out, DiagnosticSink& sink);

/// "G5.2", "G1", "M30": a G (x10) or M number as a user writes it.
std::string g_name(int code10);

}  // namespace pcnc
