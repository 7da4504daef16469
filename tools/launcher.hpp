// launcher.hpp — `pcnc run`: starts pcnc-rt and pcnc-host as two real processes, forwards
// Ctrl-C/SIGTERM to both, waits, and turns their endings into one meaningful exit status.
// If either dies, it stops the other and says which one died and why.
#pragma once

#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace pcnc {

struct LaunchOptions {
  std::string rt_path;                 // pcnc-rt executable
  std::string host_path;               // pcnc-host executable
  std::vector<std::string> rt_args;    // after the program name
  std::vector<std::string> host_args;
  double rt_start_timeout_s = 10.0;    // how long pcnc-rt may take to create the segment
  // When set, pcnc-host gets a socket (--progress-fd N) and each line it writes there is
  // handed to this function, from a reader thread, until the host exits. After the line
  // "done" the launcher answers "ok" (the host waits for it before printing its report).
  std::function<void(std::string_view line)> on_progress_line;
};

/// Exit status: the host's status when both end normally; 3 when pcnc-rt died or failed to
/// start; 128+N when interrupted by signal N.
int launch_pair(const LaunchOptions& options);

/// Directory of the running executable (to find pcnc-rt and pcnc-host beside pcnc).
std::string executable_dir();

}  // namespace pcnc
