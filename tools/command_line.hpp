// command_line.hpp — the `pcnc` command line (command_line.cpp): parses argv, runs the
// subcommand, returns its exit status (config/exit_status.hpp).
#pragma once

namespace pcnc {

int run_command_line(int argc, char** argv);

}  // namespace pcnc
