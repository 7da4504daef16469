// move_source.hpp — the head of the front-end pipeline (gcode/pipeline.hpp): source lines ->
// lexer -> control flow -> parser -> interpreter -> Moves, one at a time.
//
// Reads the program line by line (LineReader) in fixed memory and handles what belongs to the
// text as a whole: '%' delimiters, '/' block delete, over-long lines, the line's parameter
// assignments (applied after the whole line is read, before its words run, as RS274NGC
// orders it), its message comment ((MSG,...) raw, (DEBUG,...) and (PRINT,...) with the
// parameters substituted, handed to the message handler in program order among the moves),
// O-word control flow and M98/M99 subprograms (control_flow.hpp), the bound on executed
// lines (a loop that never ends is an error, not a hang), the program end (M2/M30, then only
// blanks, comments and subroutine definitions may follow) and a file that ends without one (an
// End move with a warning). Every problem goes to the DiagnosticSink; the source always ends
// with one End move.
#pragma once

#include <cstdint>
#include <functional>
#include <string>

#include "config/config.hpp"
#include "gcode/control_flow.hpp"
#include "gcode/diagnostics.hpp"
#include "gcode/interpreter.hpp"
#include "gcode/lexer.hpp"
#include "gcode/line_reader.hpp"
#include "gcode/move.hpp"
#include "gcode/parameters.hpp"
#include "gcode/parser.hpp"
#include "gcode/ruled_reader.hpp"

namespace pcnc {

/// A message comment as it runs: (MSG,...) text as written, (DEBUG,...)/(PRINT,...) with the
/// parameters substituted.
struct ProgramMessage {
  MessageKind kind = MessageKind::kMsg;
  int line = 0;
  std::string text;
};
using MessageHandler = std::function<void(const ProgramMessage&)>;

class MoveSource {
 public:
  MoveSource(LineReader& reader, const MachineConfig& config, const JobFrame& frame, DiagnosticSink& sink);

  /// Next move; false once the End move has been returned.
  bool next(Move& m);

  /// After the End move: warns once if the file holds anything but blanks, comments and
  /// subroutine definitions after it.
  void check_trailing();

  /// Called for each message comment as its line runs (none by default).
  void set_message_handler(MessageHandler handler) { on_message_ = std::move(handler); }
  /// Called after every kLineHookEvery lines run (loops and subroutines counted as they run):
  /// the progress of a long check. The hook may throw; the exception leaves next().
  static constexpr std::uint64_t kLineHookEvery = 1024;
  void set_line_hook(std::function<void()> hook) { line_hook_ = std::move(hook); }

  std::uint64_t lines() const { return reader_.line_number(); }
  std::uint64_t executed_lines() const { return executed_; }
  const Interpreter& interpreter() const { return interp_; }
  const ParameterStore& parameters() const { return params_; }

 private:
  void read_line();
  void sync_call_level(int line_no);
  void run_line(int line_no, const LineReader::Position& start);
  bool apply_assignments(int line_no);
  void message(int line_no);
  void end_program(int line_no, bool warn_no_end);
  bool ruled_group_line(int line_no);
  bool ruled_failed_ = false;  // the open G5.4 group was refused (machine without 5 axes)

  LineReader& reader_;
  DiagnosticSink& sink_;
  ParameterStore params_;
  Interpreter interp_;
  ControlFlow flow_;
  RuledGroupReader ruled_;  // G5.4 ... G5.5 groups, read before the parser sees their lines
  LexedLine lexed_;
  ParsedLine parsed_;
  MoveList pending_;
  MessageHandler on_message_;
  std::function<void()> line_hook_;
  std::uint64_t executed_ = 0;
  std::uint64_t max_executed_ = 0;
  int pos_ = 0;
  int last_line_ = 0;
  bool done_ = false;
  bool ended_by_m2_ = false;
  bool seen_content_ = false;
  bool seen_percent_ = false;
  bool percent_closed_ = false;
};

}  // namespace pcnc
