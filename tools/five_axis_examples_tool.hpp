// five_axis_examples_tool.hpp — `pcnc examples-5axis [--config F] -o DIR`: writes the project's
// 5-axis test programs (five_axis_examples.hpp) for a machine with rotary joints, the A and C
// words from its kinematics, G54 and home joints; examples/5axis/ holds them for
// configs/desktop-5axis.toml (examples/5axis/README.md).
#pragma once

#include <iosfwd>
#include <string>

namespace CLI {
class App;
}

namespace pcnc {

/// Exit status: 0 written, 2 a config without rotary kinematics or an unwritable file.
int run_five_axis_examples_tool(const std::string& config_path, const std::string& dir, std::ostream& out,
                                std::ostream& err);

/// Registers the `examples-5axis` subcommand on `app`; its callback stores the exit status.
void add_five_axis_examples_subcommand(CLI::App& app, int& exit_code);

}  // namespace pcnc
