// main.cpp — pcnc-host, the operator's process: checks a G-code program completely, then
// feeds its preprocessed blocks to pcnc-rt through the ring and reports the run (--run), or
// serves the control socket as a long-running service (--serve, see service.hpp).
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <unistd.h>
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <atomic>
#include <cerrno>
#include <cstdio>
#include <functional>
#include <memory>
#include <sstream>

#include "config/config.hpp"
#include "config/exit_status.hpp"
#include "config/output_path.hpp"
#include "config/process_start.hpp"
#include "service/job_runner.hpp"
#include "config/surface_file.hpp"
#include "gcode/program.hpp"
#include "service/pause_prompt.hpp"
#include "service/progress_update.hpp"
#include "report/run_report.hpp"
#include "report/run_summary.hpp"
#include "service/rt_link.hpp"
#include "service/service.hpp"

namespace {
std::atomic<bool> g_interrupt{false};
void on_signal(int) { g_interrupt.store(true); }

bool parse_vec3(const std::string& text, pcnc::Vec3& out) {
  std::stringstream ss(text);
  char c1 = 0, c2 = 0;
  ss >> out[0] >> c1 >> out[1] >> c2 >> out[2];
  return ss && c1 == ',' && c2 == ',' && ss.peek() == EOF;
}

// Errors and warnings go to stderr (stdout carries the run report alone); --quiet: errors only.
void print_diagnostics(const pcnc::CheckResult& check, bool quiet) {
  for (const auto& d : check.diagnostics) {
    const bool err = d.severity == pcnc::Diagnostic::Severity::kError;
    if (!err && quiet) continue;
    std::fprintf(stderr, "%s:%d:%d: %s: %s\n", d.file.c_str(), d.line, d.column,
                 err ? "error" : "warning", d.message.c_str());
  }
}
}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"pcnc-host: the planning process of pcnc. Checks a G-code program (syntax, words, soft limits, "
               "feeds) before anything moves, preprocesses each move into a block and feeds pcnc-rt through the "
               "4-slot shared-memory ring. pcnc-rt must be running with the same config."};
  std::string config_path = pcnc::default_config_path();
  std::string run_file, contouring, offset, summary_path, tool_table, surface, log_level = "warn", pauses = "continue";
  int progress_fd = -1;
  bool fit = false, serve = false, quiet = false;
  double tolerance = -1.0;
  double wait_rt_s = 5.0;
  app.add_option("--config", config_path, "machine configuration (TOML)")->capture_default_str();
  app.add_option("--run", run_file, "check and run this G-code program (or a .json ruled-surface program, docs/ruled-surface.md), then exit")->check(CLI::ExistingFile);
  app.add_flag("--serve", serve,
               "serve the control socket (process.socket_path) until SIGINT/SIGTERM: run programs, jog, pause... "
               "for `pcnc ctl` and scripts (docs/protocol.md); attaches to pcnc-rt when it appears");
  app.add_option("--contouring", contouring, "contouring at program start: on|off (default: the config's)")
      ->check(CLI::IsMember({"on", "off"}));
  app.add_option("--offset", offset, "program zero in machine coordinates X,Y,Z mm (default: the config's G54)");
  app.add_flag("--fit", fit, "scale the program down uniformly so it fits the travel");
  app.add_option("--tolerance", tolerance,
                 "path tolerance in mm for every program (smoothing, merging, corner speed; G64 P then ignored); "
                 "default: the config's motion.path_tolerance_mm")
      ->check(CLI::Range(0.0, 1.0));
  app.add_option("--tool-table", tool_table, "tool table (LinuxCNC format, mm); default: the config's gcode.tool_table");
  app.add_option("--surface", surface,
                 "correct Z of every move by this measured surface file (docs/surface.md); default: the config's gcode.surface");
  app.add_option("--summary", summary_path,
                 "after the run, write its machine-readable summary (JSON: check, transform, job, final status) to this "
                 "file; `pcnc run --report` builds the HTML page from it and the trace");
  app.add_option("--progress-fd", progress_fd,
                 "write progress lines (\"progress LINE TOTAL_LINES MACHINE_TIME_S PLANNED_DONE_S PLANNED_TOTAL_S\") to this file "
                 "descriptor while "
                 "running (for launchers: pcnc run shows them as a progress bar)");
  app.add_option("--pauses", pauses,
                 "--run: what the program's M0/M1 do. continue: the machine comes to rest there and goes on (no one "
                 "can resume a --run job from the control socket); ask: it waits at rest for the answer to a \"pause LINE "
                 "M0\" line on --progress-fd (\"resume\" or \"stop\")")
      ->check(CLI::IsMember({"continue", "ask"}))
      ->capture_default_str();
  app.add_option("--wait-rt", wait_rt_s, "seconds to wait for pcnc-rt's segment")->capture_default_str();
  app.add_option("--log-level", log_level, "trace, debug, info, warn, error")->capture_default_str();
  app.add_flag("-q,--quiet", quiet, "--run: print no G-code warnings (errors still go to stderr)");
  pcnc::add_exit_status_help(app);
  if (const int parse_status = pcnc::parse_command_line(app, argc, argv); parse_status >= 0) return parse_status;

  pcnc::start_logging("pcnc-host", log_level);  // stdout stays for reports
  if (run_file.empty() == !serve) {
    std::fprintf(stderr, "pcnc-host: give either --run FILE or --serve (see --help)\n");
    return 2;
  }

  if (pauses == "ask" && progress_fd < 0) {
    std::fprintf(stderr, "pcnc-host: --pauses ask needs --progress-fd (the launcher answers there)\n");
    return pcnc::kExitBadInput;
  }

  pcnc::on_stop_signals(on_signal);

  pcnc::MachineConfig config;
  try {
    config = pcnc::load_config(config_path);
    if (tolerance >= 0.0) pcnc::set_operator_tolerance(config.motion, tolerance);
  } catch (const pcnc::ConfigError& e) {
    for (const auto& p : e.problems) std::fprintf(stderr, "pcnc-host: %s\n", p.c_str());
    return pcnc::kExitBadInput;
  }
  // the summary is written after the run: a path that cannot take it fails now, not then
  try {
    pcnc::check_output_paths({{summary_path, "--summary"}});
  } catch (const std::exception& e) {
    std::fprintf(stderr, "pcnc-host: %s\n", e.what());
    return pcnc::kExitBadInput;
  }

  if (!surface.empty()) {
    config.gcode.surface = surface;  // the jobs' surface
    try {
      (void)pcnc::load_surface_file(surface);  // refused now, not at the first job
    } catch (const std::exception& e) {
      std::fprintf(stderr, "pcnc-host: %s\n", e.what());
      return pcnc::kExitBadInput;
    }
  }
  if (serve) {
    if (app.count("--log-level") == 0) spdlog::set_level(spdlog::level::info);  // a service logs what it does
    if (!tool_table.empty()) config.gcode.tool_table = tool_table;  // the jobs' tool table
    if (!config.gcode.tool_table.empty()) {
      try {
        (void)pcnc::load_tool_table(config.gcode.tool_table);  // refused now, not at the first job
      } catch (const std::exception& e) {
        std::fprintf(stderr, "pcnc-host: %s\n", e.what());
        return pcnc::kExitBadInput;
      }
    }
    try {
      pcnc::Service service(config);
      service.run(g_interrupt);
      return 0;
    } catch (const std::exception& e) {
      std::fprintf(stderr, "pcnc-host: %s\n", e.what());
      return 2;
    } catch (...) {  // never std::terminate: say so and exit with the failure status
      std::fprintf(stderr, "pcnc-host: the service ended on an unknown exception\n");
      return 1;
    }
  }

  pcnc::JobOptions options;
  options.fit = fit;
  if (!contouring.empty()) options.contouring = contouring == "on";
  if (!offset.empty()) {
    pcnc::Vec3 v;
    if (!parse_vec3(offset, v)) {
      std::fprintf(stderr, "pcnc-host: --offset must be X,Y,Z in mm, e.g. 12.5,12.5,20; got '%s'\n", offset.c_str());
      return 2;
    }
    options.offset = v;
  }
  if (const std::string why = pcnc::load_job_state(config, tool_table, options); !why.empty()) {
    std::fprintf(stderr, "pcnc-host: %s\n", why.c_str());
    return 2;
  }
  options.on_message = [&](const pcnc::ProgramMessage& m) {
    std::fprintf(stderr, "%s:%d: %s: %s\n", run_file.c_str(), m.line,
                 m.kind == pcnc::MessageKind::kPrint ? "print" : "message", m.text.c_str());
  };

  std::unique_ptr<pcnc::RtLink> link;
  try {
    link = pcnc::RtLink::attach(config, wait_rt_s);
  } catch (const std::exception& e) {  // pcnc-rt is not there (or not ours): nothing can move
    std::fprintf(stderr, "pcnc-host: %s\n", e.what());
    return pcnc::kExitProcessDied;
  }
  try {
    const pcnc::Status initial = link->status();
    options.start_position = initial.commanded;
    options.start_rotary = initial.rot_commanded;

    if (progress_fd >= 0) {
      signal(SIGPIPE, SIG_IGN);  // the progress reader may go away before we do
      fcntl(progress_fd, F_SETFL, fcntl(progress_fd, F_GETFL) | O_NONBLOCK);  // never wait for the reader
    }
    // The check of a long program: its progress for the launcher's display, and a stop signal
    // ends it there (nothing has moved).
    options.on_check_progress = [&](const pcnc::CheckProgress& c) {
      if (g_interrupt.load()) throw pcnc::CheckInterrupted("the check was interrupted by a stop signal before the end of the program");
      if (progress_fd < 0) return;
      const std::string line = pcnc::format_check_progress(c);
      if (write(progress_fd, line.data(), line.size()) < 0 && errno != EAGAIN && errno != EINTR) progress_fd = -1;
    };
    pcnc::CheckResult check = pcnc::check_program(run_file, config, options);
    options.on_check_progress = nullptr;  // a probing run's checks of the rest report nothing
    print_diagnostics(check, quiet);
    if (check.interrupted) {
      std::fprintf(stderr, "pcnc-host: the check of %s was interrupted; nothing was moved\n", run_file.c_str());
      return pcnc::kExitSignalBase + SIGINT;
    }
    if (!check.ok) {
      std::fprintf(stderr, "pcnc-host: %s has errors; nothing was moved\n", run_file.c_str());
      return 2;
    }
    pcnc::JobRunner runner(*link, config);
    pcnc::RunReport report;
    report.program = run_file;
    report.path_tolerance_mm = config.motion.path_tolerance_mm;
    std::function<void(const pcnc::JobProgress&)> on_progress;
    if (progress_fd >= 0) {
      const std::uint64_t total_lines = check.lines;
      const double planned_total = check.planned_time_s;
      on_progress = [&, total_lines, planned_total](const pcnc::JobProgress& p) {
        const std::string line = pcnc::format_progress_update(
            {p.status.line, total_lines, p.status.program_time_s, p.planned_done_s, planned_total});
        // best effort: a full pipe skips an update, a reader that went away ends them
        if (write(progress_fd, line.data(), line.size()) < 0 && errno != EAGAIN && errno != EINTR) progress_fd = -1;
      };
    }
    if (pauses == "ask") {
      runner.set_program_pauses(pcnc::ProgramPauses::kAsk, [&](const pcnc::PauseAt& at) {
        return pcnc::ask_over_progress_channel(progress_fd, at, g_interrupt);
      });
    } else {
      runner.set_program_pauses(pcnc::ProgramPauses::kContinue);
    }
    report.job = runner.run(run_file, options, check, g_interrupt, on_progress);
    const pcnc::WorkState work_before = options.work ? *options.work : pcnc::default_work_state(config);
    if (runner.work_after() && !(*runner.work_after() == work_before)) {  // G10, G92, G28.1 ...: kept for the next program, as LinuxCNC's var file
      try {
        pcnc::save_work_state(pcnc::work_state_path(config), *runner.work_after());
      } catch (const std::exception& e) {
        std::fprintf(stderr, "pcnc-host: the work offsets were not saved: %s\n", e.what());
      }
    }
    if (progress_fd >= 0 && write(progress_fd, "done\n", 5) == 5) {
      pollfd pfd{progress_fd, POLLIN, 0};  // the launcher clears its display, then answers
      char ok[8];
      if (poll(&pfd, 1, 500) > 0 && read(progress_fd, ok, sizeof ok) < 0) spdlog::debug("progress channel closed");
    }
    report.check = std::move(check);
    std::fputs(pcnc::format_run_report(report).c_str(), stdout);
    if (!summary_path.empty()) {
      try {
        pcnc::write_run_summary(
            pcnc::make_run_summary(report, config, config_path, options.contouring.value_or(config.motion.contouring_default)),
            summary_path);
      } catch (const std::exception& e) {
        std::fprintf(stderr, "pcnc-host: %s\n", e.what());
        if (report.job.end == pcnc::JobEnd::kCompleted) return 1;
      }
    }
    if (report.job.final_status.trace_failed) {
      std::fprintf(stderr, "pcnc-host: pcnc-rt could not write its trace (its message names the file): the trace is "
                           "incomplete and the run is not clean\n");
      if (report.job.end == pcnc::JobEnd::kCompleted) return 1;
    }
    switch (report.job.end) {
      case pcnc::JobEnd::kCompleted: return 0;
      case pcnc::JobEnd::kInterrupted: return 130;
      case pcnc::JobEnd::kRtLost: return 3;
      default: return 1;
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "pcnc-host: %s\n", e.what());
    return 1;
  }
}
