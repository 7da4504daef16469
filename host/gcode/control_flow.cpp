// control_flow.cpp — O-word control flow and subprograms (see control_flow.hpp).
#include "gcode/control_flow.hpp"

#include <cmath>
#include <stdexcept>

namespace pcnc {
namespace {

const char* keyword(OKind k) {
  switch (k) {
    case OKind::kSub: return "sub";
    case OKind::kEndsub: return "endsub";
    case OKind::kReturn: return "return";
    case OKind::kCall: return "call";
    case OKind::kIf: return "if";
    case OKind::kElseif: return "elseif";
    case OKind::kElse: return "else";
    case OKind::kEndif: return "endif";
    case OKind::kWhile: return "while";
    case OKind::kEndwhile: return "endwhile";
    case OKind::kDo: return "do";
    case OKind::kRepeat: return "repeat";
    case OKind::kEndrepeat: return "endrepeat";
    case OKind::kBreak: return "break";
    case OKind::kContinue: return "continue";
    case OKind::kNone: break;
  }
  return "?";
}

std::string name_of(const std::string& label) {
  if (!label.empty() && label[0] >= '0' && label[0] <= '9') return "O" + label;
  return "o<" + label + ">";
}

}  // namespace

std::string ControlFlow::ident(const std::string& label, bool fanuc) { return fanuc ? "P" + label : label; }

void ControlFlow::fail(int line, int column, std::string message) {
  sink_.error(line, column, std::move(message));
  failed_ = true;
  skip_ = Skip::kNone;
}

LineReader::Position ControlFlow::tell() const {
  LineReader::Position p = reader_->tell();
  p.file = file_;
  return p;
}

void ControlFlow::go(const LineReader::Position& pos, int line) {
  if (pos.file != file_) {
    file_ = pos.file;
    reader_ = file_ == 0 ? &main_ : files_[file_ - 1].get();
    sink_.set_file(reader_->path());
  }
  if (!reader_->seek(pos)) fail(line, 0, "cannot read the program file again (it changed or cannot be read); expected an unchanged file");
}

void ControlFlow::start_skip(Skip s, const std::string& label, int line) {
  skip_ = s;
  skip_label_ = label;
  skip_line_ = line;
}

bool ControlFlow::top_is(Kind k, const std::string& label) const {
  return !stack_.empty() && stack_.back().kind == k && stack_.back().label == label;
}

int ControlFlow::find_loop(const std::string& label) const {
  for (int i = static_cast<int>(stack_.size()) - 1; i >= 0; --i) {
    const Frame& f = stack_[static_cast<std::size_t>(i)];
    if (f.kind == Kind::kCall || f.kind == Kind::kFanucCall) return -1;  // not across a call
    if ((f.kind == Kind::kWhile || f.kind == Kind::kDo || f.kind == Kind::kRepeat) && f.label == label) return i;
  }
  return -1;
}

std::size_t ControlFlow::call_depth() const {
  std::size_t n = 0;
  for (const Frame& f : stack_) n += f.kind == Kind::kCall || f.kind == Kind::kFanucCall;
  return n;
}

int ControlFlow::innermost_loop_line() const {
  for (auto it = stack_.rbegin(); it != stack_.rend(); ++it) {
    if (it->kind == Kind::kWhile || it->kind == Kind::kDo || it->kind == Kind::kRepeat) return it->line;
  }
  return 0;
}

void ControlFlow::on_oword(const OWord& o, int line, const LineReader::Position& line_start) {
  if (failed_) return;
  if (skipping()) {
    skipped(o, line, line_start);
  } else {
    running(o, line, line_start);
  }
}

void ControlFlow::skipped(const OWord& o, int line, const LineReader::Position& line_start) {
  if (skip_ == Skip::kSubDefinition && o.kind == OKind::kSub) {
    return fail(line, o.column,
                name_of(o.label) + " sub inside the definition of " + name_of(skip_label_) +
                    ": subroutine definitions cannot be nested; expected " + name_of(skip_label_) + " endsub first");
  }
  if (o.label != skip_label_) return;
  switch (skip_) {
    case Skip::kSubDefinition:
      if (o.kind == OKind::kEndsub) skip_ = Skip::kNone;
      return;
    case Skip::kIfBranch:
      if (o.kind == OKind::kElseif || o.kind == OKind::kElse) {
        skip_ = Skip::kNone;
        go(line_start, line);  // read it again, running: its condition is evaluated then
      } else if (o.kind == OKind::kEndif) {
        skip_ = Skip::kNone;
        if (top_is(Kind::kIf, o.label)) stack_.pop_back();
      }
      return;
    case Skip::kIfEnd:
      if (o.kind == OKind::kEndif) {
        skip_ = Skip::kNone;
        if (top_is(Kind::kIf, o.label)) stack_.pop_back();
      }
      return;
    case Skip::kLoopEnd: {
      const bool closes_do = o.kind == OKind::kWhile && top_is(Kind::kDo, o.label);
      if (o.kind == OKind::kEndwhile || o.kind == OKind::kEndrepeat || closes_do) {
        skip_ = Skip::kNone;
        if (!stack_.empty() && stack_.back().label == o.label) stack_.pop_back();
      }
      return;
    }
    case Skip::kToDoWhile:
      if (o.kind == OKind::kWhile) {
        skip_ = Skip::kNone;
        go(line_start, line);  // the do-loop's condition, evaluated
      }
      return;
    case Skip::kNone: return;
  }
}

void ControlFlow::running(const OWord& o, int line, const LineReader::Position& line_start) {
  const std::string& label = o.label;
  const int col = o.column;
  const auto unmatched = [&](const char* opener) {
    fail(line, col,
         name_of(label) + " " + keyword(o.kind) + " without a matching " + opener + "; expected " + name_of(label) +
             " " + opener + " before it");
  };
  switch (o.kind) {
    case OKind::kSub:
      for (const Frame& f : stack_) {
        if (f.kind == Kind::kCall)
          return fail(line, col,
                      name_of(label) + " sub inside subroutine " + name_of(f.label) +
                          ": subroutine definitions cannot be nested; expected it outside every sub ... endsub");
      }
      subs_[ident(label, false)] = tell();
      start_skip(Skip::kSubDefinition, label, line);
      return;
    case OKind::kEndsub:
    case OKind::kReturn: leave_call(o.has_value, o.value, line, col); return;
    case OKind::kCall: call(o, line); return;
    case OKind::kIf: {
      Frame f{Kind::kIf, label, line};
      f.taken = o.value != 0.0;
      stack_.push_back(std::move(f));
      if (o.value == 0.0) start_skip(Skip::kIfBranch, label, line);
      return;
    }
    case OKind::kElseif:
    case OKind::kElse:
      if (!top_is(Kind::kIf, label)) return unmatched("if");
      if (stack_.back().taken) {
        start_skip(Skip::kIfEnd, label, line);
      } else if (o.kind == OKind::kElse || o.value != 0.0) {
        stack_.back().taken = true;
      } else {
        start_skip(Skip::kIfBranch, label, line);
      }
      return;
    case OKind::kEndif:
      if (!top_is(Kind::kIf, label)) return unmatched("if");
      stack_.pop_back();
      return;
    case OKind::kWhile:
      if (top_is(Kind::kDo, label)) {  // the end of a do-loop
        if (o.value != 0.0) {
          go(stack_.back().body, line);
        } else {
          stack_.pop_back();
        }
        return;
      }
      if (!(top_is(Kind::kWhile, label) && stack_.back().head.offset == line_start.offset)) {
        Frame f{Kind::kWhile, label, line};
        f.head = line_start;
        stack_.push_back(std::move(f));
      }
      if (o.value == 0.0) start_skip(Skip::kLoopEnd, label, line);
      return;
    case OKind::kEndwhile:
      if (!top_is(Kind::kWhile, label)) return unmatched("while");
      go(stack_.back().head, line);
      return;
    case OKind::kDo: {
      Frame f{Kind::kDo, label, line};
      f.body = tell();
      stack_.push_back(std::move(f));
      return;
    }
    case OKind::kRepeat: {
      Frame f{Kind::kRepeat, label, line};
      f.body = tell();
      f.count = std::floor(o.value);
      stack_.push_back(std::move(f));
      if (!(o.value >= 1.0)) start_skip(Skip::kLoopEnd, label, line);
      return;
    }
    case OKind::kEndrepeat:
      if (!top_is(Kind::kRepeat, label)) return unmatched("repeat");
      if (--stack_.back().count >= 1.0) {
        go(stack_.back().body, line);
      } else {
        stack_.pop_back();
      }
      return;
    case OKind::kBreak:
    case OKind::kContinue: {
      const int i = find_loop(label);
      if (i < 0) {
        return fail(line, col,
                    name_of(label) + " " + keyword(o.kind) + " outside a loop labelled " + name_of(label) +
                        "; expected it inside " + name_of(label) + " while, do or repeat");
      }
      stack_.resize(static_cast<std::size_t>(i) + 1);
      Frame& f = stack_.back();
      if (o.kind == OKind::kBreak) {
        start_skip(Skip::kLoopEnd, label, line);
      } else if (f.kind == Kind::kWhile) {
        go(f.head, line);
      } else if (f.kind == Kind::kRepeat) {
        if (--f.count >= 1.0) {
          go(f.body, line);
        } else {
          start_skip(Skip::kLoopEnd, label, line);
        }
      } else {
        start_skip(Skip::kToDoWhile, label, line);
      }
      return;
    }
    case OKind::kNone: return;
  }
}

void ControlFlow::call(const OWord& o, int line) {
  const LineReader::Position ret = tell();  // before find_sub reads ahead
  LineReader::Position body{};
  if (!find_sub(o.label, false, body)) {
    const bool named = !o.label.empty() && !(o.label[0] >= '0' && o.label[0] <= '9');
    return fail(line, o.column,
                "unknown subroutine " + name_of(o.label) + "; expected " + name_of(o.label) + " sub ... endsub in this file" +
                    (named ? " or in " + o.label + ".ngc beside it" : std::string()));
  }
  if (!params_.push_call(o.args.data(), static_cast<int>(o.args.size()))) {
    return fail(line, o.column,
                "subroutine calls nested more than " + std::to_string(ParameterStore::kMaxCallDepth) +
                    " deep (runaway recursion?); expected a recursion that ends");
  }
  Frame f{Kind::kCall, o.label, line};
  f.ret = ret;
  f.head = body;
  stack_.push_back(std::move(f));
  go(body, line);
}

void ControlFlow::leave_call(bool has_value, double value, int line, int column) {
  int i = static_cast<int>(stack_.size()) - 1;
  while (i >= 0 && stack_[static_cast<std::size_t>(i)].kind != Kind::kCall) --i;
  if (i < 0) return fail(line, column, "endsub/return outside a subroutine; expected it inside O.. sub ... endsub");
  const Frame f = stack_[static_cast<std::size_t>(i)];
  stack_.resize(static_cast<std::size_t>(i));
  params_.pop_call();
  params_.set_return_value(has_value, value);
  go(f.ret, line);
}

// Reads `r` (file index `file`) from where it is up to `stop_offset` in skip mode, recording
// every definition on the way; true with `body` once the one wanted (`key`) is seen.
bool ControlFlow::scan(LineReader& r, std::uint32_t file, std::uint64_t stop_offset, const std::string& key, bool fanuc,
                       LineReader::Position& body) {
  LexedLine lexed;
  DiagnosticSink quiet;
  std::string_view text;
  bool too_long = false;
  auto& table = fanuc ? programs_ : subs_;
  while (r.tell().offset < stop_offset && r.next(text, too_long)) {
    lex_line(text, static_cast<int>(r.line_number()), lexed, quiet, nullptr, true);
    LineReader::Position here = r.tell();
    here.file = file;
    if (lexed.program_number) {
      programs_.emplace("P" + lexed.oword.label, here);
    } else if (lexed.oword.kind == OKind::kSub) {
      subs_.emplace(lexed.oword.label, here);
    }
    const auto found = table.find(key);
    if (found != table.end()) {
      body = found->second;
      return true;
    }
  }
  return false;
}

bool ControlFlow::find_sub(const std::string& label, bool fanuc, LineReader::Position& body) {
  const std::string key = ident(label, fanuc);
  auto& table = fanuc ? programs_ : subs_;
  const auto it = table.find(key);
  if (it != table.end()) {
    body = it->second;
    return true;
  }
  // Read ahead in the file being read (then from its start), recording every definition on
  // the way; the position is restored (the caller then goes to the body).
  const LineReader::Position back = tell();
  bool found = scan(*reader_, file_, ~std::uint64_t{0}, key, fanuc, body);
  if (!found && reader_->seek(LineReader::Position{})) found = scan(*reader_, file_, back.offset, key, fanuc, body);
  reader_->seek(back);
  if (found) return true;
  return !fanuc && find_sub_file(label, body);
}

// LinuxCNC's subroutine files: o<name> call, not defined in the program, runs <name>.ngc
// beside it (the file holds "o<name> sub ... o<name> endsub").
bool ControlFlow::find_sub_file(const std::string& label, LineReader::Position& body) {
  if (main_.path().empty() || label.empty() || (label[0] >= '0' && label[0] <= '9')) return false;
  for (char c : label) {
    if (c == '/' || c == '.' || c == '\\') return false;  // a name, never a path
  }
  if (files_.size() >= kMaxSubFiles) return false;
  const std::string& main_path = main_.path();
  const std::size_t slash = main_path.rfind('/');
  const std::string path = (slash == std::string::npos ? std::string() : main_path.substr(0, slash + 1)) + label + ".ngc";
  std::unique_ptr<LineReader> r;
  try {
    r = std::make_unique<LineReader>(path);
  } catch (const std::exception&) {
    return false;
  }
  const auto file = static_cast<std::uint32_t>(files_.size() + 1);
  const bool found = scan(*r, file, ~std::uint64_t{0}, label, false, body);
  files_.push_back(std::move(r));
  return found;
}

void ControlFlow::on_program_number(const std::string& label, int line) {
  (void)line;
  if (failed_ || skipping()) return;
  programs_.emplace("P" + label, tell());
}

void ControlFlow::m98(double p, bool has_l, double l, int line, int column) {
  if (failed_) return;
  if (!(p >= 0.0) || p != std::floor(p)) return fail(line, column, "M98 needs P with a program number; expected M98 P1000");
  const std::string label = std::to_string(static_cast<long>(p));
  const double count = has_l ? std::floor(l) : 1.0;
  if (!(count >= 0.0)) return fail(line, column, "M98 L must not be negative; expected the number of times to run it");
  if (count == 0.0) return;  // L0: not run at all (LinuxCNC)
  const LineReader::Position ret = tell();  // before find_sub reads ahead
  LineReader::Position body{};
  if (!find_sub(label, true, body)) {
    return fail(line, column, "M98 P" + label + ": no subprogram O" + label + " in this file; expected a line O" +
                                  label + " starting it, ended by M99");
  }
  int depth = 0;
  for (const Frame& f : stack_) depth += (f.kind == Kind::kFanucCall || f.kind == Kind::kCall) ? 1 : 0;
  if (depth >= ParameterStore::kMaxCallDepth)
    return fail(line, column, "subprogram calls nested too deeply; expected a recursion that ends");
  Frame f{Kind::kFanucCall, label, line};
  f.body = body;
  f.ret = ret;
  f.count = count;
  stack_.push_back(std::move(f));
  go(body, line);
}

bool ControlFlow::m99(int line, int column) {
  (void)column;
  int i = static_cast<int>(stack_.size()) - 1;
  while (i >= 0 && stack_[static_cast<std::size_t>(i)].kind != Kind::kFanucCall) --i;
  if (i < 0) return false;
  stack_.resize(static_cast<std::size_t>(i) + 1);
  Frame& f = stack_.back();
  if (--f.count >= 1.0) {
    go(f.body, line);
  } else {
    const LineReader::Position ret = f.ret;
    stack_.pop_back();
    go(ret, line);
  }
  return true;
}

void ControlFlow::end_of_input(int line) {
  if (failed_) return;
  switch (skip_) {
    case Skip::kSubDefinition:
      return fail(skip_line_, 0, name_of(skip_label_) + " sub has no endsub; expected " + name_of(skip_label_) + " endsub");
    case Skip::kIfBranch:
    case Skip::kIfEnd:
      return fail(skip_line_, 0, name_of(skip_label_) + " if has no endif; expected " + name_of(skip_label_) + " endif");
    case Skip::kLoopEnd:
    case Skip::kToDoWhile:
      return fail(skip_line_, 0, name_of(skip_label_) + " loop has no end; expected its endwhile, endrepeat or while");
    case Skip::kNone: break;
  }
  if (stack_.empty()) return;
  const Frame& f = stack_.back();
  const char* want = f.kind == Kind::kIf        ? "endif"
                     : f.kind == Kind::kWhile   ? "endwhile"
                     : f.kind == Kind::kDo      ? "while"
                     : f.kind == Kind::kRepeat  ? "endrepeat"
                     : f.kind == Kind::kCall    ? "endsub"
                                                : "M99";
  fail(f.line, 0,
       name_of(f.label) + " opened at line " + std::to_string(f.line) + " is not closed at the end of the file (line " +
           std::to_string(line) + "); expected " + want);
}

}  // namespace pcnc
