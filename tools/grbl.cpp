// grbl.cpp — `pcnc grbl`: pcnc-rt and pcnc-host --serve as `pcnc serve` starts them, plus a
// pseudo-terminal that speaks grbl 1.1 (host/grbl/session.hpp) so G-code senders (CNCjs, UGS,
// bCNC...) drive the machine. The port talks to the service through its control socket like
// any client (no second path to the ring); the JSON socket is served as usual. A symlink names
// the terminal: --link PATH, by default `ttyGRBL` in the service's runtime directory (beside
// control.sock: a private directory, never a fixed name in a world-writable one). Ctrl-C ends
// it with exit 0. docs/grbl-protocol.md.
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <termios.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <deque>
#include <filesystem>
#include <memory>
#include <string>
#include <thread>

#include "config/config.hpp"
#include "config/exit_status.hpp"
#include "config/runtime_paths.hpp"
#include "ctl.hpp"
#include "grbl/session.hpp"
#include "launcher.hpp"
#include "serve.hpp"

namespace pcnc {
namespace {

using nlohmann::json;

// The control socket as the session's ServicePort; notifications are kept for the loop.
class SocketPort : public grbl::ServicePort {
 public:
  explicit SocketPort(const std::string& socket) : client_(socket) {
    client_.on_notification = [this](const json& n) { notes_.push_back(n); };
  }
  json call(const std::string& method, const json& params) override { return client_.call(method, params, 30.0); }
  int fd() const { return client_.fd(); }
  // Reads what has arrived (the socket is readable) into the notifications.
  void read_available() {
    std::string line;
    for (double wait = 0.002; client_.read_line(line, wait); wait = 0.0) {
      json j = json::parse(line, nullptr, false);
      if (!j.is_discarded() && !j.contains("id")) notes_.push_back(std::move(j));
    }
  }
  std::deque<json>& notes() { return notes_; }

 private:
  CtlClient client_;
  std::deque<json> notes_;
};

// The pseudo-terminal: raw (no echo, no line editing: bytes as a serial line carries them).
struct Pty {
  int master = -1;
  std::string slave_path;
  bool open() {
    master = posix_openpt(O_RDWR | O_NOCTTY | O_CLOEXEC);
    if (master < 0 || grantpt(master) != 0 || unlockpt(master) != 0) return false;
    const char* name = ptsname(master);
    if (!name) return false;
    slave_path = name;
    const int slave = ::open(name, O_RDWR | O_NOCTTY | O_CLOEXEC);
    if (slave < 0) return false;
    termios t{};
    tcgetattr(slave, &t);
    cfmakeraw(&t);
    cfsetspeed(&t, B115200);
    tcsetattr(slave, TCSANOW, &t);
    ::close(slave);  // a sender's open is seen as the end of the hang-up (POLLHUP)
    fcntl(master, F_SETFL, fcntl(master, F_GETFL) | O_NONBLOCK);
    return true;
  }
  // Writes all of `text` unless the sender stops reading for a second (then the rest is lost,
  // as on a serial line nobody reads).
  void write_all(const std::string& text) const {
    std::size_t done = 0;
    int stalls = 0;
    while (done < text.size()) {
      const ssize_t n = ::write(master, text.data() + done, text.size() - done);
      if (n > 0) {
        done += static_cast<std::size_t>(n);
        continue;
      }
      if (n < 0 && errno == EINTR) continue;
      if (n < 0 && errno == EAGAIN && ++stalls < 100) {
        pollfd p{master, POLLOUT, 0};
        poll(&p, 1, 10);
        continue;
      }
      return;  // EIO: nobody has the port open
    }
  }
  ~Pty() {
    if (master >= 0) ::close(master);
  }
};

std::atomic<bool> g_port_stop{false};

// The port's thread: waits for the service's socket, then serves the terminal until stopped.
void serve_port(const MachineConfig& config, const std::string& link, std::atomic<int>& failed) {
  Pty pty;
  if (!pty.open()) {
    std::fprintf(stderr, "pcnc grbl: cannot create a pseudo-terminal: %s\n", std::strerror(errno));
    failed = 1;
    kill(getpid(), SIGTERM);  // the launcher stops the pair
    return;
  }
  const std::string socket = control_socket_path(config);
  std::unique_ptr<SocketPort> port;
  std::unique_ptr<grbl::Session> session;
  bool linked = false, open_by_sender = false;
  while (!g_port_stop.load()) {
    if (!port) {
      try {
        port = std::make_unique<SocketPort>(socket);
        port->call("subscribe", json{{"rate_hz", 10}});
        session = std::make_unique<grbl::Session>(*port, config, [&pty](const std::string& s) { pty.write_all(s); });
      } catch (const std::exception&) {
        port.reset();
        std::this_thread::sleep_for(std::chrono::milliseconds(50));  // the service is starting (or restarting)
        continue;
      }
      if (!linked) {
        std::error_code ec;
        std::filesystem::remove(link, ec);
        std::filesystem::create_symlink(pty.slave_path, link, ec);
        if (ec) {
          std::fprintf(stderr, "pcnc grbl: cannot create the link %s: %s\n", link.c_str(), ec.message().c_str());
          failed = 1;
          kill(getpid(), SIGTERM);
          return;
        }
        linked = true;
        std::fprintf(stderr, "pcnc grbl: grbl 1.1 port on %s (%s)\n", link.c_str(), pty.slave_path.c_str());
      }
      if (open_by_sender) session->connected();
    }
    try {
      pollfd fds[2] = {{pty.master, POLLIN, 0}, {port->fd(), POLLIN, 0}};
      poll(fds, 2, 5);
      const bool hangup = (fds[0].revents & POLLHUP) != 0;
      if (!hangup && !open_by_sender) session->connected();  // a sender opened the port
      open_by_sender = !hangup;
      if (fds[0].revents & POLLIN) {
        char buf[4096];
        const ssize_t n = ::read(pty.master, buf, sizeof buf);
        if (n > 0) session->on_bytes(std::string_view(buf, static_cast<std::size_t>(n)));
      }
      if (fds[1].revents & (POLLIN | POLLHUP)) port->read_available();
      while (!port->notes().empty()) {
        const json n = std::move(port->notes().front());
        port->notes().pop_front();
        session->on_notification(n);
      }
      session->tick();
      if (hangup) std::this_thread::sleep_for(std::chrono::milliseconds(20));  // POLLHUP returns at once
    } catch (const std::exception& e) {
      std::fprintf(stderr, "pcnc grbl: the control socket: %s; connecting again\n", e.what());
      session.reset();
      port.reset();
    }
  }
  if (linked) {
    std::error_code ec;
    std::filesystem::remove(link, ec);
  }
}

}  // namespace

void add_grbl_subcommand(CLI::App& app, int& exit_code) {
  auto* cmd = app.add_subcommand("grbl", "start pcnc-rt and pcnc-host --serve and a grbl 1.1 serial port (a pseudo-terminal) "
                                         "for G-code senders such as CNCjs; Ctrl-C ends it");
  static std::string config_path = default_config_path(), link, clock = "real";
  cmd->add_option("--config", config_path, "machine configuration (TOML)")->capture_default_str();
  cmd->add_option("--link", link, "symlink to the pseudo-terminal (default: ttyGRBL in the service's runtime directory)");
  cmd->add_option("--clock", clock, "real: 2 kHz in real time; virtual: as fast as possible, same cycles")
      ->check(CLI::IsMember({"real", "virtual"}))
      ->capture_default_str();
  cmd->callback([&exit_code] {
    if (!check_serve_inputs("pcnc grbl", config_path, "")) {
      exit_code = kExitBadInput;
      return;
    }
    const MachineConfig config = load_config(config_path);
    std::string where = link;
    if (where.empty()) where = (std::filesystem::path(control_socket_path(config)).parent_path() / "ttyGRBL").string();
    std::error_code ec;
    const auto parent = std::filesystem::path(where).parent_path();
    if (!link.empty() && !parent.empty() && !std::filesystem::is_directory(parent, ec)) {
      std::fprintf(stderr, "pcnc grbl: --link %s: %s is not a directory\n", link.c_str(), parent.c_str());
      exit_code = kExitBadInput;
      return;
    }
    std::atomic<int> failed{0};
    std::thread port([&] { serve_port(config, where, failed); });
    const int status = launch_pair(serve_launch_options(config_path, clock, "", ""));
    g_port_stop = true;
    port.join();
    // Ctrl-C or SIGTERM is how the port is meant to end: exit 0.
    exit_code = (status == 128 + SIGINT || status == 128 + SIGTERM) ? 0 : status;
    if (exit_code == 0 && failed.load()) exit_code = 1;
  });
}

}  // namespace pcnc
