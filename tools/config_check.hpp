// config_check.hpp — `pcnc config check [FILE]`: the machine config as understood, or every
// problem in it (exit 2).
#pragma once

#include <iosfwd>
#include <string>

namespace CLI {
class App;
}

namespace pcnc {

/// Loads `path`; prints the machine on `out` (exit 0) or each problem on `err` (exit 2).
int run_config_check(const std::string& path, bool quiet, std::ostream& out, std::ostream& err);

void add_config_subcommand(CLI::App& app, int& exit_code);

}  // namespace pcnc
