// progress_update.hpp — the line pcnc-host writes on its progress pipe (--progress-fd) while
// it runs a program, for the launcher's progress display (tools/progress.hpp):
//   "progress LINE TOTAL_LINES MACHINE_TIME_S [PLANNED_DONE_S PLANNED_TOTAL_S]\n"
// LINE is the source line the machine is executing, TOTAL_LINES the program's line count
// from the check pass, MACHINE_TIME_S the program time on the machine so far; PLANNED_TOTAL_S
// the planned time of all the program's blocks (the check's) and PLANNED_DONE_S that of the
// blocks the machine has done (gcode/planned_time.hpp): the bar's fraction and ETA. When the job
// has ended the host writes "done\n" and waits (briefly) for "ok\n" from the launcher, which
// has then cleared its progress display: the run report that follows starts on a clean line.
// Under `--pauses ask` the host writes "pause LINE M0|M1\n" when the machine stands at one of
// the program's pauses and waits for the launcher's answer, "resume\n" or "stop\n" (the
// operator pressed Enter, or cannot answer).
// Before anything moves, while the host checks the program (gcode/check_progress.hpp), it writes
//   "checking fit|check LINE BYTES_READ TOTAL_BYTES BLOCKS\n"
// at most ten times a second: the pass (--fit's measuring pass, then the check), the line
// reached, how much of the program's text is read, and the blocks made so far.
//
// May include: the C++ library and gcode/check_progress.hpp (tools/ reads it too).
#pragma once

#include <cstdint>
#include <cstdio>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>

#include "gcode/check_progress.hpp"

namespace pcnc {

struct ProgressUpdate {
  std::uint32_t line = 0;
  std::uint64_t total_lines = 0;
  double machine_time_s = 0.0;
  double planned_done_s = 0.0;   // 0 with planned_total_s 0: not known (an older host)
  double planned_total_s = 0.0;
};

inline std::string format_progress_update(const ProgressUpdate& u) {
  char buf[128];
  std::snprintf(buf, sizeof buf, "progress %u %llu %.4f %.4f %.4f\n", u.line, static_cast<unsigned long long>(u.total_lines),
                u.machine_time_s, u.planned_done_s, u.planned_total_s);
  return buf;
}

/// The update in one line (without or with its newline); nothing when it is not one.
inline std::optional<ProgressUpdate> parse_progress_update(std::string_view line) {
  std::istringstream in{std::string(line)};
  std::string word;
  ProgressUpdate u;
  if (!(in >> word) || word != "progress") return std::nullopt;
  if (!(in >> u.line >> u.total_lines >> u.machine_time_s)) return std::nullopt;
  if ((in >> std::ws).eof()) return u;
  if (!(in >> u.planned_done_s >> u.planned_total_s)) return std::nullopt;
  if (!(in >> std::ws).eof()) return std::nullopt;
  if (!(u.planned_done_s >= 0.0) || !(u.planned_total_s >= 0.0)) return std::nullopt;
  return u;
}

inline std::string format_check_progress(const CheckProgress& c) {
  char buf[160];
  std::snprintf(buf, sizeof buf, "checking %s %llu %llu %llu %llu\n", c.pass == CheckPass::kFit ? "fit" : "check",
                static_cast<unsigned long long>(c.line), static_cast<unsigned long long>(c.bytes_read),
                static_cast<unsigned long long>(c.total_bytes), static_cast<unsigned long long>(c.blocks));
  return buf;
}

/// The check's progress in one line (without or with its newline); nothing when it is not one.
inline std::optional<CheckProgress> parse_check_progress(std::string_view line) {
  std::istringstream in{std::string(line)};
  std::string word, pass;
  CheckProgress c;
  if (!(in >> word) || word != "checking" || !(in >> pass) || (pass != "fit" && pass != "check")) return std::nullopt;
  c.pass = pass == "fit" ? CheckPass::kFit : CheckPass::kCheck;
  if (!(in >> c.line >> c.bytes_read >> c.total_bytes >> c.blocks)) return std::nullopt;
  if (!(in >> std::ws).eof()) return std::nullopt;
  return c;
}

/// "pause LINE M0\n" (or M1): the machine stands at the program's pause on LINE.
struct PauseRequest {
  std::uint32_t line = 0;
  bool optional = false;  // M1
};

inline std::string format_pause_request(const PauseRequest& p) {
  return "pause " + std::to_string(p.line) + (p.optional ? " M1\n" : " M0\n");
}

inline std::optional<PauseRequest> parse_pause_request(std::string_view line) {
  std::istringstream in{std::string(line)};
  std::string word, m;
  PauseRequest p;
  if (!(in >> word) || word != "pause" || !(in >> p.line >> m) || (m != "M0" && m != "M1")) return std::nullopt;
  if (!(in >> std::ws).eof()) return std::nullopt;
  p.optional = m == "M1";
  return p;
}

}  // namespace pcnc
