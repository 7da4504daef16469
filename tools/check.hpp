// check.hpp — `pcnc check FILE`: the whole G-code front end without a machine.
//
// Runs the whole front-end pipeline over the program (pass 1: lexer, parser, interpreter,
// preflight, preprocessor, and the rt's own block check on every block), prints errors and
// warnings ("file:line:col: error: ..."), the transform, extents and feed time, and with
// --print-blocks streams the very same blocks (pass 2) in their stable text form. With
// --print-moves it runs the front end only (lexer, control flow, interpreter) and prints the
// moves as they leave it, one per line, with the (MSG,...)/(DEBUG,...) messages in order:
// the form to compare with LinuxCNC's interpreter (docs/gcode.md).
#pragma once

#include <array>
#include <cstdio>
#include <iosfwd>
#include <optional>
#include <string>

namespace CLI {
class App;
}

namespace pcnc {

struct CheckCommandOptions {
  std::string file;
  std::string config_path;  // empty: default_config_path()
  bool fit = false;
  double tolerance = -1.0;  // --tolerance MM; < 0: the config's (and the program's G64 P)
  std::string offset;      // "X,Y,Z" mm, empty: the config's G54
  std::string contouring;  // "on" | "off" | empty (config default)
  bool print_blocks = false;
  bool print_moves = false;
  std::string tool_table;  // empty: the config's gcode.tool_table
  std::string surface;     // --surface S.json: the measured surface Z is corrected by; empty: the config's gcode.surface
  bool quiet = false;  // only errors and the verdict
};

/// Runs the check; writes the report and blocks to `out`, diagnostics to `err`, and the
/// progress of a long check to `progress` (tools/progress.hpp; null: none; none with --quiet).
/// Exit status: 0 program OK, 2 program has errors, bad options or unreadable config.
int run_check_command(const CheckCommandOptions& options, std::ostream& out, std::ostream& err,
                      std::FILE* progress = nullptr);

/// Registers the `check` subcommand on `app`; its callback stores the exit status in `exit_code`.
void add_check_subcommand(CLI::App& app, int& exit_code);

/// Parses "X,Y,Z" (mm). Returns nothing on a malformed value.
std::optional<std::array<double, 3>> parse_xyz(const std::string& text);

}  // namespace pcnc
