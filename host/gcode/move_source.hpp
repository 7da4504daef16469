// move_source.hpp — the head of the front-end pipeline (gcode/pipeline.hpp): source lines ->
// lexer -> parser -> interpreter -> Moves, one at a time.
//
// Reads the program line by line (LineReader) in fixed memory and handles what belongs to the
// text as a whole: '%' delimiters, '/' block delete, over-long lines, the program end (M2/M30,
// then only blanks and comments may follow) and a file that ends without one (an End move with
// a warning). Every problem goes to the DiagnosticSink; the source always ends with one End move.
#pragma once

#include <cstdint>

#include "config/config.hpp"
#include "gcode/diagnostics.hpp"
#include "gcode/interpreter.hpp"
#include "gcode/lexer.hpp"
#include "gcode/line_reader.hpp"
#include "gcode/move.hpp"
#include "gcode/parser.hpp"

namespace pcnc {

class MoveSource {
 public:
  MoveSource(LineReader& reader, const MachineConfig& config, const JobFrame& frame, DiagnosticSink& sink)
      : reader_(reader), sink_(sink), interp_(config, frame, sink) {}

  /// Next move; false once the End move has been returned.
  bool next(Move& m);

  /// After the End move: warns once if the file holds anything but blanks and comments after it.
  void check_trailing();

  std::uint64_t lines() const { return reader_.line_number(); }

 private:
  void read_line();

  LineReader& reader_;
  DiagnosticSink& sink_;
  Interpreter interp_;
  LexedLine lexed_;
  ParsedLine parsed_;
  MoveList pending_;
  int pos_ = 0;
  int last_line_ = 0;
  bool done_ = false;
  bool ended_by_m2_ = false;
  bool seen_content_ = false;
  bool seen_percent_ = false;
  bool percent_closed_ = false;
};

}  // namespace pcnc
