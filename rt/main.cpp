// main.cpp — pcnc-rt, the machine process: creates the shared segment, asks for real-time
// scheduling and locked memory, and runs the 2 kHz loop until SIGINT/SIGTERM. The first such
// signal brings a moving machine to rest along its path before the process exits (exit 0;
// 1 when it did not come to rest within the bound, or its trace could not be written
// completely); a second one ends it at once (128+N).
#include <sched.h>
#include <signal.h>
#include <spdlog/spdlog.h>
#include <sys/mman.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cerrno>
#include <cstring>

#include "config/config.hpp"
#include "config/exit_status.hpp"
#include "config/output_path.hpp"
#include "config/process_start.hpp"
#include "loop/rt_loop.hpp"
#include "loop/stop_request.hpp"
#include "ipc/segment.hpp"

namespace {
pcnc::StopRequest g_stop;
bool g_trace_stops = true;  // process.on_trace_failure, for the failure's message
void on_signal(int sig) { g_stop.note_signal(sig); }

// What the loop did with a stop signal, in the log; returns the exit status.
int report_shutdown(const pcnc::ShutdownReport& r) {
  if (!r.requested) return 0;
  const char* sig = sigabbrev_np(r.signal);
  if (r.immediate) {
    const char* second = sigabbrev_np(r.second_signal);
    spdlog::warn("second stop signal (SIG{}): exiting at once, machine {} at {:.1f} mm/s", second ? second : "?",
                 pcnc::to_string(r.final_state), r.final_speed);
    return 128 + r.second_signal;
  }
  if (r.timed_out) {
    spdlog::error("SIG{}: the machine did not come to rest within {:.1f} s (state {}, {:.1f} mm/s); exiting anyway",
                  sig ? sig : "?", r.wall_s, pcnc::to_string(r.final_state), r.final_speed);
    return 1;
  }
  if (r.was_moving) {
    spdlog::warn("SIG{}: brought the machine to rest before exiting: {} at {:.1f} mm/s, setpoint at rest after {:.1f} ms, "
                 "axes still after {:.1f} ms of machine time ({:.1f} ms wall)",
                 sig ? sig : "?", pcnc::to_string(r.state_at_request), r.speed_at_request, r.motion_rest_s * 1e3,
                 r.settled_s * 1e3, r.wall_s * 1e3);
  }
  return 0;
}

void request_realtime(int priority) {
  if (mlockall(MCL_CURRENT | MCL_FUTURE) != 0) {
    spdlog::warn("mlockall not granted ({}): page faults may delay cycles; run as root or raise RLIMIT_MEMLOCK",
                 std::strerror(errno));
  } else {
    spdlog::info("memory locked (mlockall)");
  }
  sched_param sp{};
  sp.sched_priority = priority;
  if (sched_setscheduler(0, SCHED_FIFO, &sp) != 0) {
    spdlog::warn("SCHED_FIFO priority {} not granted ({}): running under the normal scheduler, expect jitter; "
                 "run as root or grant CAP_SYS_NICE / an rtprio limit",
                 priority, std::strerror(errno));
  } else {
    spdlog::info("running SCHED_FIFO priority {}", priority);
  }
}
}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "pcnc-rt: the machine process of pcnc. Creates the shared-memory segment named in the config, then runs the "
      "interpolation, servo and simulated mill at the configured rate (2 kHz) until SIGINT/SIGTERM, and removes "
      "the segment on exit. The first SIGINT/SIGTERM brings a moving machine to rest along its path, then exits 0; a "
      "second one exits at once. Normally started by `pcnc run`; start it yourself for service use with pcnc-host "
      "--serve."};
  std::string config_path = pcnc::default_config_path();
  std::string clock = "real";
  std::string trace_path, trace_digest_path;
  std::string log_level = "info";
  int ready_fd = -1;
  app.add_option("--config", config_path, "machine configuration (TOML)")->capture_default_str();
  app.add_option("--clock", clock,
                 "real: one cycle per period on CLOCK_MONOTONIC; virtual: the same cycles back to back, "
                 "as fast as the host feeds blocks (deterministic replay)")
      ->check(CLI::IsMember({"real", "virtual"}))
      ->capture_default_str();
  app.add_option("--trace", trace_path, "write the per-cycle trace CSV to this file");
  app.add_option("--trace-digest", trace_digest_path,
                 "write the compact trace the run report reads to this file (per time slice min/max, speed runs, "
                 "decimated path; docs/replay.md)");
  app.add_option("--log-level", log_level, "trace, debug, info, warn, error")->capture_default_str();
  app.add_option("--ready-fd", ready_fd, "write 'ready' to this file descriptor once the segment exists (for launchers)");
  pcnc::add_exit_status_help(app);
  if (const int parse_status = pcnc::parse_command_line(app, argc, argv); parse_status >= 0) return parse_status;

  pcnc::start_logging("pcnc-rt", log_level);  // stdout stays for reports

  // A bad config or a trace that cannot be written: exit 2 before the segment exists.
  pcnc::MachineConfig config;
  try {
    config = pcnc::load_config(config_path);
  } catch (const pcnc::ConfigError& e) {
    for (const auto& p : e.problems) spdlog::error("{}", p);
    return pcnc::kExitBadInput;
  }
  try {
    pcnc::check_output_paths({{trace_path, "--trace"}, {trace_digest_path, "--trace-digest"}});
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return pcnc::kExitBadInput;
  }

  pcnc::on_stop_signals(on_signal);
  // A hang-up (the terminal pcnc-rt was started from went away) is a stop request too: by
  // default it would end the process with the machine moving.
  struct sigaction hup {};
  hup.sa_handler = on_signal;
  sigemptyset(&hup.sa_mask);
  sigaction(SIGHUP, &hup, nullptr);

  const bool virtual_clock = clock == "virtual";
  if (!virtual_clock) request_realtime(config.process.rt_priority);

  int exit_code = 0;
  // A trace file that reaches a size limit (RLIMIT_FSIZE) fails its write with EFBIG, reported
  // like a full disk, instead of ending the process with the machine moving.
  signal(SIGXFSZ, SIG_IGN);

  try {
    std::string note;
    pcnc::RtSegment segment(config.process.shm_name, &note);
    if (!note.empty()) spdlog::warn("{}", note);
    pcnc::RtLoopOptions options;
    options.virtual_clock = virtual_clock;
    options.trace_path = trace_path;
    options.trace_digest_path = trace_digest_path;
    options.on_trace_failure = [](const std::string& what) {
      spdlog::error("{}{}", what,
                    g_trace_stops ? "; stopping the program along the path, no program starts until pcnc-rt restarts "
                                    "(process.on_trace_failure = \"stop\")"
                                  : "; programs run on without it (process.on_trace_failure = \"continue\")");
    };
    g_trace_stops = config.process.trace_failure_stops;
    if (const auto& prev = segment.previous_status()) {
      // The dead rt's last measured position: the simulated axes stand there, at rest, as
      // absolute encoders would report after a drive's power loss. Its program is not resumed.
      options.start_position = prev->actual;
      if (prev->rotary_mask == config.rotary_mask() && prev->rotary_mask != 0) options.start_rotary = prev->rot_actual;
      spdlog::warn("the axes stand where pcnc-rt last measured them: X{:.4f} Y{:.4f} Z{:.4f} mm (it was {}{}); "
                   "starting IDLE at rest there",
                   prev->actual[0], prev->actual[1], prev->actual[2], pcnc::to_string(prev->state),
                   prev->program_active ? ", its program is abandoned" : "");
    }
    pcnc::RtLoop loop(config, segment.shm(), options);
    spdlog::info("segment '{}' ready ({} bytes); {} clock at {} Hz; config {}", config.process.shm_name,
                 sizeof(pcnc::SharedSegment), clock, config.motion.cycle_hz, config_path);
    if (ready_fd >= 0) {
      (void)!write(ready_fd, "ready\n", 6);
      close(ready_fd);
    }
    const std::uint64_t cycles = loop.run(g_stop);
    const pcnc::CycleTiming& t = loop.timing();
    spdlog::info("stopped after {} cycles; compute p50 {:.2f} us p99 {:.2f} us max {:.2f} us; wake-up latency "
                 "p50 {:.1f} us p99 {:.1f} us p99.9 {:.1f} us max {:.1f} us; {} overruns",
                 cycles, t.compute.quantile(0.5), t.compute.quantile(0.99), t.compute.max(), t.wake.quantile(0.5),
                 t.wake.quantile(0.99), t.wake.quantile(0.999), t.wake.max(), t.overruns);
    exit_code = report_shutdown(loop.shutdown());
    const std::string trace_failure = loop.close_trace();
    if (!trace_failure.empty()) {
      spdlog::error("{}", trace_failure);
      if (exit_code == 0) exit_code = 1;
    }
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return 1;
  }
  return exit_code;
}
