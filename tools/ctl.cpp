// ctl.cpp — `pcnc ctl`: subcommands for every control-socket method (see ctl.hpp).
#include "ctl.hpp"
#include "ctl_support.hpp"

#include <poll.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <thread>

#include "config/config.hpp"
#include "config/exit_status.hpp"
#include "config/output_path.hpp"
#include "config/runtime_paths.hpp"
#include "check.hpp"  // parse_xyz, as `pcnc run --offset`
#include "ctl_capture.hpp"

namespace pcnc {

using json = nlohmann::json;
using Clock = std::chrono::steady_clock;

// ---------------------------------------------------------------- client

CtlClient::CtlClient(const std::string& socket_path) {
  sockaddr_un addr{};
  addr.sun_family = AF_UNIX;
  if (socket_path.size() >= sizeof addr.sun_path) throw std::runtime_error("socket path too long: " + socket_path);
  std::memcpy(addr.sun_path, socket_path.c_str(), socket_path.size() + 1);
  fd_ = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (fd_ < 0) throw std::runtime_error(std::string("socket: ") + std::strerror(errno));
  if (connect(fd_, reinterpret_cast<const sockaddr*>(&addr), sizeof addr) != 0) {
    const std::string why = std::strerror(errno);
    close(fd_);
    fd_ = -1;
    throw std::runtime_error("cannot connect to pcnc-host at " + socket_path + ": " + why +
                             " (is `pcnc-host --serve` running with this config?)");
  }
  // Talk only to a server that runs as root or as ourselves: a socket another user created
  // first (squatting a world-writable directory) must not receive our commands or feed us
  // a fake status.
  ucred peer{};
  socklen_t len = sizeof peer;
  if (getsockopt(fd_, SOL_SOCKET, SO_PEERCRED, &peer, &len) != 0 || len != sizeof peer) {
    const std::string why = std::strerror(errno);
    close(fd_);
    fd_ = -1;
    throw std::runtime_error("cannot tell who serves " + socket_path + ": " + why);
  }
  if (peer.uid != 0 && peer.uid != geteuid()) {
    close(fd_);
    fd_ = -1;
    throw std::runtime_error("refusing to talk to " + socket_path + ": it is served by uid " + std::to_string(peer.uid) +
                             " (pid " + std::to_string(peer.pid) + "), neither root nor you (uid " +
                             std::to_string(geteuid()) + "); another user may have created the socket first");
  }
}

CtlClient::~CtlClient() {
  if (fd_ >= 0) close(fd_);
}

void CtlClient::send_raw(const std::string& text) {
  std::size_t done = 0;
  while (done < text.size()) {
    const ssize_t n = ::send(fd_, text.data() + done, text.size() - done, MSG_NOSIGNAL);
    if (n < 0) {
      if (errno == EINTR) continue;
      throw std::runtime_error(std::string("control socket write: ") + std::strerror(errno));
    }
    done += static_cast<std::size_t>(n);
  }
}

bool CtlClient::read_line(std::string& line, double timeout_s) {
  const auto deadline = Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(timeout_s));
  for (;;) {
    const auto nl = buffer_.find('\n');
    if (nl != std::string::npos) {
      line = buffer_.substr(0, nl);
      buffer_.erase(0, nl + 1);
      return true;
    }
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
    if (left <= 0) return false;
    pollfd p{fd_, POLLIN, 0};
    const int r = poll(&p, 1, static_cast<int>(std::min<long long>(left, 100)));
    if (r < 0 && errno != EINTR) throw std::runtime_error(std::string("poll: ") + std::strerror(errno));
    if (r <= 0) {
      if (r < 0 || left <= 100) {
        if (Clock::now() >= deadline) return false;
      }
      continue;
    }
    char buf[65536];
    const ssize_t n = recv(fd_, buf, sizeof buf, 0);
    if (n == 0) throw std::runtime_error("pcnc-host closed the connection");
    if (n < 0) {
      if (errno == EINTR) continue;
      throw std::runtime_error(std::string("control socket read: ") + std::strerror(errno));
    }
    buffer_.append(buf, static_cast<std::size_t>(n));
  }
}

json CtlClient::call(const std::string& method, const json& params, double timeout_s) {
  const long long id = next_id_++;
  send_raw(json{{"id", id}, {"method", method}, {"params", params}}.dump() + "\n");
  const auto deadline = Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(timeout_s));
  for (;;) {
    const double left = std::chrono::duration<double>(deadline - Clock::now()).count();
    std::string line;
    if (left <= 0.0 || !read_line(line, left)) throw std::runtime_error("no reply to '" + method + "' within " + std::to_string(timeout_s) + " s");
    json j = json::parse(line, nullptr, false);
    if (j.is_discarded()) continue;
    if (j.contains("id") && j["id"] == id) return j;
    if (j.contains("id") && j["id"].is_null() && j.contains("error")) return j;  // connection-level error
    if (on_notification && !j.contains("id")) on_notification(j);
  }
}

// ---------------------------------------------------------------- human output

namespace ctl {  // shared with the other ctl_*.cpp files (ctl_support.hpp)

std::atomic<bool> g_ctl_interrupt{false};
void on_ctl_signal(int) { g_ctl_interrupt.store(true); }

void install_interrupt() {
  struct sigaction sa {};
  sa.sa_handler = on_ctl_signal;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
}

std::string xyz(const json& v) {
  if (!v.is_object()) return "-";
  char buf[128];
  std::snprintf(buf, sizeof buf, "X %9.4f  Y %9.4f  Z %9.4f", v.value("x", 0.0), v.value("y", 0.0), v.value("z", 0.0));
  return buf;
}

void print_status(const json& s) {
  const json rt = s.value("rt", json::object());
  std::printf("state      %s", s.value("state", "?").c_str());
  if (s.contains("fault") && s["fault"] != "none") {
    std::printf("  (fault: %s, axis %s, line %d, value %g)", s["fault"].get<std::string>().c_str(), s.value("fault_axis", "?").c_str(),
                s.value("fault_line", 0), s.value("fault_value", 0.0));
  }
  std::printf("\n");
  std::printf("pcnc-rt    %s", rt.value("state", "?").c_str());
  if (rt.value("pid", 0) > 0) std::printf(" (pid %d)", rt.value("pid", 0));
  if (!rt.value("message", std::string()).empty()) std::printf(": %s", rt.value("message", std::string()).c_str());
  std::printf("\n");
  if (s.contains("commanded")) {
    std::printf("commanded  %s mm\n", xyz(s["commanded"]).c_str());
    std::printf("actual     %s mm\n", xyz(s["actual"]).c_str());
    if (s.contains("work_position")) {  // work = machine - the active offset - G92 (when applied)
      const std::string active = s.value("work_state", json::object()).value("active", "G54");
      std::printf("work       %s mm (%s = %s)\n", xyz(s["work_position"]["commanded"]).c_str(), active.c_str(),
                  xyz(s.value("work_offsets", json::object()).value(active, json())).c_str());
    }
    std::printf("ferr       %s mm\n", xyz(s["following_error"]).c_str());
    std::printf("line %u  block %llu  speed %.2f mm/s  override %.0f %%  ring %d/4  underruns %llu  clock %s\n",
                s.value("line", 0u), static_cast<unsigned long long>(s.value("block_seq", 0ull)), s.value("path_speed", 0.0),
                s.value("feed_override_percent", 100.0), s.value("ring_fill", 0),
                static_cast<unsigned long long>(s.value("underruns", 0ull)), s.value("clock", "?").c_str());
    const json t = s.value("timing", json::object());
    std::printf("cycle      compute mean %.2f us p99 %.2f us max %.2f us; wake p99 %.1f us max %.1f us; %llu overruns\n",
                t.value("compute_mean_us", 0.0), t.value("compute_p99_us", 0.0), t.value("compute_max_us", 0.0), t.value("wake_p99_us", 0.0),
                t.value("wake_max_us", 0.0), static_cast<unsigned long long>(t.value("overruns", 0ull)));
  }
  const json job = s.value("job", json::object());
  if (job.value("active", false)) {
    std::printf("program    %s (%s", job.value("file", "?").c_str(), job.value("phase", "?").c_str());
    if (job.contains("lines_read")) std::printf(", %llu lines read", static_cast<unsigned long long>(job.value("lines_read", 0ull)));
    std::printf(")\n");
  }
  const json last = s.value("last_job", json());
  if (last.is_object()) {
    std::printf("last       %s: %s", last.value("file", "?").c_str(), last.value("end", "?").c_str());
    if (!last.value("message", std::string()).empty()) std::printf(" (%s)", last.value("message", std::string()).c_str());
    std::printf("\n");
  }
  if (s.value("resume", json()).is_object()) {
    const json r = s["resume"];
    std::printf("resumable  %s from line %u (pcnc ctl resume continues, pcnc ctl stop abandons)\n", r.value("file", "?").c_str(),
                r.value("line", 0u));
  }
}

std::string resolve_socket(const CtlOptions& o) {
  if (!o.socket.empty()) return o.socket;
  const std::string cfg = o.config_path.empty() ? default_config_path() : o.config_path;
  return find_control_socket(load_config(cfg));  // the path pcnc-host --serve computes (or a root service's)
}

// The exit status for an error reply (README "Exit status"): the request or the program was
// refused as given (bad parameters, preflight errors) 2; pcnc-rt not available 3; refused in
// the machine's state, or anything else, 1.
int exit_status_of_error(int code) {
  if (code == -32700 || code == -32600 || code == -32601 || code == -32602 || code == 3) return kExitBadInput;
  if (code == 2) return kExitProcessDied;
  return kExitFault;
}

// Prints a reply; returns the exit status (0 for a result, else exit_status_of_error).
int report(const CtlOptions& o, const json& reply, const std::function<void(const json&)>& human) {
  if (o.json_output) {
    std::printf("%s\n", reply.dump().c_str());
  } else if (reply.contains("error")) {
    const json e = reply["error"];
    std::fprintf(stderr, "pcnc ctl: error %d: %s\n", e.value("code", 0), e.value("message", std::string("?")).c_str());
    if (e.contains("data") && e["data"].contains("errors")) {
      for (const auto& d : e["data"]["errors"]) std::fprintf(stderr, "  %s\n", d.get<std::string>().c_str());
    }
  } else if (human) {
    human(reply["result"]);
  } else {
    std::printf("ok\n");
  }
  std::fflush(stdout);
  return reply.contains("error") ? exit_status_of_error(reply["error"].value("code", 0)) : kExitOk;
}

// Runs `body` with a connected client; a bad config exits 2, no server (or a lost one) 3.
int with_client(const CtlOptions& o, const std::function<int(CtlClient&)>& body) {
  std::string socket;
  try {
    socket = resolve_socket(o);
  } catch (const ConfigError& e) {
    for (const auto& p : e.problems) std::fprintf(stderr, "pcnc ctl: %s\n", p.c_str());
    return kExitBadInput;
  }
  try {
    CtlClient client(socket);
    return body(client);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "pcnc ctl: %s\n", e.what());
    return 3;
  }
}

int simple_call(const CtlOptions& o, const std::string& method, const json& params = json::object(),
                const std::function<void(const json&)>& human = {}) {
  return with_client(o, [&](CtlClient& c) { return report(o, c.call(method, params, o.timeout_s), human); });
}

// Waits until the machine has left JOGGING (an incremental jog finished), printing where.
int wait_jog_end(const CtlOptions& o, CtlClient& c) {
  for (int i = 0; i < 60000 && !g_ctl_interrupt.load(); ++i) {
    const json s = c.call("status", json::object(), o.timeout_s);
    if (s.contains("error")) return report(o, s, {});
    if (s["result"].value("state", "") != "JOGGING") {
      if (o.json_output) {
        std::printf("%s\n", s.dump().c_str());
      } else {
        std::printf("%s at %s mm\n", s["result"].value("state", "?").c_str(), xyz(s["result"].value("commanded", json())).c_str());
      }
      return 0;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  if (g_ctl_interrupt.load()) c.call("jog_stop", json::object(), o.timeout_s);
  return 1;
}

}  // namespace ctl
using namespace ctl;

// ---------------------------------------------------------------- subcommands

void add_ctl_subcommand(CLI::App& app, int& exit_code) {
  auto* ctl = app.add_subcommand("ctl", "talk to a running `pcnc-host --serve` over its control socket (docs/protocol.md)");
  ctl->require_subcommand(1);
  ctl->fallthrough();
  static CtlOptions o;  // the subcommands' callbacks outlive this function
  ctl->add_option("--socket", o.socket, "control socket path (default: process.socket_path of the config, else control.sock in the machine's runtime "
                 "directory: /run/pcnc/<machine> as root, $XDG_RUNTIME_DIR/pcnc/<machine> otherwise, falling back to "
                 "/run/pcnc/<machine> when only a root service's socket exists)");
  ctl->add_option("--config", o.config_path, "machine configuration (TOML) naming the socket");
  ctl->add_flag("--json", o.json_output, "print the raw JSON reply lines (for scripts)");
  ctl->add_option("--timeout", o.timeout_s, "seconds to wait for a reply")->capture_default_str();

  // status
  auto* status = ctl->add_subcommand("status", "machine state, positions, following error, override, ring, underruns, timing");
  static bool watch = false;
  static double rate = 5.0;
  status->add_flag("--watch", watch, "live view until Ctrl-C: redrawn in place on a terminal (machine and work "
                 "coordinates, offset, following error, progress and time left), one line per update when piped");
  status->add_option("--rate", rate, "--watch rate in Hz (at most 50)")->capture_default_str();
  status->callback([&exit_code] {
    if (!watch) {
      exit_code = simple_call(o, "status", json::object(), print_status);
      return;
    }
    install_interrupt();
    exit_code = with_client(o, [](CtlClient& c) { return watch_status(o, c, rate); });  // ctl_watch.cpp
  });

  // run
  auto* run = ctl->add_subcommand("run", "check FILE and run it (refused unless IDLE, or when preflight finds errors)");
  static std::string run_file, work_offset, contouring, run_offset;
  static bool fit = false, run_wait = false;
  run->add_option("FILE", run_file, "G-code program, or a ruled-surface program in the JSON file form (a .json file: pcnc ruled --json, docs/ruled-surface.md), run as the G-code form the host makes of it")->required();
  run->add_option("--work-offset", work_offset, "default coordinate system G54..G59");
  run->add_option("--contouring", contouring, "contouring at program start: on|off")->check(CLI::IsMember({"on", "off"}));
  run->add_flag("--fit", fit, "scale the program down so it fits the travel");
  run->add_option("--offset", run_offset, "program zero in machine coordinates X,Y,Z mm for this run (replaces G54)");
  run->add_flag("--wait", run_wait, "wait for the program's end and print how it ended");
  run->callback([&exit_code] {
    json params = {{"file", std::filesystem::absolute(run_file).lexically_normal().string()}};
    if (!work_offset.empty()) params["work_offset"] = work_offset;
    if (!contouring.empty()) params["contouring"] = contouring == "on";
    if (fit) params["fit"] = true;
    if (!run_offset.empty()) {
      const auto v = pcnc::parse_xyz(run_offset);
      if (!v) {
        std::fprintf(stderr, "pcnc ctl run: --offset '%s': expected X,Y,Z in mm, e.g. 12.5,12.5,25\n", run_offset.c_str());
        exit_code = pcnc::kExitBadInput;
        return;
      }
      params["offset"] = json{{"x", (*v)[0]}, {"y", (*v)[1]}, {"z", (*v)[2]}};
    }
    install_interrupt();
    exit_code = with_client(o, [&](CtlClient& c) {
      json ended;
      c.on_notification = [&](const json& n) {
        if (n.value("method", "") == "event" && n["params"].value("event", "") == "program_end") ended = n["params"];
      };
      if (run_wait) c.call("subscribe", json{{"rate_hz", 1}}, o.timeout_s);
      const json r = c.call("run", params, o.timeout_s);
      const int rc = report(o, r, [](const json& res) {
        std::printf("started %s (%llu lines, %llu moves)\n", res.value("file", "?").c_str(),
                    static_cast<unsigned long long>(res.value("lines", 0ull)), static_cast<unsigned long long>(res.value("moves", 0ull)));
        const json off = res.value("offset", json::object());
        std::printf("placement  machine = %.6f * program + (%.4f, %.4f, %.4f) mm\n", res.value("scale", 1.0), off.value("x", 0.0),
                    off.value("y", 0.0), off.value("z", 0.0));
        for (const auto& w : res.value("warnings", json::array())) std::fprintf(stderr, "  %s\n", w.get<std::string>().c_str());
      });
      if (rc != 0 || !run_wait) return rc;
      bool interrupted = false;
      while (ended.is_null()) {
        if (g_ctl_interrupt.load()) {
          c.call("stop", json::object(), o.timeout_s);
          g_ctl_interrupt = false;
          interrupted = true;
        }
        std::string line;
        if (!c.read_line(line, 0.2)) continue;
        const json n = json::parse(line, nullptr, false);
        if (!n.is_discarded() && !n.contains("id") && c.on_notification) c.on_notification(n);
      }
      if (o.json_output) {
        std::printf("%s\n", ended.dump().c_str());
      } else {
        std::printf("%s: %s%s%s; %.3f s machine time, %llu underruns\n", ended.value("file", "?").c_str(),
                    ended.value("end", "?").c_str(), ended.value("message", std::string()).empty() ? "" : ": ",
                    ended.value("message", std::string()).c_str(), ended.value("program_time_s", 0.0),
                    static_cast<unsigned long long>(ended.value("underruns", 0ull)));
      }
      if (interrupted) return kExitSignalBase + SIGINT;  // Ctrl-C stopped the program
      return ended.value("end", "") == "completed" ? kExitOk : kExitFault;
    });
  });

  add_operator_subcommands(*ctl, o, exit_code);  // mdi, touch-off (ctl_operator.cpp)

  // the simple ones
  struct Simple {
    const char* name;
    const char* help;
  };
  static const Simple simples[] = {
      {"pause", "feed hold: decelerate along the path and wait (a jog in progress is stopped)"},
      {"resume", "continue after pause or M00/M01; after HOST_LOST continue the interrupted program"},
      {"stop", "decelerate along the path and abandon the program (also abandons a HOST_LOST program)"},
      {"estop", "amplifiers off at once: ESTOP"},
      {"reset", "leave FAULT, ESTOP or HOST_LOST"},
      {"jog_stop", "decelerate any jog to rest"},
  };
  for (const auto& s : simples) {
    auto* sub = ctl->add_subcommand(s.name, s.help);
    if (std::string(s.name) == "jog_stop") sub->alias("jog-stop");
    const std::string name = s.name;
    sub->callback([&exit_code, name] {
      exit_code = simple_call(o, name, json::object(), [](const json& r) {
        if (r.value("resumed", false)) {
          std::printf("resumed %s at line %d from %s mm\n", r.value("file", "?").c_str(), r.value("line", 0),
                      xyz(r.value("from", json())).c_str());
          return;
        }
        std::printf("ok%s%s\n", r.contains("state") ? ": " : "", r.contains("state") ? r["state"].get<std::string>().c_str() : "");
        if (r.contains("note")) std::printf("%s\n", r["note"].get<std::string>().c_str());
      });
    });
  }

  // override
  auto* ovr = ctl->add_subcommand("override", "feed override in percent, 0..200");
  static double percent = 100.0;
  ovr->add_option("PERCENT", percent, "0..200")->required();
  ovr->callback([&exit_code] {
    exit_code = simple_call(o, "override", json{{"percent", percent}},
                            [](const json& r) { std::printf("feed override %.0f %%\n", r.value("percent", 0.0)); });
  });

  // jog
  auto* jog = ctl->add_subcommand("jog", "jog one axis: `jog X +1.0 --feed 300` (incremental, mm) or `jog Y - --continuous`");
  static std::string axis, amount;
  static double feed = 0.0, jog_for = 0.0;
  static bool continuous = false, no_wait = false;
  jog->add_option("AXIS", axis, "X, Y or Z; A, B or C: a rotary joint the machine has (degrees, --feed in deg/min)")->required();
  jog->add_option("AMOUNT", amount, "signed distance in mm (incremental), or + / - (continuous)")->required();
  jog->add_option("--feed", feed, "mm/min (default 600 or the axis maximum)");
  jog->add_flag("--continuous", continuous, "move until Ctrl-C (the client keeps the jog alive; stops at the soft limit)");
  jog->add_option("--for", jog_for, "continuous: stop after this many seconds");
  jog->add_flag("--no-wait", no_wait, "incremental: return once the rt took the jog, without waiting for its end");
  jog->callback([&exit_code] {
    json params = {{"axis", axis}};
    if (feed > 0.0) params["feed"] = feed;
    if (continuous) {
      params["continuous"] = true;
      if (amount != "+" && amount != "-") {
        std::fprintf(stderr, "pcnc ctl jog: a continuous jog takes + or - as direction, got '%s'\n", amount.c_str());
        exit_code = 2;
        return;
      }
      params["direction"] = amount;
    } else {
      try {
        std::size_t used = 0;
        const double d = std::stod(amount, &used);
        if (used != amount.size()) throw std::invalid_argument(amount);
        params["distance"] = d;
      } catch (const std::exception&) {
        std::fprintf(stderr, "pcnc ctl jog: distance must be a number in mm (e.g. +1.0), got '%s'\n", amount.c_str());
        exit_code = 2;
        return;
      }
    }
    install_interrupt();
    exit_code = with_client(o, [&](CtlClient& c) {
      const json r = c.call("jog", params, o.timeout_s);
      const int rc = report(o, r, [](const json& res) {
        if (res.contains("note")) std::printf("%s\n", res["note"].get<std::string>().c_str());
      });
      if (rc != 0) return rc;
      if (!continuous) return no_wait ? 0 : wait_jog_end(o, c);
      // Keep the jog alive until Ctrl-C, --for, or the rt ends it (soft limit).
      const double deadman = r["result"].value("deadman_s", 0.5);
      const auto t0 = Clock::now();
      while (!g_ctl_interrupt.load()) {
        if (jog_for > 0.0 && std::chrono::duration<double>(Clock::now() - t0).count() >= jog_for) break;
        std::this_thread::sleep_for(std::chrono::duration<double>(deadman / 4.0));
        const json k = c.call("jog_keepalive", json::object(), o.timeout_s);
        if (k.contains("error")) break;  // the jog ended on the rt (e.g. at the soft limit)
      }
      c.call("jog_stop", json::object(), o.timeout_s);
      g_ctl_interrupt = false;
      return wait_jog_end(o, c);
    });
  });

  // set_offset
  auto* off = ctl->add_subcommand("set_offset", "set a work offset for later runs, kept across restarts: `set_offset G55 --x 5 --y 6 --z 20` (mm)");
  off->alias("set-offset");
  static std::string which;
  static double ox = NAN, oy = NAN, oz = NAN;
  off->add_option("OFFSET", which, "G54..G59, G59.1..G59.3")->required();
  off->add_option("--x", ox, "program zero X in machine coordinates, mm");
  off->add_option("--y", oy, "program zero Y, mm");
  off->add_option("--z", oz, "program zero Z, mm");
  off->callback([&exit_code] {
    json params = {{"offset", which}};
    if (!std::isnan(ox)) params["x"] = ox;
    if (!std::isnan(oy)) params["y"] = oy;
    if (!std::isnan(oz)) params["z"] = oz;
    exit_code = simple_call(o, "set_offset", params, [](const json& r) {
      std::printf("%s = X %.4f Y %.4f Z %.4f\n", r.value("offset", "?").c_str(), r.value("x", 0.0), r.value("y", 0.0), r.value("z", 0.0));
    });
  });

  // capture: the scope (docs/servo-tuning.md); the files are written here, by the client
  auto* cap = ctl->add_subcommand("capture", "record signals at the rt's full cycle rate into -o PAGE.html and PAGE.csv: "
                                             "`capture --signals cmd_x,act_x,ferr_x --seconds 2 --trigger \"ferr_x>0.005\" -o scope.html`");
  static std::string cap_signals, cap_trigger, cap_out;
  static double cap_seconds = 0.0, cap_pre = 10.0, cap_wait = 60.0;
  cap->add_option("--signals", cap_signals, "comma-separated trace columns: line,state,cmd_x..cmd_z,act_x..act_z,ferr_x..ferr_z,speed")->required();
  cap->add_option("--seconds", cap_seconds, "record length, s (at most 10, and 48000 values: seconds x cycle rate x signals)")->required();
  cap->add_option("--trigger", cap_trigger, "start on a condition, e.g. \"ferr_x>0.005\" or \"abs(ferr_y)>=0.002\" (default: at once)");
  auto* cap_pre_opt = cap->add_option("--pre-trigger", cap_pre, "percent of the record before the trigger")->capture_default_str();
  auto* cap_wait_opt = cap->add_option("--trigger-timeout", cap_wait, "seconds to wait for the trigger")->capture_default_str();
  cap->add_option("-o,--output", cap_out, "the HTML page; the CSV goes beside it with the same stem")->required();
  cap->callback([&exit_code, cap_pre_opt, cap_wait_opt] {
    if (cap_trigger.empty() && (cap_pre_opt->count() > 0 || cap_wait_opt->count() > 0)) {
      std::fprintf(stderr, "pcnc ctl capture: --pre-trigger and --trigger-timeout need --trigger (without one the record starts at once)\n");
      exit_code = kExitBadInput;
      return;
    }
    json params = {{"seconds", cap_seconds}, {"signals", json::array()}};
    for (std::size_t a = 0; a <= cap_signals.size();) {
      const std::size_t b = std::min(cap_signals.find(',', a), cap_signals.size());
      params["signals"].push_back(cap_signals.substr(a, b - a));
      a = b + 1;
    }
    if (!cap_trigger.empty()) {
      params["trigger"] = cap_trigger;
      params["pre_trigger_percent"] = cap_pre;
      params["trigger_timeout_s"] = cap_wait;
    }
    try {
      if (std::filesystem::path(cap_out).extension() == ".csv") throw OutputPathError("-o names the HTML page; the CSV is written beside it");
      check_output_paths({{cap_out, "-o"}, {capture_csv_path(cap_out), "the CSV beside -o"}});
    } catch (const OutputPathError& e) {
      std::fprintf(stderr, "pcnc ctl capture: %s\n", e.what());
      exit_code = kExitBadInput;
      return;
    }
    exit_code = with_client(o, [&](CtlClient& c) {
      const json r = c.call("capture", params, o.timeout_s + cap_seconds + (cap_trigger.empty() ? 0.0 : cap_wait));
      if (r.contains("error")) return report(o, r, {});
      try {
        write_capture_files(capture_record(r["result"]), cap_out);
      } catch (const std::exception& e) {
        std::fprintf(stderr, "pcnc ctl capture: %s\n", e.what());
        return kExitFault;
      }
      return report(o, r, [](const json& res) {
        char when[64] = "";
        if (res["trigger"].is_string()) std::snprintf(when, sizeof when, ", trigger at machine time %.4f s", res.value("t_trigger_s", 0.0));
        std::printf("captured %zu cycles (%.3f s)%s; wrote %s and %s\n", res.value("rows", std::size_t{0}),
                    static_cast<double>(res.value("rows", 0)) * res.value("period_s", 0.0), when, cap_out.c_str(),
                    capture_csv_path(cap_out).c_str());
      });
    });
  });

  // subscribe: the raw form of status --watch
  auto* sub = ctl->add_subcommand("subscribe", "print status pushes (JSON lines) at RATE Hz until Ctrl-C");
  static double sub_rate = 10.0;
  sub->add_option("RATE", sub_rate, "Hz, at most 50")->capture_default_str();
  sub->callback([&exit_code] {
    install_interrupt();
    exit_code = with_client(o, [](CtlClient& c) {
      const json r = c.call("subscribe", json{{"rate_hz", sub_rate}}, o.timeout_s);
      if (r.contains("error")) return report(o, r, {});
      while (!g_ctl_interrupt.load()) {
        std::string line;
        if (c.read_line(line, 0.2)) {
          std::printf("%s\n", line.c_str());
          std::fflush(stdout);
        }
      }
      return 0;
    });
  });

  // call: any method with JSON params (scripts, debugging)
  auto* call = ctl->add_subcommand("call", "send METHOD with PARAMS (a JSON object) and print the reply");
  static std::string method, params_text = "{}";
  call->add_option("METHOD", method, "method name")->required();
  call->add_option("PARAMS", params_text, "JSON object")->capture_default_str();
  call->callback([&exit_code] {
    const json params = json::parse(params_text, nullptr, false);
    if (params.is_discarded()) {
      std::fprintf(stderr, "pcnc ctl call: PARAMS is not valid JSON: %s\n", params_text.c_str());
      exit_code = 2;
      return;
    }
    exit_code = with_client(o, [&](CtlClient& c) {
      const json r = c.call(method, params, o.timeout_s);
      std::printf("%s\n", r.dump(o.json_output ? -1 : 2).c_str());
      return r.contains("error") ? 1 : 0;
    });
  });
}

}  // namespace pcnc
