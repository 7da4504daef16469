// ctl_watch.cpp — `pcnc ctl status --watch`: the operator's live view. On a terminal it
// redraws one block of lines in place (cursor up, erase each line); piped, it prints one plain
// line per status push. The view: state, line and program; machine and work coordinates
// (work = machine - the active G5x - the applied G92, as the service computes them), the
// active work offset, following error per axis, speed and override, and a progress bar with
// the time left from the plan (docs/protocol.md, status `job.planned_time_s`).
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "ctl_support.hpp"
#include "ctl_watch.hpp"
#include "progress.hpp"

namespace pcnc {

using json = nlohmann::json;

namespace {

std::string fmt_text(const char* format, auto... args) {
  char buf[512];
  const int n = std::snprintf(buf, sizeof buf, format, args...);
  return std::string(buf, n > 0 ? std::min<std::size_t>(static_cast<std::size_t>(n), sizeof buf - 1) : 0);
}

double axis(const json& v, const char* k) { return v.is_object() ? v.value(k, 0.0) : 0.0; }

std::string pos3(const json& v) {
  if (!v.is_object()) return "      -            -            -    ";
  return fmt_text("X %9.4f  Y %9.4f  Z %9.4f", axis(v, "x"), axis(v, "y"), axis(v, "z"));
}

}  // namespace

std::optional<WatchProgress> watch_progress(const json& s) {
  const json job = s.value("job", json::object());
  if (!job.is_object() || !job.value("active", false)) return std::nullopt;
  const double total = job.value("planned_time_s", 0.0);
  if (!(total > 0.0)) return std::nullopt;
  WatchProgress p;
  const double done = std::clamp(job.value("planned_done_s", 0.0), 0.0, total);
  p.fraction = done / total;
  const double taken = s.value("program_time_s", 0.0);
  // the planned time left at the pace so far (flowing junctions, override); not on the first percent
  if (p.fraction >= 0.01 && taken > 0.0) p.remaining_s = (total - done) * taken / done;
  return p;
}

// While the service checks a program before it runs (`job.phase` preflight, docs/protocol.md):
// "checking  [#########.....................]  30.2 %  line 12345"; empty otherwise.
std::string watch_check(const json& s) {
  const json job = s.value("job", json::object());
  if (!job.is_object() || !job.value("active", false) || !job.contains("check_fraction")) return {};
  const double f = std::clamp(job.value("check_fraction", 0.0), 0.0, 1.0);
  const int width = 30;
  const int filled = static_cast<int>(std::floor(f * width));
  const std::string pass = job.value("check_pass", "check");
  const char* what = pass == "fit" ? "measuring for --fit" : (pass == "locate" ? "locating the stop" : "checking");
  return fmt_text("%s  [%s%s] %5.1f %%  line %llu", what,
                  std::string(static_cast<std::size_t>(filled), '#').c_str(),
                  std::string(static_cast<std::size_t>(width - filled), '.').c_str(), 100.0 * f,
                  static_cast<unsigned long long>(job.value("check_line", 0ull)));
}

std::vector<std::string> format_watch(const json& s) {
  std::vector<std::string> out;
  const json job = s.value("job", json::object());
  const json ws = s.value("work_state", json::object());
  const std::string active = ws.value("active", "G54");
  std::string program = "-";
  if (job.is_object() && job.value("active", false)) program = job.value("file", "?");
  out.push_back(fmt_text("%-9s line %-6u program %s", s.value("state", "?").c_str(), s.value("line", 0u), program.c_str()));
  if (!s.contains("commanded")) {
    const json rt = s.value("rt", json::object());
    out.push_back(fmt_text("pcnc-rt %s %s", rt.value("state", "?").c_str(), rt.value("message", std::string()).c_str()));
    return out;
  }
  const json wp = s.value("work_position", json::object());
  out.push_back(fmt_text("%-10s %-37s %s", "", "machine mm", ("work mm (" + active + ")").c_str()));
  out.push_back(fmt_text("%-10s %s   %s", "commanded", pos3(s["commanded"]).c_str(), pos3(wp.value("commanded", json())).c_str()));
  out.push_back(fmt_text("%-10s %s   %s", "actual", pos3(s["actual"]).c_str(), pos3(wp.value("actual", json())).c_str()));
  const json fe = s.value("following_error", json::object());
  out.push_back(fmt_text("%-10s X %8.2f um  Y %8.2f um  Z %8.2f um", "ferr", 1000.0 * axis(fe, "x"), 1000.0 * axis(fe, "y"),
                    1000.0 * axis(fe, "z")));
  const json offsets = s.value("work_offsets", json::object());
  const json g92 = ws.value("G92", json::object());
  std::string g92_text = ws.value("G92_applied", false) ? fmt_text("G92 X %.4f Y %.4f Z %.4f", axis(g92, "x"), axis(g92, "y"), axis(g92, "z"))
                                                        : std::string("G92 off");
  // The tool in the spindle and its length offset, as the last program or MDI left them.
  const int tool = ws.value("tool", 0);
  std::string tool_text = tool > 0 ? fmt_text("T%d", tool) : std::string("no tool");
  if (ws.value("tool_offset_applied", false)) {
    tool_text += fmt_text(" G43 Z %+.4f", axis(ws.value("tool_offset", json::object()), "z"));
  } else {
    tool_text += " G49";
  }
  out.push_back(fmt_text("%-10s %s %s  %s  %s", "offset", active.c_str(), pos3(offsets.value(active, json())).c_str(),
                    g92_text.c_str(), tool_text.c_str()));
  out.push_back(fmt_text("%-10s %.2f mm/s  override %.0f %%  ring %d/4  underruns %llu", "speed", s.value("path_speed", 0.0),
                    s.value("feed_override_percent", 100.0), s.value("ring_fill", 0),
                    static_cast<unsigned long long>(s.value("underruns", 0ull))));
  if (const auto p = watch_progress(s)) {
    const int width = 30;
    const int filled = static_cast<int>(std::floor(p->fraction * width));
    out.push_back(fmt_text("[%s%s] %5.1f %%  left %s  machine %s", std::string(static_cast<std::size_t>(filled), '#').c_str(),
                      std::string(static_cast<std::size_t>(width - filled), '.').c_str(), 100.0 * p->fraction,
                      p->remaining_s ? format_duration(*p->remaining_s).c_str() : "?",
                      format_duration(s.value("program_time_s", 0.0)).c_str()));
  } else if (const std::string c = watch_check(s); !c.empty()) {
    out.push_back(c);
  } else {
    out.push_back("");  // the block keeps its height
  }
  return out;
}

std::string format_watch_line(const json& s) {
  const json c = s.value("commanded", json::object());
  const json w = s.value("work_position", json::object()).value("commanded", json::object());
  const json fe = s.value("following_error", json::object());
  std::string line = fmt_text("%-9s line %-6u X %9.4f Y %9.4f Z %9.4f  work %s X %9.4f Y %9.4f Z %9.4f  ferr %.2f %.2f %.2f um  "
                         "v %8.2f mm/s  ovr %3.0f%%",
                         s.value("state", "?").c_str(), s.value("line", 0u), axis(c, "x"), axis(c, "y"), axis(c, "z"),
                         s.value("work_state", json::object()).value("active", "G54").c_str(), axis(w, "x"), axis(w, "y"),
                         axis(w, "z"), 1000.0 * axis(fe, "x"), 1000.0 * axis(fe, "y"), 1000.0 * axis(fe, "z"),
                         s.value("path_speed", 0.0), s.value("feed_override_percent", 100.0));
  if (const auto p = watch_progress(s)) {
    line += fmt_text("  %.1f %% left %s", 100.0 * p->fraction, p->remaining_s ? format_duration(*p->remaining_s).c_str() : "?");
  } else if (const std::string c = watch_check(s); !c.empty()) {
    line += "  " + c;
  }
  return line;
}

int watch_status(const CtlOptions& o, CtlClient& c, double rate_hz) {
  const json r = c.call("subscribe", json{{"rate_hz", rate_hz}}, o.timeout_s);
  if (r.contains("error")) return ctl::report(o, r, {});
  const char* term = std::getenv("TERM");
  const bool terminal = !o.json_output && isatty(STDOUT_FILENO) && !(term && std::strcmp(term, "dumb") == 0);
  std::size_t drawn = 0;  // lines of the block on screen
  while (!ctl::g_ctl_interrupt.load()) {
    std::string line;
    if (!c.read_line(line, 0.2)) continue;
    const json j = json::parse(line, nullptr, false);
    if (j.is_discarded()) continue;
    if (o.json_output) {
      std::printf("%s\n", line.c_str());
    } else if (j.value("method", "") == "status") {
      if (terminal) {
        if (drawn > 0) std::printf("\x1b[%zuA", drawn);  // back to the block's first line
        const auto lines = format_watch(j["params"]);
        for (const auto& l : lines) std::printf("\r%s\x1b[K\n", l.c_str());
        for (std::size_t i = lines.size(); i < drawn; ++i) std::printf("\r\x1b[K\n");  // a shorter block
        drawn = std::max(drawn, lines.size());
      } else {
        std::printf("%s\n", format_watch_line(j["params"]).c_str());
      }
    } else if (j.value("method", "") == "event") {
      if (terminal && drawn > 0) {
        std::printf("\x1b[%zuA\r\x1b[J", drawn);  // the event goes above the block, which is drawn again
        drawn = 0;
      }
      std::printf("event: %s\n", j["params"].dump().c_str());
    }
    std::fflush(stdout);
  }
  return 0;
}

}  // namespace pcnc
