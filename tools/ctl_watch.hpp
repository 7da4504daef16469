// ctl_watch.hpp — the text of `pcnc ctl status --watch` from a status object (pure, so tests
// can read it): the block redrawn on a terminal, the line printed when piped, and the
// progress the bar shows (the planned time done, the time left at the pace so far).
#pragma once

#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <vector>

namespace pcnc {

struct WatchProgress {
  double fraction = 0.0;              // of the program's planned time
  std::optional<double> remaining_s;  // machine time left; none before 1 %
};
/// Nothing without a job under way that has a plan (status job.planned_time_s).
std::optional<WatchProgress> watch_progress(const nlohmann::json& status);

/// While the service checks the program before it runs (status job.check_fraction): "checking
/// [###...] 30.2 %  line 12345" (or "measuring for --fit ..."); empty otherwise.
std::string watch_check(const nlohmann::json& status);

/// The terminal block: the same number of lines for every status with the rt attached.
std::vector<std::string> format_watch(const nlohmann::json& status);
/// The piped form: one line.
std::string format_watch_line(const nlohmann::json& status);

}  // namespace pcnc
