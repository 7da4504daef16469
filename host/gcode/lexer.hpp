// lexer.hpp — first stage of the G-code front end: one line of text to a list of words.
//
// RS274 lexing rules as CAM programs use them: letters in either case; spaces and tabs anywhere
// outside comments (even inside a number, "X 1 .5" is X1.5); numbers with or without sign,
// leading zeros and decimal point; comments in parentheses and after ';'; '/' block delete at
// the start of a line; a line holding only '%' (program delimiter); "O123" alone on a line
// (program number). A value may also be a constant bracket expression ("[1 + 2 * sqrt[2]]",
// functions in degrees as in LinuxCNC). Parameters ('#'), O-word control flow and anything
// else is an error naming the column. No allocation: words go into a fixed array.
#pragma once

#include <string_view>

#include "gcode/diagnostics.hpp"

namespace pcnc {

struct Word {
  char letter = 0;  // 'A'..'Z'
  int column = 0;   // 1-based column of the letter
  double value = 0.0;
};

struct LexedLine {
  static constexpr int kMaxWords = 64;
  Word words[kMaxWords];
  int count = 0;
  bool block_delete = false;    // the line starts with '/'
  bool percent = false;         // the line holds a '%' delimiter (nothing else)
  bool program_number = false;  // an O word alone on its line
};

/// Lexes one line (without its end-of-line characters). Returns false after reporting the first
/// error of the line to `sink` (the rest of that line is not looked at).
bool lex_line(std::string_view text, int line_no, LexedLine& out, DiagnosticSink& sink);

/// Parses a plain decimal number (optional sign, digits, optional point, digits) exactly as
/// std::from_chars would, faster on the short numbers G-code is made of. Returns the number of
/// characters used (0: not a number).
std::size_t parse_decimal(const char* first, const char* last, double& out);

}  // namespace pcnc
