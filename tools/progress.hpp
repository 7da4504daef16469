// progress.hpp — how far `pcnc run` has got, shown to the user while the program runs.
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

/// Shows updates on `out`. `terminal`: redraw one line in place (\r, erase to end of line);
/// else print a log line at most every `log_interval_s` of wall time.
class ProgressDisplay {
 public:
  ProgressDisplay(std::FILE* out, bool terminal, double log_interval_s = 5.0);
  /// The terminal decision for a stream: isatty(fileno(out)) and TERM is not "dumb".
  static bool is_terminal(std::FILE* out);
  void update(const ProgressUpdate& u);
  /// Clears the bar (terminal) so that the run report starts on a clean line.
  void finish();

 private:
  std::FILE* out_;
  bool terminal_;
  double interval_s_;
  std::chrono::steady_clock::time_point start_;
  std::optional<std::chrono::steady_clock::time_point> last_log_;
  bool drawn_ = false;
};

}  // namespace pcnc
