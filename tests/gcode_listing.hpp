// gcode_listing.hpp — test helper: a program text through the front end only (list_moves, what
// `pcnc check --print-moves` prints), its moves' end points and messages in program order.
#pragma once

#include <string>
#include <vector>

#include "gcode/program.hpp"
#include "gcode_test_util.hpp"

namespace pcnc::test {

struct Listing {
  MoveListing result;
  std::vector<Move> moves;          // motion and dwell moves (no pause/end)
  std::vector<std::string> lines;   // the --print-moves text, "MSG ..." lines included
  std::vector<std::string> messages;
  bool has_error(const std::string& fragment) const {
    return has_diagnostic(result.diagnostics, Diagnostic::Severity::kError, fragment);
  }
  bool has_warning(const std::string& fragment) const {
    return has_diagnostic(result.diagnostics, Diagnostic::Severity::kWarning, fragment);
  }
  std::string first_error() const {
    for (const Diagnostic& d : result.diagnostics) {
      if (d.severity == Diagnostic::Severity::kError) return format_diagnostic(d);
    }
    return {};
  }
};

inline Listing list_program(const std::string& text, const MachineConfig& config = wide_config(), JobOptions options = {}) {
  if (!options.start_position) options.start_position = Vec3{0.0, 0.0, 0.0};
  if (!options.offset) options.offset = Vec3{0.0, 0.0, 0.0};
  Listing l;
  l.result = list_moves_text(
      text, "test.ngc", config, options,
      [&](const Move& m) {
        const std::string s = format_move(m);
        if (s.empty()) return;
        l.moves.push_back(m);
        l.lines.push_back(s);
      },
      [&](const ProgramMessage& m) {
        if (m.kind == MessageKind::kPrint) return;
        l.messages.push_back(m.text);
        l.lines.push_back("MSG " + m.text);
      });
  return l;
}

}  // namespace pcnc::test
