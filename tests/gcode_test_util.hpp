// gcode_test_util.hpp — helpers shared by the G-code front-end tests: run a program text through
// check_program_text and BlockStream, and a machine config with room to move.
#pragma once

#include <string>
#include <vector>

#include "config/config.hpp"
#include "gcode/move.hpp"
#include "gcode/program.hpp"
#include "test_paths.hpp"

namespace pcnc::test {

/// A G1 move from a to b as the interpreter makes it (machine mm), for the move stages' tests.
inline Move line_move(const Vec3& a, const Vec3& b, int line, double feed = 10.0, bool contouring = true,
                      double path_tolerance_mm = 0.0) {
  Move m;
  m.kind = MoveKind::kLine;
  m.start = a;
  m.end = b;
  m.line = line;
  m.feed_mm_s = feed;
  m.contouring = contouring;
  m.path_tolerance_mm = path_tolerance_mm;
  return m;
}

/// The default desktop mill, loaded from configs/desktop-mill.toml.
inline MachineConfig mill_config() { return load_config(default_config()); }

/// The desktop mill with +-1000 mm travel and G54 at the machine origin, so tests can use
/// program coordinates as machine coordinates.
inline MachineConfig wide_config() {
  MachineConfig c = mill_config();
  for (AxisConfig& a : c.axes) {
    a.travel_min_mm = -1000.0;
    a.travel_max_mm = 1000.0;
  }
  for (Vec3& w : c.gcode.work_offsets) w = Vec3{0.0, 0.0, 0.0};
  return c;
}

/// True when one of `diags` has this severity and holds `fragment` in its message.
inline bool has_diagnostic(const std::vector<Diagnostic>& diags, Diagnostic::Severity severity,
                           const std::string& fragment) {
  for (const Diagnostic& d : diags) {
    if (d.severity == severity && d.message.find(fragment) != std::string::npos) return true;
  }
  return false;
}

struct RunResult {
  CheckResult check;
  std::vector<Block> blocks;
  bool has_error(const std::string& fragment) const {
    return has_diagnostic(check.diagnostics, Diagnostic::Severity::kError, fragment);
  }
  bool has_warning(const std::string& fragment) const {
    return has_diagnostic(check.diagnostics, Diagnostic::Severity::kWarning, fragment);
  }
  const Diagnostic* first_error() const {
    for (const Diagnostic& d : check.diagnostics) {
      if (d.severity == Diagnostic::Severity::kError) return &d;
    }
    return nullptr;
  }
  std::vector<Block> motion() const {
    std::vector<Block> m;
    for (const Block& b : blocks) {
      if (b.kind == BlockKind::kRapid || b.kind == BlockKind::kLine || b.kind == BlockKind::kArc) m.push_back(b);
    }
    return m;
  }
};

/// Checks `text`; when it is OK, also streams its blocks.
inline RunResult run_program(const std::string& text, const MachineConfig& config, JobOptions options = {}) {
  if (!options.start_position) options.start_position = Vec3{0.0, 0.0, 0.0};
  RunResult r;
  r.check = check_program_text(text, "test.ngc", config, options);
  if (r.check.ok) {
    BlockStream s(BlockStream::FromText{}, text, "test.ngc", config, options, r.check.transform);
    Block b;
    while (s.next(b)) r.blocks.push_back(b);
  }
  return r;
}

}  // namespace pcnc::test
