// serve.hpp — `pcnc serve`: starts pcnc-rt and `pcnc-host --serve` as a pair (launcher.hpp),
// so a user can then run programs and jog from other terminals with `pcnc ctl`.
#pragma once

#include <string>

#include "launcher.hpp"

namespace CLI {
class App;
}

namespace pcnc {

/// The pair `pcnc serve` starts (pcnc-rt and pcnc-host --serve, supervised), for `pcnc grbl` too.
LaunchOptions serve_launch_options(const std::string& config_path, const std::string& clock, const std::string& trace,
                                   const std::string& tool_table, const std::string& surface = "",
                                   const std::string& tolerance = "");

/// Checks the config and the trace path before anything starts; false (after saying why, as
/// `who`) when they are bad: exit 2.
bool check_serve_inputs(const char* who, const std::string& config_path, const std::string& trace);

/// Registers `serve` on `app`; its callback stores the exit status in `exit_code`.
void add_serve_subcommand(CLI::App& app, int& exit_code);

/// Registers `grbl` (tools/grbl.cpp): the pair of `serve` plus a grbl 1.1 pseudo-terminal.
void add_grbl_subcommand(CLI::App& app, int& exit_code);

}  // namespace pcnc
