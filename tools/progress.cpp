// progress.cpp — progress lines from pcnc-host and their display (see progress.hpp).
#include "progress.hpp"

#include <sys/ioctl.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>

namespace pcnc {

ProgressView make_progress_view(const ProgressUpdate& u, double elapsed_s) {
  ProgressView v;
  v.elapsed_s = elapsed_s;
  if (u.planned_total_s > 0.0) {
    // From the plan (gcode/planned_time.hpp): the fraction of the planned time done, and the
    // planned time that remains at the pace of the run so far (wall time per planned second,
    // which takes in the flowing junctions, the override and the clock). Never shown on the
    // first percent.
    v.fraction = std::clamp(u.planned_done_s / u.planned_total_s, 0.0, 1.0);
    if (v.fraction >= 0.01 && elapsed_s > 0.0) {
      v.remaining_s = (u.planned_total_s - std::min(u.planned_done_s, u.planned_total_s)) * elapsed_s / u.planned_done_s;
    }
    return v;
  }
  if (u.total_lines > 0) {
    v.fraction = std::clamp(static_cast<double>(u.line) / static_cast<double>(u.total_lines), 0.0, 1.0);
  }
  // no plan (an older host): a straight extrapolation of the wall time per line so far
  if (v.fraction >= 0.01 && elapsed_s > 0.0) v.remaining_s = elapsed_s * (1.0 - v.fraction) / v.fraction;
  return v;
}

std::string format_duration(double seconds) {
  if (!(seconds >= 0.0)) seconds = 0.0;
  const auto total = static_cast<long long>(std::llround(seconds));
  char buf[64];
  if (total >= 3600) {
    std::snprintf(buf, sizeof buf, "%lld:%02lld:%02lld", total / 3600, (total / 60) % 60, total % 60);
  } else {
    std::snprintf(buf, sizeof buf, "%lld:%02lld", total / 60, total % 60);
  }
  return buf;
}

std::string format_progress_bar(const ProgressView& v, const ProgressUpdate& u, int bar_width) {
  std::string bar;
  if (bar_width > 0) {
    const int filled = static_cast<int>(std::floor(v.fraction * bar_width));
    bar = "[" + std::string(static_cast<std::size_t>(filled), '#') +
          std::string(static_cast<std::size_t>(bar_width - filled), '.') + "] ";
  }
  char buf[256];
  std::snprintf(buf, sizeof buf, "%5.1f %%  line %u/%llu  elapsed %s  left %s  machine %s", 100.0 * v.fraction, u.line,
                static_cast<unsigned long long>(u.total_lines), format_duration(v.elapsed_s).c_str(),
                v.remaining_s ? format_duration(*v.remaining_s).c_str() : "?", format_duration(u.machine_time_s).c_str());
  return bar + buf;
}

std::string format_progress_log(const ProgressView& v, const ProgressUpdate& u) {
  char buf[256];
  std::snprintf(buf, sizeof buf, "pcnc: line %u/%llu (%.1f %%), elapsed %s, %s%s left, machine time %s", u.line,
                static_cast<unsigned long long>(u.total_lines), 100.0 * v.fraction, format_duration(v.elapsed_s).c_str(),
                v.remaining_s ? "about " : "", v.remaining_s ? format_duration(*v.remaining_s).c_str() : "unknown time",
                format_duration(u.machine_time_s).c_str());
  return buf;
}

namespace {
const char* pass_label(CheckPass pass) { return pass == CheckPass::kFit ? "measuring for --fit" : "checking"; }
}  // namespace

std::string format_check_bar(const CheckProgress& c, double elapsed_s, std::optional<double> left_s, int bar_width) {
  const double f = c.fraction();
  std::string bar;
  if (bar_width > 0) {
    const int filled = static_cast<int>(std::floor(f * bar_width));
    bar = "[" + std::string(static_cast<std::size_t>(filled), '#') +
          std::string(static_cast<std::size_t>(bar_width - filled), '.') + "] ";
  }
  char buf[256];
  std::snprintf(buf, sizeof buf, "%s  %s%5.1f %%  line %llu  elapsed %s  left %s", pass_label(c.pass), bar.c_str(),
                100.0 * f, static_cast<unsigned long long>(c.line), format_duration(elapsed_s).c_str(),
                left_s ? format_duration(*left_s).c_str() : "?");
  return buf;
}

std::string format_check_log(const CheckProgress& c, double elapsed_s, std::optional<double> left_s) {
  char buf[256];
  std::snprintf(buf, sizeof buf, "pcnc: %s line %llu (%.1f %% of the file), elapsed %s, %s%s left", pass_label(c.pass),
                static_cast<unsigned long long>(c.line), 100.0 * c.fraction(), format_duration(elapsed_s).c_str(),
                left_s ? "about " : "", left_s ? format_duration(*left_s).c_str() : "unknown time");
  return buf;
}

ProgressDisplay::ProgressDisplay(std::FILE* out, bool terminal, double log_interval_s)
    : out_(out), terminal_(terminal), interval_s_(log_interval_s), start_(std::chrono::steady_clock::now()) {}

bool ProgressDisplay::is_terminal(std::FILE* out) {
  if (!isatty(fileno(out))) return false;
  const char* term = std::getenv("TERM");
  return !(term && std::strcmp(term, "dumb") == 0);
}

namespace {
int terminal_columns(std::FILE* out) {
  winsize ws{};
  if (ioctl(fileno(out), TIOCGWINSZ, &ws) == 0 && ws.ws_col > 0) return ws.ws_col;
  return 80;
}
}  // namespace

void ProgressDisplay::update(const ProgressUpdate& u) {
  const auto now = std::chrono::steady_clock::now();
  const ProgressView v = make_progress_view(u, std::chrono::duration<double>(now - start_).count());
  // the text after the bar is about 70 characters; the bar takes what is left (up to 30)
  const int bar = terminal_ ? std::clamp(terminal_columns(out_) - 75, 0, 30) : 0;
  show(terminal_ ? format_progress_bar(v, u, bar) : std::string(), terminal_ ? std::string() : format_progress_log(v, u),
       v.elapsed_s);
}

void ProgressDisplay::checking(const CheckProgress& c) {
  const auto now = std::chrono::steady_clock::now();
  if (!pass_ || *pass_ != c.pass) {
    pass_ = c.pass;
    pass_start_ = now;
    pass_fraction0_ = c.fraction();
  }
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  // the pace of this pass since it was first seen (a pass starts 0.1 s before its first report)
  std::optional<double> left;
  const double done = c.fraction() - pass_fraction0_;
  const double pass_s = std::chrono::duration<double>(now - pass_start_).count();
  if (done >= 0.01 && pass_s > 0.0) left = pass_s * (1.0 - c.fraction()) / done;
  const int bar = terminal_ ? std::clamp(terminal_columns(out_) - 70, 0, 30) : 0;
  show(terminal_ ? format_check_bar(c, elapsed, left, bar) : std::string(),
       terminal_ ? std::string() : format_check_log(c, elapsed, left), elapsed);
}

// On a terminal: redraws the one line; else a log line at most every interval_s_ (and none in
// the first interval_s_: short runs print no progress at all).
void ProgressDisplay::show(const std::string& bar_text, const std::string& log_text, double elapsed_s) {
  const auto now = std::chrono::steady_clock::now();
  if (terminal_) {
    const int columns = terminal_columns(out_);
    std::string text = bar_text;
    if (static_cast<int>(text.size()) >= columns) text.resize(static_cast<std::size_t>(std::max(columns - 1, 0)));
    std::fprintf(out_, "\r%s\x1b[K", text.c_str());
    std::fflush(out_);
    drawn_ = true;
    return;
  }
  if (last_log_ && std::chrono::duration<double>(now - *last_log_).count() < interval_s_) return;
  if (!last_log_ && elapsed_s < interval_s_) return;
  last_log_ = now;
  std::fprintf(out_, "%s\n", log_text.c_str());
  std::fflush(out_);
}

void ProgressDisplay::finish() {
  if (terminal_ && drawn_) {
    std::fprintf(out_, "\r\x1b[K");
    std::fflush(out_);
  }
  drawn_ = false;
}

}  // namespace pcnc
