// ctl_support.hpp — what the files of `pcnc ctl` share (ctl.cpp holds the client and most
// subcommands; ctl_operator.cpp the operator's mdi and touch-off; ctl_watch.cpp the
// status --watch view): the options every subcommand takes, the Ctrl-C flag, and the helpers
// that connect, print a reply and map it to the README's exit status.
#pragma once

#include <nlohmann/json.hpp>

#include <atomic>
#include <functional>
#include <string>

#include "ctl.hpp"

namespace CLI {
class App;
}

namespace pcnc {

struct CtlOptions {
  std::string socket;
  std::string config_path;
  bool json_output = false;
  double timeout_s = 30.0;
};

namespace ctl {

extern std::atomic<bool> g_ctl_interrupt;  // Ctrl-C or SIGTERM seen (after install_interrupt)
void install_interrupt();
/// "X    1.0000  Y    2.0000  Z    3.0000" from {"x":..,"y":..,"z":..}.
std::string xyz(const nlohmann::json& v);
/// Prints a reply (human form, or the raw line with --json); returns the exit status.
int report(const CtlOptions& o, const nlohmann::json& reply, const std::function<void(const nlohmann::json&)>& human);
/// Runs `body` with a connected client; a bad config exits 2, no server (or a lost one) 3.
int with_client(const CtlOptions& o, const std::function<int(CtlClient&)>& body);

}  // namespace ctl

/// `pcnc ctl mdi TEXT...` and `pcnc ctl touch-off AXIS VALUE` (ctl_operator.cpp).
void add_operator_subcommands(CLI::App& ctl, const CtlOptions& o, int& exit_code);
/// `pcnc ctl status --watch`: redrawn in place on a terminal, plain lines otherwise, until
/// Ctrl-C (ctl_watch.cpp). Returns the exit status.
int watch_status(const CtlOptions& o, CtlClient& c, double rate_hz);

}  // namespace pcnc
