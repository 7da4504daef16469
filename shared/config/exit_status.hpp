// exit_status.hpp — the exit status every pcnc command keeps (README "Exit status"): its
// numbers, the table each --help shows, and command-line parsing that maps the argument
// parser's own codes (CLI11's 105, 106, 109...) onto it, so none of them leaks through.
//
// May include: the standard library and CLI11 (header only).
#pragma once

#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>

namespace pcnc {

inline constexpr int kExitOk = 0;             // ran cleanly; --help
inline constexpr int kExitFault = 1;          // the machine faulted or the run failed
inline constexpr int kExitBadInput = 2;       // bad G-code, config or command line: nothing moved
inline constexpr int kExitProcessDied = 3;    // pcnc-rt or pcnc-host died, or is not there
inline constexpr int kExitSignalBase = 128;   // + N: interrupted by signal N

inline constexpr const char* kExitStatusHelp =
    "Exit status (the same for every pcnc command):\n"
    "  0      ran cleanly (and --help)\n"
    "  1      the machine faulted or the run failed\n"
    "  2      bad G-code, config or command line: refused before anything moved\n"
    "  3      a process died (pcnc-rt or pcnc-host lost, or not running)\n"
    "  128+N  interrupted by signal N (130: Ctrl-C, 143: SIGTERM)";

/// Shows the exit status table under the --help of `app` and of all its subcommands; call
/// after the last subcommand is added.
inline void add_exit_status_help(CLI::App& app) {
  app.footer(kExitStatusHelp);
  for (CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; })) add_exit_status_help(*sub);
}

/// Parses the command line and runs the chosen callbacks. Returns -1 when parsing succeeded
/// (the caller goes on), else the exit status: 0 after --help, 2 after any parse error (its
/// message printed by CLI11 on stderr), 1 when a callback threw.
inline int parse_command_line(CLI::App& app, int argc, char** argv) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? kExitOk : kExitBadInput;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: %s\n", app.get_name().empty() ? "pcnc" : app.get_name().c_str(), e.what());
    return kExitFault;
  }
  return -1;
}

}  // namespace pcnc
