// launcher.hpp — `pcnc run` and `pcnc serve`: starts pcnc-rt and pcnc-host as two real
// processes, forwards Ctrl-C/SIGTERM to both, waits, and turns their endings into one
// meaningful exit status.
//
// `pcnc run` (one job): when either process dies, the other is asked to end (SIGTERM: the rt
// first brings a moving machine to rest) and the launcher says which one died and why.
// `pcnc serve` (supervise): a process that dies on its own is started again and the other is
// left alone, because each survives the other's loss by itself: the rt brings the machine to
// rest on the path when the host is lost (HOST_LOST; a new host can resume), and the host
// refuses motion while the rt is gone and re-attaches to the new one. A host that exits 2
// (it refused its config or a directory it was given) is not restarted: the service ends
// with that status. Power is never cut to
// a moving process. More than `max_restarts` restarts within `restart_window_s` end the
// service (exit 3): a process that cannot stay up is a fault to look at, not to hide.
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
  // "done" the launcher answers "ok" (the host waits for it before printing its report); after
  // "pause LINE M0|M1" (pcnc-host --pauses ask) it waits for Enter on stdin and answers
  // "resume", or "stop" when stdin ends, a stop signal comes or the host goes away.
  std::function<void(std::string_view line)> on_progress_line;
  bool supervise = false;              // pcnc serve: restart a process that died on its own
  int max_restarts = 5;                // per process, within restart_window_s
  double restart_window_s = 60.0;
  double restart_delay_s = 0.2;        // before a restart (the rt needs none to stop the machine)
};

/// Exit status: the host's status when both end normally (at least 1 when pcnc-rt exited 1:
/// a failure it reported, such as a trace it could not write); 3 when pcnc-rt died or failed
/// to start (or, supervising, kept dying); 128+N when interrupted by signal N. A child gets
/// one stop signal at most from the launcher (pcnc-rt takes a second one as "exit at once").
int launch_pair(const LaunchOptions& options);

/// Directory of the running executable (to find pcnc-rt and pcnc-host beside pcnc).
std::string executable_dir();

}  // namespace pcnc
