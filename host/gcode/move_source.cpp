// move_source.cpp — lines to Moves: the lexer, parser and interpreter stages (see move_source.hpp).
#include "gcode/move_source.hpp"

#include <algorithm>
#include <string_view>

namespace pcnc {

bool MoveSource::next(Move& m) {
  while (pos_ >= pending_.count) {
    if (done_) return false;
    pending_.clear();
    pos_ = 0;
    read_line();
  }
  m = pending_.moves[pos_++];
  if (m.kind == MoveKind::kEnd) {
    done_ = true;
    pending_.clear();
    pos_ = 0;
  }
  return true;
}

void MoveSource::check_trailing() {
  if (!ended_by_m2_) return;
  std::string_view text;
  bool too_long = false;
  DiagnosticSink scratch;
  while (reader_.next(text, too_long)) {
    const int line_no = static_cast<int>(reader_.line_number());
    if (!lex_line(text, line_no, lexed_, scratch) || lexed_.count > 0 || lexed_.block_delete) {
      sink_.warning(line_no, 0, "after-end", "text after the program end (M2/M30) is not executed");
      return;
    }
  }
}

void MoveSource::read_line() {
  std::string_view text;
  bool too_long = false;
  if (!percent_closed_ && reader_.next(text, too_long)) {
    const int line_no = static_cast<int>(std::min<std::uint64_t>(reader_.line_number(), 0x7fffffff));
    last_line_ = line_no;
    if (too_long) {
      sink_.error(line_no, static_cast<int>(LineReader::kMaxLine),
                  "line too long; expected at most 65536 characters per line");
      return;
    }
    if (!lex_line(text, line_no, lexed_, sink_)) return;
    if (lexed_.block_delete) {
      sink_.warning(line_no, 1, "block-delete",
                    "'/' block delete: the line is skipped (the block delete switch is always on)");
      return;
    }
    if (lexed_.percent) {
      if (seen_content_ || seen_percent_) {
        percent_closed_ = true;  // the closing '%': the program ends here
      }
      seen_percent_ = true;
      return;
    }
    if (lexed_.count == 0) return;
    seen_content_ = true;
    if (!parse_line(lexed_, line_no, parsed_, sink_)) return;
    interp_.execute(parsed_, pending_);
    if (interp_.ended()) ended_by_m2_ = true;
    return;
  }
  // End of input (or closing '%') without M2/M30.
  interp_.end_of_input(last_line_);
  sink_.warning(last_line_, 0, "no-end", "the program has no M2/M30; it ends at the end of the file");
  pending_.push(interp_.end_move(last_line_));
}

}  // namespace pcnc
