// move_source.cpp — lines to Moves: the lexer, control flow, parser and interpreter stages
// (see move_source.hpp).
#include "gcode/move_source.hpp"

#include <algorithm>
#include <cmath>
#include <string_view>

#include "gcode/expression.hpp"
#include "gcode/words.hpp"

namespace pcnc {

MoveSource::MoveSource(LineReader& reader, const MachineConfig& config, const JobFrame& frame, DiagnosticSink& sink)
    : reader_(reader),
      sink_(sink),
      interp_(config, frame, sink, params_),
      flow_(reader, params_, sink),
      max_executed_(static_cast<std::uint64_t>(std::max(1.0, config.gcode.max_executed_lines))) {}

bool MoveSource::next(Move& m) {
  while (pos_ >= pending_.count) {
    if (done_) return false;
    if (interp_.probe_sync()) return false;  // a probing move whose result is not known yet: stop here
    pending_.clear();
    pos_ = 0;
    read_line();
  }
  m = pending_.moves[static_cast<std::size_t>(pos_++)];
  if (m.kind == MoveKind::kEnd) {
    done_ = true;
    pending_.clear();
    pos_ = 0;
  }
  return true;
}

void MoveSource::check_trailing() {
  if (!ended_by_m2_ || !flow_.in_main_file()) return;
  std::string_view text;
  bool too_long = false;
  DiagnosticSink scratch;
  bool in_sub = false;
  while (reader_.next(text, too_long)) {
    const int line_no = static_cast<int>(reader_.line_number());
    // Subroutine definitions after the end are where LinuxCNC programs keep them.
    lex_line(text, line_no, lexed_, scratch, nullptr, true);
    if (lexed_.program_number) return;  // Fanuc subprograms (O1000 ... M99) follow the end
    if (lexed_.oword.kind == OKind::kSub) in_sub = true;
    if (in_sub) {
      if (lexed_.oword.kind == OKind::kEndsub) in_sub = false;
      continue;
    }
    if (lexed_.oword.kind != OKind::kNone) continue;
    if (!lex_line(text, line_no, lexed_, scratch, &params_, false) || !lexed_.empty() || lexed_.block_delete) {
      sink_.warning(line_no, 0, "after-end", "text after the program end (M2/M30) is not executed");
      return;
    }
  }
}

// A line of a G5.4 ... G5.5 group goes to the group reader instead of the parser; a group closed
// without errors becomes the interpreter's ruled move. On a machine without 5-axis kinematics the
// G5.4 is refused here (the group is still read to its G5.5, without further errors).
bool MoveSource::ruled_group_line(int line_no) {
  RuledModal modal = interp_.ruled_modal();
  const bool machine = interp_.ruled_machine();
  if (!machine) modal.tcp = true;  // the machine's error below stands for the TCP rule
  if (!ruled_.open()) {
    bool opens = false;
    for (int i = 0; i < lexed_.count; ++i) {
      const Word& w = lexed_.words[static_cast<std::size_t>(i)];
      if (w.letter == 'G' && std::abs(w.value - 5.4) < 1e-9) {
        opens = true;
        if (!machine) {
          sink_.error(line_no, w.column,
                      "G5.4: a ruled-surface piece needs a 5-axis machine (rotary joints and a [kinematics] section); "
                      "this machine has none");
          ruled_failed_ = true;
        }
      }
    }
    if (opens && machine) ruled_failed_ = false;
  }
  interp_.set_line(line_no);
  if (!ruled_.take(lexed_, line_no, modal, sink_)) return false;
  RuledGroup group;
  if (ruled_.take_group(group) && !ruled_failed_) interp_.ruled_group(group, pending_);
  return true;
}

void MoveSource::end_program(int line_no, bool warn_no_end) {
  ruled_.finish(sink_);
  flow_.end_of_input(line_no);
  interp_.end_of_input(line_no);
  if (warn_no_end)
    sink_.warning(line_no, 0, "no-end", "the program has no M2/M30; it ends at the end of the file");
  pending_.push(interp_.end_move(line_no));
}

void MoveSource::read_line() {
  std::string_view text;
  bool too_long = false;
  LineReader& reader = flow_.reader();  // the program, or a subroutine file while in it
  const LineReader::Position start = flow_.tell();
  if (percent_closed_ || flow_.failed() || !reader.next(text, too_long)) {
    // End of input (or closing '%', or a lost control flow) without M2/M30.
    end_program(last_line_, !flow_.failed());
    return;
  }
  const int line_no = static_cast<int>(std::min<std::uint64_t>(reader.line_number(), 0x7fffffff));
  last_line_ = line_no;
  if (line_hook_ && (executed_ + 1) % kLineHookEvery == 0) line_hook_();
  if (++executed_ > max_executed_) {
    const int loop = flow_.innermost_loop_line();
    sink_.error(loop > 0 ? loop : line_no, 0,
                "the program ran more than " + std::to_string(max_executed_) + " lines" +
                    (loop > 0 ? " in the loop that starts here (at line " + std::to_string(line_no) + ")"
                              : std::string()) +
                    "; expected a loop that ends (config gcode.max_executed_lines)");
    pending_.push(interp_.end_move(line_no));
    return;
  }
  if (too_long) {
    if (flow_.skipping()) return;
    sink_.error(line_no, static_cast<int>(LineReader::kMaxLine), "line too long; expected at most 65536 characters per line");
    return;
  }
  if (flow_.skipping()) {
    lex_line(text, line_no, lexed_, sink_, &params_, true);
    if (lexed_.oword.kind != OKind::kNone) flow_.on_oword(lexed_.oword, line_no, start);
    return;
  }
  if (!lex_line(text, line_no, lexed_, sink_, &params_)) return;
  run_line(line_no, start);
}

bool MoveSource::apply_assignments(int line_no) {
  for (int i = 0; i < lexed_.assignment_count; ++i) {
    const Assignment& a = lexed_.assignments[static_cast<std::size_t>(i)];
    std::string why;
    const bool ok = a.number > 0 ? interp_.write_parameter(a.number, a.value, why) : params_.write(a.name, a.value, why);
    if (!ok) {
      sink_.error(line_no, a.column, why);
      return false;
    }
  }
  return true;
}

void MoveSource::message(int line_no) {
  if (lexed_.message == MessageKind::kNone) return;
  if (lexed_.message == MessageKind::kProbeOpen || lexed_.message == MessageKind::kProbeClose) {
    // the probe log (docs/probe.md): the name as written, trimmed; the runner writes the file
    std::string name = lexed_.message == MessageKind::kProbeOpen ? lexed_.message_text : std::string();
    const auto first = name.find_first_not_of(" \t");
    const auto last = name.find_last_not_of(" \t");
    interp_.set_probe_log(first == std::string::npos ? std::string() : name.substr(first, last - first + 1));
    return;
  }
  if (lexed_.message == MessageKind::kDebug) {  // #5599 = 0 hides them (LinuxCNC)
    double shown = 1.0;
    std::string why;
    if (params_.read(ParameterStore::kDebugOutput, shown, why) && shown == 0.0) return;
  }
  ProgramMessage m;
  m.kind = lexed_.message;
  m.line = line_no;
  m.text = lexed_.message == MessageKind::kMsg ? lexed_.message_text : substitute_parameters(lexed_.message_text, params_);
  if (on_message_) on_message_(m);
}

void MoveSource::run_line(int line_no, const LineReader::Position& start) {
  if (lexed_.block_delete) {
    sink_.warning(line_no, 1, "block-delete", "'/' block delete: the line is skipped (the block delete switch is always on)");
    return;
  }
  if (lexed_.percent) {
    if (seen_content_ || seen_percent_) percent_closed_ = true;  // the closing '%': the program ends here
    seen_percent_ = true;
    return;
  }
  if (lexed_.program_number) {
    flow_.on_program_number(lexed_.oword.label, line_no);
    return;
  }
  if (lexed_.oword.kind != OKind::kNone) {
    seen_content_ = true;
    if (!apply_assignments(line_no)) return;
    flow_.on_oword(lexed_.oword, line_no, start);
    sync_call_level(line_no);
    return;
  }
  if (lexed_.empty()) return;
  seen_content_ = true;
  if (ruled_group_line(line_no)) return;
  if (!parse_line(lexed_, line_no, parsed_, sink_)) return;
  interp_.set_line(line_no);
  if (!apply_assignments(line_no)) return;
  message(line_no);
  interp_.execute(parsed_, pending_);
  if (interp_.ended()) {
    ended_by_m2_ = true;
    return;
  }
  const int sub = parsed_.m[kMSubprogram];
  if (sub == 98) {
    flow_.m98(parsed_.has('P') ? parsed_.get('P') : -1.0, parsed_.has('L'), parsed_.get('L'), line_no,
              parsed_.m_col[kMSubprogram]);
  } else if (sub == 99 && !flow_.m99(line_no, parsed_.m_col[kMSubprogram])) {
    sink_.error(line_no, parsed_.m_col[kMSubprogram],
                "M99 outside a subprogram (pcnc does not restart the main program); expected M99 only at the end of "
                "a subprogram called by M98, and M2/M30 to end the program");
  }
  if (sub == 98 || sub == 99) sync_call_level(line_no);
}

// The interpreter's call levels (M70-M73's saved modal states) follow the control flow's calls:
// a level for each call entered; a level left restores what M73 saved there.
void MoveSource::sync_call_level(int line_no) {
  const std::size_t depth = flow_.call_depth();
  while (interp_.call_level() < depth) interp_.enter_call();
  while (interp_.call_level() > depth) interp_.leave_call(line_no);
}

}  // namespace pcnc
