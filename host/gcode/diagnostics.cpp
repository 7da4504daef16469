// diagnostics.cpp — bounded collection and the one text form of front-end diagnostics.
#include "gcode/diagnostics.hpp"

namespace pcnc {

std::string format_diagnostic(const Diagnostic& d) {
  std::string s = d.file;
  if (d.line > 0) {
    s += ':';
    s += std::to_string(d.line);
    if (d.column > 0) {
      s += ':';
      s += std::to_string(d.column);
    }
  }
  s += d.severity == Diagnostic::Severity::kError ? ": error: " : ": warning: ";
  s += d.message;
  return s;
}

void DiagnosticSink::place(int& line, int& column, std::string& message) const {
  if (!places_ || line < 1 || static_cast<std::size_t>(line) > places_->size()) return;
  const SourcePlace& p = (*places_)[static_cast<std::size_t>(line - 1)];
  line = p.line;
  column = p.column;
  if (!p.path.empty()) message = p.path + ": " + message;
}

int DiagnosticSink::file_line(int line) const {
  if (!places_ || line < 1 || static_cast<std::size_t>(line) > places_->size()) return line;
  return (*places_)[static_cast<std::size_t>(line - 1)].line;
}

void DiagnosticSink::error(int line, int column, std::string message) {
  ++error_count_;
  if (error_count_ > kMaxErrors) return;
  place(line, column, message);
  kept_.push_back({Diagnostic{Diagnostic::Severity::kError, file_, line, column, std::move(message)}, {}, 0});
}

void DiagnosticSink::warning(int line, int column, std::string_view key, std::string message) {
  ++warning_count_;
  if (!key.empty()) {
    for (Kept& k : kept_) {
      if (k.d.severity == Diagnostic::Severity::kWarning && k.key == key) {
        ++k.repeats;
        return;
      }
    }
  }
  if (kept_.size() >= 4 * kMaxErrors) {  // bounded even for unkeyed warnings
    ++dropped_warnings_;
    return;
  }
  place(line, column, message);
  kept_.push_back(
      {Diagnostic{Diagnostic::Severity::kWarning, file_, line, column, std::move(message)}, std::string(key), 0});
}

bool DiagnosticSink::repeat(std::string_view key) {
  if (key.empty()) return false;
  for (Kept& k : kept_) {
    if (k.d.severity == Diagnostic::Severity::kWarning && k.key == key) {
      ++k.repeats;
      ++warning_count_;
      return true;
    }
  }
  return false;
}

std::vector<Diagnostic> DiagnosticSink::take() {
  std::vector<Diagnostic> out;
  out.reserve(kept_.size() + 2);
  for (Kept& k : kept_) {
    if (k.repeats > 0) {
      k.d.message += " (and " + std::to_string(k.repeats) + " more time" + (k.repeats == 1 ? "" : "s") + ")";
    }
    out.push_back(std::move(k.d));
  }
  if (error_count_ > kMaxErrors) {
    out.push_back(Diagnostic{Diagnostic::Severity::kError, file_, 0, 0,
                             std::to_string(error_count_ - kMaxErrors) + " more errors not shown"});
  }
  if (dropped_warnings_ > 0) {
    out.push_back(Diagnostic{Diagnostic::Severity::kWarning, file_, 0, 0,
                             std::to_string(dropped_warnings_) + " more warnings not shown"});
  }
  kept_.clear();
  return out;
}

}  // namespace pcnc
