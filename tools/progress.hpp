// progress.hpp — how far `pcnc run` has got, shown to the user while the program runs.
//
// Before the machine moves, the program is checked (pcnc check; pcnc run's host): that pass
// reports its own progress (gcode/check_progress.hpp), shown the same way.
//
// pcnc-host reports its progress as one text line per update on a pipe the launcher gives
// it (--progress-fd); the launcher (pcnc) parses the lines and shows them on its own stderr:
// on a terminal a bar redrawn in place (line, percent, elapsed, time left); otherwise —
// a log file, CI, a pipe — a plain line every few seconds. The terminal test is done by the
// process that owns the terminal (pcnc), on the stream the bar goes to.
#pragma once

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <optional>
#include <string>
#include <string_view>

#include "gcode/check_progress.hpp"
#include "service/progress_update.hpp"  // the pipe line format (ProgressUpdate)

namespace pcnc {

/// What the bar shows, computed from an update and the wall time since the start.
struct ProgressView {
  double fraction = 0.0;   // 0..1 of the program's planned time (of its lines without a plan)
  double elapsed_s = 0.0;  // wall
  std::optional<double> remaining_s;  // wall; none until 1 % is done
};
ProgressView make_progress_view(const ProgressUpdate& u, double elapsed_s);

/// "[#########.........]  45.2 %  line 1234/2730  elapsed 0:12  left 0:15  machine 3:04.2"
std::string format_progress_bar(const ProgressView& v, const ProgressUpdate& u, int bar_width);
/// "pcnc: line 1234/2730 (45.2 %), elapsed 0:12, about 0:15 left, machine time 3:04.2"
std::string format_progress_log(const ProgressView& v, const ProgressUpdate& u);
/// 75 -> "1:15", 3725 -> "1:02:05"
std::string format_duration(double seconds);

/// The check's progress (pcnc check, and pcnc run before anything moves): `elapsed_s` since the
/// command started, `left_s` the estimate for the rest of this pass (none yet).
/// "checking  [#########.........]  45.2 %  line 12345  elapsed 0:12  left 0:15"
/// (--fit's pass: "measuring for --fit" in place of "checking")
std::string format_check_bar(const CheckProgress& c, double elapsed_s, std::optional<double> left_s, int bar_width);
/// "pcnc: checking line 12345 (45.2 % of the file), elapsed 0:12, about 0:15 left"
std::string format_check_log(const CheckProgress& c, double elapsed_s, std::optional<double> left_s);

/// Shows updates on `out`. `terminal`: redraw one line in place (\r, erase to end of line);
/// else print a log line at most every `log_interval_s` of wall time.
class ProgressDisplay {
 public:
  ProgressDisplay(std::FILE* out, bool terminal, double log_interval_s = 5.0);
  /// The terminal decision for a stream: isatty(fileno(out)) and TERM is not "dumb".
  static bool is_terminal(std::FILE* out);
  void update(const ProgressUpdate& u);
  /// The check's progress: the same bar (or log line) with the pass, the line reached and the
  /// part of the program's text read; the estimate of the time left is per pass, from the pace
  /// since the pass was first seen.
  void checking(const CheckProgress& c);
  /// Clears the bar (terminal) so that the run report starts on a clean line.
  void finish();

 private:
  std::FILE* out_;
  bool terminal_;
  double interval_s_;
  std::chrono::steady_clock::time_point start_;
  std::optional<std::chrono::steady_clock::time_point> last_log_;
  bool drawn_ = false;
  // the check pass being shown: when it was first seen and how far it was then
  std::optional<CheckPass> pass_;
  std::chrono::steady_clock::time_point pass_start_{};
  double pass_fraction0_ = 0.0;
  void show(const std::string& bar_text, const std::string& log_text, double elapsed_s);
};

}  // namespace pcnc
