// parser.cpp — modal-group sorting of the words of one line.
#include "gcode/parser.hpp"

#include <cmath>
#include <string>

namespace pcnc {

std::string g_name(int code10) {
  std::string s = "G" + std::to_string(code10 / 10);
  if (code10 % 10) s += "." + std::to_string(code10 % 10);
  return s;
}

bool parse_line(const LexedLine& lexed, int line_no, ParsedLine& out, DiagnosticSink& sink) {
  out.line = line_no;
  // Reset only the groups the previous line used (the line buffer is reused).
  for (std::uint32_t b = out.g_groups; b; b &= b - 1) out.g[static_cast<std::size_t>(__builtin_ctz(b))] = -1;
  for (std::uint32_t b = out.m_groups; b; b &= b - 1) out.m[static_cast<std::size_t>(__builtin_ctz(b))] = -1;
  out.g_groups = 0;
  out.m_groups = 0;
  out.present = 0;
  out.g80_col = 0;
  out.empty = lexed.count == 0;
  for (int i = 0; i < lexed.count; ++i) {
    const Word& w = lexed.words[i];
    if (w.letter == 'G') {
      const double x10 = w.value * 10.0;
      const long code = static_cast<long>(x10 + 0.5);  // w.value >= 0 is checked next
      if (w.value < 0.0 || std::fabs(x10 - static_cast<double>(code)) > 1e-6 || code > 9999) {
        sink.error(line_no, w.column, "bad G number; expected a G code such as G1 or G5.2");
        return false;
      }
      const int c = static_cast<int>(code);
      const int group = g_group(c);
      if (group < 0) {
        sink.error(line_no, w.column,
                   "unknown G code " + g_name(c) + "; expected an RS274 G code (docs/gcode.md lists them)");
        return false;
      }
      if (group == kGMotion && out.g[kGMotion] >= 0 && (c == 800) != (out.g[kGMotion] == 800)) {
        // "G80 G0": cancel the canned cycle, then select G0 (LinuxCNC-era posts write this).
        out.g80_col = c == 800 ? w.column : out.g_col[kGMotion];
        if (c == 800) continue;
      } else if (out.g[static_cast<std::size_t>(group)] >= 0) {
        sink.error(line_no, w.column,
                   g_name(c) + " and " + g_name(out.g[static_cast<std::size_t>(group)]) +
                       " are in the same modal group; expected at most one of them per line");
        return false;
      }
      out.g[static_cast<std::size_t>(group)] = static_cast<std::int16_t>(c);
      out.g_groups |= 1u << group;
      out.g_col[static_cast<std::size_t>(group)] = static_cast<std::int16_t>(w.column > 32767 ? 32767 : w.column);
    } else if (w.letter == 'M') {
      const long code = static_cast<long>(w.value + 0.5);  // w.value >= 0 is checked next
      if (w.value < 0.0 || std::fabs(w.value - static_cast<double>(code)) > 1e-6 || code > 9999) {
        sink.error(line_no, w.column, "bad M number; expected a whole number such as M3 or M30");
        return false;
      }
      const int c = static_cast<int>(code);
      const int group = m_group(c);
      if (group < 0) {
        sink.error(line_no, w.column,
                   "unknown M code M" + std::to_string(c) + "; expected an M code listed in docs/gcode.md");
        return false;
      }
      if (out.m[static_cast<std::size_t>(group)] >= 0) {
        sink.error(line_no, w.column,
                   "M" + std::to_string(c) + " and M" + std::to_string(out.m[static_cast<std::size_t>(group)]) +
                       " are in the same modal group; expected at most one of them per line");
        return false;
      }
      out.m[static_cast<std::size_t>(group)] = static_cast<std::int16_t>(c);
      out.m_groups |= 1u << group;
      out.m_col[static_cast<std::size_t>(group)] = static_cast<std::int16_t>(w.column > 32767 ? 32767 : w.column);
    } else {
      const auto i26 = static_cast<std::size_t>(word_slot(w.letter));
      const std::uint32_t bit = 1u << i26;
      if (out.present & bit) {
        sink.error(line_no, w.column,
                   std::string("second ") + w.letter + " word on one line; expected at most one " + w.letter +
                       " word per line");
        return false;
      }
      out.present |= bit;
      out.value[i26] = w.value;
      out.col[i26] = w.column;
    }
  }
  return true;
}

}  // namespace pcnc
