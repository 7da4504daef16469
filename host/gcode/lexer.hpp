// lexer.hpp — first stage of the G-code front end: one line of text to its words, its
// parameter assignments, its O-word and its message comment.
//
// RS274 lexing rules as CAM programs and LinuxCNC use them: letters in either case; spaces and
// tabs anywhere outside comments (even inside a number, "X 1 .5" is X1.5); numbers with or
// without sign, leading zeros and decimal point; comments in parentheses (nested ones, as
// Estlcam writes them, are accepted with a warning naming the column) and after ';'; '/' block
// delete at the start of a line; a line holding only '%' (program delimiter). A word's value
// may be a parameter, a function or a bracketed expression (expression.hpp), evaluated here
// against the parameters as they stand before this line's own assignments ('#1=2' is kept in
// `assignments` and applied by the caller after the line is read, as RS274NGC orders it).
// An O-word line (O100 sub, o<name> call [1] [2], O101 while [#1 LT 3], ...) is returned in
// `oword` for the control flow (control_flow.hpp); "O123" alone is a program number (and the
// start of a Fanuc subprogram that M98 calls). (MSG,...), (DEBUG,...) and (PRINT,...) are kept
// in `message` with their raw text.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "gcode/diagnostics.hpp"
#include "gcode/parameters.hpp"

namespace pcnc {

struct Word {
  char letter = 0;  // 'A'..'Z', or LinuxCNC's polar words '@' and '^'
  int column = 0;   // 1-based column of the letter
  double value = 0.0;
};

/// '#1=...' or '#<name>=...' on a line: applied after the whole line has been read.
struct Assignment {
  int number = 0;    // > 0: numbered parameter
  std::string name;  // else the normalized name
  double value = 0.0;
  int column = 0;
};

enum class OKind : std::uint8_t {
  kNone,
  kSub,
  kEndsub,
  kReturn,
  kCall,
  kIf,
  kElseif,
  kElse,
  kEndif,
  kWhile,
  kEndwhile,
  kDo,
  kRepeat,
  kEndrepeat,
  kBreak,
  kContinue
};

/// The O-word of a control-flow line.
struct OWord {
  OKind kind = OKind::kNone;
  std::string label;  // "100" for O100 (numbers compare by value), else the normalized name
  int column = 0;     // of the 'O'
  bool has_value = false;  // the one [expr] of if/elseif/while/repeat/return/endsub
  double value = 0.0;
  std::vector<double> args;  // call arguments, in order
};

// kProbeOpen/kProbeClose: LinuxCNC's probe log comments (PROBEOPEN name) and (PROBECLOSE).
enum class MessageKind : std::uint8_t { kNone, kMsg, kDebug, kPrint, kProbeOpen, kProbeClose };

struct LexedLine {
  static constexpr int kMaxWords = 64;
  Word words[kMaxWords];
  int count = 0;
  bool block_delete = false;    // the line starts with '/'
  bool percent = false;         // the line holds a '%' delimiter (nothing else)
  bool program_number = false;  // an O word alone on its line
  double program_value = 0.0;   // its number
  std::vector<Assignment> assignments;
  int assignment_count = 0;     // the first assignment_count entries are this line's
  OWord oword;
  MessageKind message = MessageKind::kNone;
  std::string message_text;     // after "MSG," / "DEBUG," / "PRINT," (raw, as written)
  int message_column = 0;

  bool empty() const { return count == 0 && assignment_count == 0 && message == MessageKind::kNone; }
};

/// Lexes one line (without its end-of-line characters), reading parameters from `params`
/// (nullptr: a program without parameters; '#' reads then see an empty store). Returns false
/// after reporting the first error of the line to `sink` (the rest of that line is not looked
/// at). With `skipping` (a line inside a branch or subroutine not being run) only an O-word
/// is recognized, nothing is evaluated and nothing is reported.
bool lex_line(std::string_view text, int line_no, LexedLine& out, DiagnosticSink& sink,
              const ParameterStore* params = nullptr, bool skipping = false);

}  // namespace pcnc
