// ctl.hpp — `pcnc ctl METHOD [ARGS] [--json]`: the command-line client of pcnc-host's control
// socket (docs/protocol.md). One subcommand per method; human-readable output by default,
// the raw JSON reply lines with --json for scripts. Also the small client class tests and
// tools use to talk to the socket.
#pragma once

#include <nlohmann/json.hpp>

#include <functional>
#include <string>

namespace CLI {
class App;
}

namespace pcnc {

/// A blocking line client of the control socket (one request at a time; notifications that
/// arrive in between are handed to `on_notification`).
class CtlClient {
 public:
  /// Connects; throws std::runtime_error naming the path and the reason. The server must run
  /// as root or as this process's user (SO_PEERCRED): anything else is refused.
  explicit CtlClient(const std::string& socket_path);
  ~CtlClient();
  CtlClient(const CtlClient&) = delete;
  CtlClient& operator=(const CtlClient&) = delete;

  /// Sends {"id", "method", "params"} and waits up to timeout_s for the reply with that id.
  /// Throws std::runtime_error on timeout or a closed connection.
  nlohmann::json call(const std::string& method, const nlohmann::json& params = nlohmann::json::object(), double timeout_s = 30.0);
  /// Reads one line (reply or notification) within timeout_s; false on timeout.
  bool read_line(std::string& line, double timeout_s);
  /// The socket (to poll for notifications between calls).
  int fd() const { return fd_; }
  /// Sends raw text (for tests of malformed input).
  void send_raw(const std::string& text);

  std::function<void(const nlohmann::json&)> on_notification;

 private:
  int fd_ = -1;
  std::string buffer_;
  long long next_id_ = 1;
};

/// Registers `ctl` on `app`; its callback stores the exit status in `exit_code`
/// (0 ok, 1 the server answered with an error, 2 bad usage, 3 cannot reach the server).
void add_ctl_subcommand(CLI::App& app, int& exit_code);

}  // namespace pcnc
