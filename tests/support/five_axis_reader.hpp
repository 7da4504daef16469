// five_axis_reader.hpp — reads a 5-axis program of the LinuxCNC XYZAC demos' dialect
// (M428 ... M429, G0/G1 X Y Z A C F, G93/G94) with the project's lexer (host/gcode/lexer.hpp),
// for tests that check examples/5axis/ against the kinematics word by word (the front end's own
// run is checked separately, through run_check_command): the tests read the words and follow
// the modal state themselves. Every line but M428/M429 must also pass the parser
// (host/gcode/parser.hpp: its G and M words known, none twice). Header only.
#pragma once


#include <cstdint>
#include <string>
#include <vector>

#include "gcode/diagnostics.hpp"
#include "gcode/lexer.hpp"
#include "gcode/parser.hpp"
#include "geometry/vec3.hpp"
#include "text_lines.hpp"

namespace pcnc::test {

/// One motion line: where it goes (the words not written keep their last value).
struct ReadPose {
  int line = 0;
  bool rapid = false;
  bool tcp = false;           // M428 in effect
  bool inverse_time = false;  // G93 in effect
  bool has_f = false;         // an F word on this line
  double f = 0.0;
  Vec3 tip{};                 // program coordinates
  double a_deg = 0.0, c_deg = 0.0;
};

struct ReadProgram {
  std::vector<ReadPose> poses;
  bool ended = false;       // M2 or M30 seen
  bool tcp_at_end = true;   // M428 still on at the end
  std::vector<std::string> errors;
  std::uint64_t warnings = 0;  // the lexer's (a nested comment, say)
};

/// Starts at program (0, 0, 0), A = C = 0 (the home pose of desktop-5axis under its G54).
inline ReadProgram read_five_axis_program(const std::string& text) {
  ReadProgram r;
  DiagnosticSink sink("program");
  bool tcp = false, inverse_time = false, rapid = true;
  ReadPose at;
  int n = 0;
  for (const std::string& line : split_lines(text)) {
    ++n;
    LexedLine lx;
    if (!lex_line(line, n, lx, sink)) {
      r.errors.push_back("line " + std::to_string(n) + " does not lex");
      continue;
    }
    bool tcp_word = false;
    for (int i = 0; i < lx.count; ++i)
      tcp_word |= lx.words[i].letter == 'M' && (lx.words[i].value == 428.0 || lx.words[i].value == 429.0);
    ParsedLine parsed;
    if (!tcp_word && !parse_line(lx, n, parsed, sink)) r.errors.push_back("line " + std::to_string(n) + " does not parse");
    bool motion = false;
    for (int i = 0; i < lx.count; ++i) {
      const Word& w = lx.words[i];
      const double v = w.value;
      switch (w.letter) {
        case 'G':
          if (v == 0.0 || v == 1.0) { rapid = v == 0.0; motion = true; }
          else if (v == 93.0) inverse_time = true;
          else if (v == 94.0) inverse_time = false;
          break;
        case 'M':
          if (v == 428.0) tcp = true;
          else if (v == 429.0) tcp = false;
          else if (v == 2.0 || v == 30.0) r.ended = true;
          break;
        case 'X': at.tip[0] = v; motion = true; break;
        case 'Y': at.tip[1] = v; motion = true; break;
        case 'Z': at.tip[2] = v; motion = true; break;
        case 'A': at.a_deg = v; motion = true; break;
        case 'C': at.c_deg = v; motion = true; break;
        default: break;
      }
    }
    at.has_f = false;
    for (int i = 0; i < lx.count; ++i)
      if (lx.words[i].letter == 'F') { at.has_f = true; at.f = lx.words[i].value; }
    if (!motion) continue;
    at.line = n;
    at.rapid = rapid;
    at.tcp = tcp;
    at.inverse_time = inverse_time;
    r.poses.push_back(at);
  }
  r.tcp_at_end = tcp;
  r.warnings = sink.warning_count();
  return r;
}

}  // namespace pcnc::test
