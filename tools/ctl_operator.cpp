// ctl_operator.cpp — the machinist's two commands of `pcnc ctl`: `mdi` (type G-code lines and
// run them as a small program, through the same pipeline as a file) and `touch-off` (set the
// active work offset so that the current position reads a value, G10 L20's meaning). Both are
// socket methods (docs/protocol.md); this file only builds the request and prints the reply.
#include <CLI/CLI.hpp>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <string>
#include <vector>

#include "config/exit_status.hpp"
#include "ctl_support.hpp"

namespace pcnc {

using json = nlohmann::json;

namespace {

// Waits for the program_end event of the MDI just started; Ctrl-C stops it (exit 130).
int wait_mdi_end(const CtlOptions& o, CtlClient& c, json& ended) {
  bool interrupted = false;
  while (ended.is_null()) {
    if (ctl::g_ctl_interrupt.load()) {
      c.call("stop", json::object(), o.timeout_s);
      ctl::g_ctl_interrupt = false;
      interrupted = true;
    }
    std::string line;
    if (!c.read_line(line, 0.2)) continue;
    const json n = json::parse(line, nullptr, false);
    if (!n.is_discarded() && !n.contains("id") && c.on_notification) c.on_notification(n);
  }
  if (interrupted) return kExitSignalBase + SIGINT;
  return ended.value("end", "") == "completed" ? kExitOk : kExitFault;
}

}  // namespace

void add_operator_subcommands(CLI::App& ctl, const CtlOptions& o, int& exit_code) {
  // mdi
  auto* mdi = ctl.add_subcommand("mdi", "run G-code typed here as a small program: `mdi \"G1 X5 F300\"` (several arguments are "
                                        "several lines); checked whole before anything moves, refused while a program runs");
  static std::vector<std::string> lines;
  static bool no_wait = false;
  mdi->add_option("LINES", lines, "G-code lines (work coordinates of the active offset; starts where the machine stands)")
      ->required();
  mdi->add_flag("--no-wait", no_wait, "return once it started, without waiting for its end");
  mdi->callback([&exit_code, &o] {
    std::string text;
    for (const auto& l : lines) text += l + "\n";
    ctl::install_interrupt();
    exit_code = ctl::with_client(o, [&](CtlClient& c) {
      json ended;
      c.on_notification = [&](const json& n) {
        if (n.value("method", "") == "event" && n["params"].value("event", "") == "program_end") ended = n["params"];
      };
      if (!no_wait) c.call("subscribe", json{{"rate_hz", 1}}, o.timeout_s);
      const json r = c.call("mdi", json{{"text", text}}, o.timeout_s);
      const int rc = ctl::report(o, r, [](const json& res) {
        for (const auto& w : res.value("warnings", json::array())) std::fprintf(stderr, "  %s\n", w.get<std::string>().c_str());
      });
      if (rc != 0 || no_wait) return rc;
      const int end = wait_mdi_end(o, c, ended);
      const json s = c.call("status", json::object(), o.timeout_s);
      if (o.json_output) {
        std::printf("%s\n", ended.dump().c_str());
      } else {
        std::printf("MDI %s%s%s", ended.value("end", "?").c_str(), ended.value("message", std::string()).empty() ? "" : ": ",
                    ended.value("message", std::string()).c_str());
        if (s.contains("result") && s["result"].contains("work_position")) {
          std::printf("; at %s (%s)", ctl::xyz(s["result"]["work_position"]["commanded"]).c_str(),
                      s["result"]["work_state"].value("active", "?").c_str());
        }
        std::printf("\n");
      }
      std::fflush(stdout);
      return end;
    });
  });

  // probe (docs/probe.md)
  auto* probe = ctl.add_subcommand("probe", "one probing move for a person at the machine: `probe Z- --feed 50` moves down "
                                            "until the probe triggers (G38.2) and prints where");
  static std::string direction;
  static double feed = 50.0;
  static double distance = 0.0;
  static std::string code = "G38.2";
  probe->add_option("DIRECTION", direction, "axis and sign: X+, X-, Y+, Y-, Z+ or Z-")->required();
  probe->add_option("--feed", feed, "mm/min (capped so that the stop fits the probe's overtravel)");
  probe->add_option("--distance", distance, "how far at most, mm (default: to the end of the travel)");
  probe->add_option("--code", code, "G38.2 (default), G38.3, G38.4 or G38.5");
  probe->callback([&exit_code, &o] {
    if (direction.size() != 2 || std::string("XYZxyz").find(direction[0]) == std::string::npos ||
        (direction[1] != '+' && direction[1] != '-')) {
      std::fprintf(stderr, "pcnc ctl probe: DIRECTION '%s': expected an axis and a sign, e.g. Z-\n", direction.c_str());
      exit_code = kExitBadInput;
      return;
    }
    json params = {{"axis", std::string(1, direction[0])}, {"direction", direction[1] == '-' ? -1 : 1}, {"feed", feed}, {"code", code}};
    if (distance > 0.0) params["distance"] = distance;
    ctl::install_interrupt();
    exit_code = ctl::with_client(o, [&](CtlClient& c) {
      json ended;
      c.on_notification = [&](const json& n) {
        if (n.value("method", "") == "event" && n["params"].value("event", "") == "program_end") ended = n["params"];
      };
      c.call("subscribe", json{{"rate_hz", 1}}, o.timeout_s);
      const int rc = ctl::report(o, c.call("probe", params, o.timeout_s), [](const json&) {});
      if (rc != 0) return rc;
      int end = wait_mdi_end(o, c, ended);
      // the job's error (a G38.2 without contact is refused by the check after the sync point)
      // reaches us in its end event when the request was already answered "started"
      if (end != kExitOk && !ended.value("message", std::string()).empty()) {
        std::fprintf(stderr, "%s\n", ended.value("message", std::string()).c_str());
      }
      const json s = c.call("status", json::object(), o.timeout_s);
      const json p = s.contains("result") ? s["result"].value("probe", json::object()) : json::object();
      const std::string outcome = p.value("outcome", "none");
      if (end == kExitOk && outcome != "contact" && (code == "G38.2" || code == "G38.4")) end = kExitFault;
      if (o.json_output) {
        std::printf("%s\n", p.dump().c_str());
      } else {
        std::printf("probe %s: %s; latched at machine %s, stopped at %s\n", code.c_str(), outcome.c_str(),
                    ctl::xyz(p.value("latched", json())).c_str(), ctl::xyz(p.value("stop", json())).c_str());
      }
      std::fflush(stdout);
      return end;
    });
  });

  // touch-off
  auto* touch = ctl.add_subcommand("touch-off", "set the active work offset so that the current position reads VALUE on AXIS "
                                                "(G10 L20): `touch-off Z 0`; kept across restarts");
  touch->alias("touch_off");
  static std::string axis;
  static double value = 0.0;
  touch->add_option("AXIS", axis, "X, Y or Z")->required();
  touch->add_option("VALUE", value, "what the position shall read, mm")->required();
  touch->callback([&exit_code, &o] {
    exit_code = ctl::with_client(o, [&](CtlClient& c) {
      return ctl::report(o, c.call("touch_off", json{{"axis", axis}, {"value", value}}, o.timeout_s), [](const json& r) {
        std::printf("%s = X %.4f Y %.4f Z %.4f: %s now reads %.4f (machine %s)\n", r.value("offset", "?").c_str(), r.value("x", 0.0),
                    r.value("y", 0.0), r.value("z", 0.0), r.value("axis", "?").c_str(), r.value("value", 0.0),
                    ctl::xyz(r.value("machine", json())).c_str());
      });
    });
  });
}

}  // namespace pcnc
