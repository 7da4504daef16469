// main.cpp — pcnc-rt, the machine process: creates the shared segment, asks for real-time
// scheduling and locked memory, and runs the 2 kHz loop until SIGINT/SIGTERM.
#include <sched.h>
#include <signal.h>
#include <spdlog/spdlog.h>
#include <sys/mman.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <atomic>
#include <cerrno>
#include <cstring>

#include "config/config.hpp"
#include "config/process_start.hpp"
#include "loop/rt_loop.hpp"
#include "ipc/segment.hpp"

namespace {
std::atomic<bool> g_stop{false};
void on_signal(int) { g_stop.store(true); }

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
      "the segment on exit. Normally started by `pcnc run`; start it yourself for service use with pcnc-host --serve."};
  std::string config_path = pcnc::default_config_path();
  std::string clock = "real";
  std::string trace_path;
  std::string log_level = "info";
  int ready_fd = -1;
  app.add_option("--config", config_path, "machine configuration (TOML)")->capture_default_str();
  app.add_option("--clock", clock,
                 "real: one cycle per period on CLOCK_MONOTONIC; virtual: the same cycles back to back, "
                 "as fast as the host feeds blocks (deterministic replay)")
      ->check(CLI::IsMember({"real", "virtual"}))
      ->capture_default_str();
  app.add_option("--trace", trace_path, "write the per-cycle trace CSV to this file");
  app.add_option("--log-level", log_level, "trace, debug, info, warn, error")->capture_default_str();
  app.add_option("--ready-fd", ready_fd, "write 'ready' to this file descriptor once the segment exists (for launchers)");
  CLI11_PARSE(app, argc, argv);

  pcnc::start_logging("pcnc-rt", log_level);  // stdout stays for reports

  pcnc::MachineConfig config;
  try {
    config = pcnc::load_config(config_path);
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return 2;
  }

  pcnc::on_stop_signals(on_signal);

  const bool virtual_clock = clock == "virtual";
  if (!virtual_clock) request_realtime(config.process.rt_priority);

  try {
    std::string note;
    pcnc::RtSegment segment(config.process.shm_name, &note);
    if (!note.empty()) spdlog::warn("{}", note);
    pcnc::RtLoopOptions options;
    options.virtual_clock = virtual_clock;
    options.trace_path = trace_path;
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
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return 1;
  }
  return 0;
}
