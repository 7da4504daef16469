// control_flow.hpp — O-word control flow and subprograms, between the lexer and the
// interpreter (MoveSource drives it): which line is read next.
//
// LinuxCNC's O-words: `sub`/`endsub`/`return` (arguments in #1-#30, a value in #<_value>),
// `call`, `if`/`elseif`/`else`/`endif`, `while`/`endwhile`, `do`/`while`, `repeat`/`endrepeat`,
// `break`, `continue`, with numbered (O100) or named (o<name>) labels; and Fanuc's
// `M98 P<program> L<count>` calling `O<program>` ... `M99`. The file is not held in memory:
// a loop's head, a subroutine's body and a call's return are positions in the file
// (LineReader::tell/seek), so a straight-line program still streams in fixed memory and a
// loop run 10^6 times costs no more memory than one run. A subroutine defined after the main
// program (after M2, as LinuxCNC allows) is found by reading ahead for its `sub` line.
//
// Lines the flow passes over (a false branch, a subroutine's definition, the rest of a loop
// after `break`) are lexed with `skipping` set: only their O-word is looked at.
// A named subroutine the program does not define is looked for, as LinuxCNC does, in a file of
// its name beside the program (o<drill> call -> drill.ngc, name in lower case), which holds its
// `sub ... endsub`; the lines read then are that file's (moves and messages name its lines).
// A control-flow error ends the program (nothing after it is run): the flow is lost.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

#include "gcode/diagnostics.hpp"
#include "gcode/lexer.hpp"
#include "gcode/line_reader.hpp"
#include "gcode/parameters.hpp"

namespace pcnc {

class ControlFlow {
 public:
  ControlFlow(LineReader& reader, ParameterStore& params, DiagnosticSink& sink)
      : main_(reader), reader_(&reader), params_(params), sink_(sink) {}

  /// The file lines are read from now (the program, or a subroutine file while in it).
  LineReader& reader() { return *reader_; }
  /// Where the next line starts, in the file being read.
  LineReader::Position tell() const;
  /// True while the program's own file is being read.
  bool in_main_file() const { return file_ == 0; }

  /// True while lines are passed over (read with `skipping`).
  bool skipping() const { return skip_ != Skip::kNone; }
  /// True once an error has made the flow unusable (the program ends there).
  bool failed() const { return failed_; }

  /// A line's O-word, running or skipping. `line_start` is where the line began (tell()
  /// before it was read).
  void on_oword(const OWord& o, int line, const LineReader::Position& line_start);
  /// "O123" alone on a line (a program number, or the start of a Fanuc subprogram).
  void on_program_number(const std::string& label, int line);
  /// M98 P<program> L<count> on `line`, after the line's other words ran.
  void m98(double p, bool has_l, double l, int line, int column);
  /// M99: the end of a Fanuc subprogram. False when no subprogram is running (the caller
  /// reports what M99 means there).
  bool m99(int line, int column);
  /// The input ended: reports what is still open.
  void end_of_input(int line);

  /// The loop or call the program is in (for "the program loops" messages); 0: none.
  int innermost_loop_line() const;
  /// How many subroutine calls (o-word calls and M98) are running: 0 in the main program.
  std::size_t call_depth() const;

 private:
  enum class Skip : std::uint8_t { kNone, kIfBranch, kIfEnd, kLoopEnd, kSubDefinition, kToDoWhile };
  enum class Kind : std::uint8_t { kIf, kWhile, kDo, kRepeat, kCall, kFanucCall };
  struct Frame {
    Kind kind;
    std::string label;
    int line = 0;                    // of its opening line
    LineReader::Position head{};     // while: its own line (re-evaluated); call: the body
    LineReader::Position body{};     // do/repeat/fanuc: after the opening line
    LineReader::Position ret{};      // call: after the call line
    double count = 0.0;              // repeat / M98 L: runs left
    bool taken = false;              // if: a branch has run
  };

  void running(const OWord& o, int line, const LineReader::Position& line_start);
  void skipped(const OWord& o, int line, const LineReader::Position& line_start);
  void fail(int line, int column, std::string message);
  void go(const LineReader::Position& pos, int line);
  void start_skip(Skip s, const std::string& label, int line);
  bool top_is(Kind k, const std::string& label) const;
  int find_loop(const std::string& label) const;  // index in stack_, -1 if none
  void call(const OWord& o, int line);
  void leave_call(bool has_value, double value, int line, int column);
  bool find_sub(const std::string& label, bool fanuc, LineReader::Position& body);
  static std::string ident(const std::string& label, bool fanuc);

  bool scan(LineReader& r, std::uint32_t file, std::uint64_t stop_offset, const std::string& key, bool fanuc,
            LineReader::Position& body);
  bool find_sub_file(const std::string& label, LineReader::Position& body);

  static constexpr std::size_t kMaxSubFiles = 64;
  LineReader& main_;
  LineReader* reader_;  // the file being read
  std::uint32_t file_ = 0;
  std::vector<std::unique_ptr<LineReader>> files_;  // subroutine files, index + 1
  ParameterStore& params_;
  DiagnosticSink& sink_;
  std::vector<Frame> stack_;
  Skip skip_ = Skip::kNone;
  std::string skip_label_;
  int skip_line_ = 0;                // where the skip started (for "never closed" messages)
  std::string pending_branch_;       // an if whose next elseif/else is to be evaluated
  std::unordered_map<std::string, LineReader::Position> subs_;      // label -> body
  std::unordered_map<std::string, LineReader::Position> programs_;  // Fanuc O-number -> body
  bool failed_ = false;
};

}  // namespace pcnc
