// soak.hpp — `pcnc soak FILE`: the fault-injection soak (docs/reliability.md, "The
// fault-injection soak"). It starts pcnc-rt (--clock real, --trace) and pcnc-host --serve on a
// private config (own socket and segment in a fresh directory), runs FILE through the control
// socket again and again for the time asked, and at random moments (seeded, printed) kills the
// host with SIGKILL and starts a new one that resumes, pauses and resumes, changes the feed
// override, jogs while paused (resume returns to the pause point) and, with --kill-rt, kills
// and restarts the rt. At the end it checks the rt's traces against the program's blocks (the
// ones `pcnc check --print-blocks` prints): every setpoint on the path, the whole path cut
// once (nothing skipped, nothing repeated beyond a resume point), no step beyond an axis's
// velocity, no acceleration beyond its limit, no setpoint outside the travel; and prints the
// figures (faults injected and survived, lost work, following error at each recovery,
// recovery times). Exit 0 when every invariant held, 1 when one failed, 2 bad command line,
// 3 a process could not be started.
#pragma once

namespace CLI {
class App;
}

namespace pcnc {

void add_soak_subcommand(CLI::App& app, int& exit_code);

}  // namespace pcnc
