// command_line.cpp — the `pcnc` command users type: run a program on the two processes,
// check a program offline, check a config, and the other front-end tools, as CLI11
// subcommands. Every command keeps one exit status table (config/exit_status.hpp).
// In the pcnc_tools library with the commands' own files, so that a unity build compiles
// CLI11 with them rather than once more for the executable (pcnc_main.cpp).
#include "command_line.hpp"

#include <CLI/CLI.hpp>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "biarc_tool.hpp"
#include "check.hpp"
#include "config_check.hpp"
#include "ctl.hpp"
#include "five_axis_examples_tool.hpp"
#include "config/config.hpp"
#include "config/exit_status.hpp"
#include "config/output_path.hpp"
#include "launcher.hpp"
#include "measure.hpp"
#include "nurbs_tool.hpp"
#include "progress.hpp"
#include "report/run_outputs.hpp"
#include "ruled_tool.hpp"
#include "serve.hpp"
#include "soak.hpp"
#include "surface_tool.hpp"

namespace pcnc {

int run_command_line(int argc, char** argv) {
  CLI::App app{"pcnc: an open PC-based NC controller for a 3-axis desktop mill.\n"
               "pcnc run replays a G-code program on pcnc-rt (the machine) and pcnc-host (the planner)."};
  app.require_subcommand(1);
  int exit_code = 0;

  // ---- run ----
  auto* run = app.add_subcommand("run", "start pcnc-rt and pcnc-host, run FILE to the end, print a run report");
  std::string file, config_path = pcnc::default_config_path(), clock = "real", contouring, offset, trace, report, summary, tool_table,
      surface, tolerance, pauses;
  bool fit = false, quiet = false, verbose = false;
  run->add_option("FILE", file, "G-code program, or a ruled-surface program in the JSON file form (a .json file: pcnc ruled --json, docs/ruled-surface.md), run as the G-code form the host makes of it")->required()->check(CLI::ExistingFile);
  run->add_option("--config", config_path, "machine configuration (TOML)")->capture_default_str();
  run->add_option("--clock", clock, "real: 2 kHz in real time; virtual: as fast as possible, same cycles")
      ->check(CLI::IsMember({"real", "virtual"}))
      ->capture_default_str();
  run->add_option("--contouring", contouring, "contouring at program start (default: the config's); M21/M22 override")
      ->check(CLI::IsMember({"on", "off"}));
  run->add_option("--tolerance", tolerance,
                  "path tolerance in mm for the whole program (smoothing, merging, corner speed); default: the "
                  "config's motion.path_tolerance_mm, changed by G64 P")
      ->check(CLI::Range(0.0, 1.0));
  run->add_option("--offset", offset, "program zero in machine coordinates X,Y,Z mm (default: the config's G54)");
  run->add_option("--tool-table", tool_table, "tool table (LinuxCNC format, mm); default: the config's gcode.tool_table");
  run->add_option("--surface", surface, "correct Z of every move by this measured surface (`pcnc surface fit`; docs/surface.md)");
  run->add_flag("--fit", fit, "scale the program down uniformly (never up) so it fits the travel; the report states the scale");
  run->add_option("--trace", trace, "write the per-cycle trace (CSV) to this file");
  run->add_option("--report", report,
                  "also write the run report as a self-contained HTML page (figures, isometric tool path, speed and "
                  "following error over time; built after both processes have ended from the compact trace pcnc-rt keeps "
                  "for it, or from the CSV when --trace is given)");
  run->add_option("--summary", summary, "also write the run's figures as JSON (check, transform, job, final status)");
  run->add_option("--pauses", pauses,
                  "what the program's M0/M1 do (pcnc run serves no control socket to resume from). ask: the machine "
                  "waits at rest and Enter continues (Ctrl-C stops); continue: it comes to rest there and goes on. "
                  "Default: ask under the real clock with a terminal on stdin, continue otherwise")
      ->check(CLI::IsMember({"ask", "continue"}));
  run->add_flag("-q,--quiet", quiet, "stderr: errors only (no G-code warnings, no progress, no process log)");
  run->add_flag("-v,--verbose", verbose, "stderr: the processes' informational log too");
  run->callback([&] {
    // Before anything starts: the config and every file the run will write. A problem with
    // either exits 2 at once, with nothing moved (and never after a long run).
    try {
      (void)pcnc::load_config(config_path);
      pcnc::check_output_paths({{trace, "--trace"}, {summary, "--summary"}, {report, "--report"}});
    } catch (const pcnc::ConfigError& e) {
      for (const auto& p : e.problems) std::fprintf(stderr, "pcnc run: %s\n", p.c_str());
      exit_code = pcnc::kExitBadInput;
      return;
    } catch (const std::exception& e) {
      std::fprintf(stderr, "pcnc run: %s; nothing was started\n", e.what());
      exit_code = pcnc::kExitBadInput;
      return;
    }
    if (!offset.empty() && !pcnc::parse_xyz(offset)) {
      std::fprintf(stderr, "pcnc run: --offset '%s': expected X,Y,Z in mm, e.g. 12.5,12.5,25; nothing was started\n",
                   offset.c_str());
      exit_code = pcnc::kExitBadInput;
      return;
    }
    pcnc::LaunchOptions lo;
    const std::string dir = pcnc::executable_dir();
    lo.rt_path = dir + "/../rt/pcnc-rt";
    lo.host_path = dir + "/../host/pcnc-host";
    // installed layout: all three side by side
    if (access((dir + "/pcnc-rt").c_str(), X_OK) == 0) lo.rt_path = dir + "/pcnc-rt";
    if (access((dir + "/pcnc-host").c_str(), X_OK) == 0) lo.host_path = dir + "/pcnc-host";
    lo.rt_args = {"--config", config_path, "--clock", clock};
    lo.host_args = {"--config", config_path, "--run", file};
    // stderr: warnings and errors by default; --quiet errors only; --verbose the processes' info log
    const char* level = quiet ? "error" : verbose ? "info" : "warn";
    for (auto* args : {&lo.rt_args, &lo.host_args}) args->insert(args->end(), {"--log-level", level});
    if (quiet) lo.host_args.push_back("--quiet");
    // --report: the HTML page needs the trace and the host's summary; --summary's time_by_cause
    // needs the trace too. Without --trace, pcnc-rt keeps only the compact trace the report
    // reads (--trace-digest, docs/replay.md); with it, the report reads the CSV. What the user
    // did not ask for goes to a temporary directory that is removed afterwards.
    std::string scratch, trace_file = trace, summary_file = summary;
    if ((!report.empty() && (trace.empty() || summary.empty())) || (!summary.empty() && trace.empty())) {
      std::string tmpl = (std::getenv("TMPDIR") ? std::string(std::getenv("TMPDIR")) : std::string("/tmp")) + "/pcnc-run-XXXXXX";
      if (mkdtemp(tmpl.data()) == nullptr) {
        std::fprintf(stderr, "pcnc: cannot create a temporary directory for the report's trace: %s\n", tmpl.c_str());
        exit_code = pcnc::kExitFault;
        return;
      }
      scratch = tmpl;
      if (trace_file.empty()) {
        trace_file = scratch + "/trace.pcct";
        lo.rt_args.insert(lo.rt_args.end(), {"--trace-digest", trace_file});
      }
      if (summary_file.empty()) summary_file = scratch + "/summary.json";
    }
    if (!trace.empty()) lo.rt_args.insert(lo.rt_args.end(), {"--trace", trace});
    if (pauses.empty()) pauses = clock == "real" && isatty(STDIN_FILENO) ? "ask" : "continue";
    lo.host_args.insert(lo.host_args.end(), {"--pauses", pauses});
    if (!contouring.empty()) lo.host_args.insert(lo.host_args.end(), {"--contouring", contouring});
    if (!offset.empty()) lo.host_args.insert(lo.host_args.end(), {"--offset", offset});
    if (fit) lo.host_args.push_back("--fit");
    if (!tolerance.empty()) lo.host_args.insert(lo.host_args.end(), {"--tolerance", tolerance});
    if (!tool_table.empty()) lo.host_args.insert(lo.host_args.end(), {"--tool-table", tool_table});
    if (!surface.empty()) lo.host_args.insert(lo.host_args.end(), {"--surface", surface});
    if (!summary_file.empty()) {
      std::filesystem::remove(summary_file);  // a stale summary must not make a report of an earlier run
      lo.host_args.insert(lo.host_args.end(), {"--summary", summary_file});
    }
    // progress: a bar when our stderr is a terminal, plain lines every few seconds otherwise
    pcnc::ProgressDisplay display(stderr, pcnc::ProgressDisplay::is_terminal(stderr));
    // (the channel is needed for --pauses ask even when --quiet hides the progress)
    if (!quiet || pauses == "ask") lo.on_progress_line = [&display, quiet](std::string_view line) {
      if (line == "done") {
        display.finish();
      } else if (const auto p = pcnc::parse_pause_request(line)) {
        display.finish();  // the launcher now waits for Enter
        std::fprintf(stderr, "pcnc: the program paused at line %u (%s): the machine waits at rest; press Enter to "
                             "continue, Ctrl-C to stop\n", p->line, p->optional ? "M1, optional stop" : "M0");
      } else if (const auto u = pcnc::parse_progress_update(line); u && !quiet) {
        display.update(*u);
      } else if (const auto c = pcnc::parse_check_progress(line); c && !quiet) {
        display.checking(*c);  // the host checks the program before anything moves
      }
    };
    // three.js is the same in every report: packed while the processes run (this process only
    // waits for them), not after
    std::shared_future<pcnc::PackedLibrary> three;
    if (!report.empty()) three = pcnc::start_packing_three_js();
    exit_code = pcnc::launch_pair(lo);
    display.finish();
    // both processes have ended: the trace is complete and flushed; the summary gets the time
    // by cause from it, the report is drawn from both
    if (!report.empty() || !summary.empty()) {
      std::error_code ec;
      if (!std::filesystem::exists(summary_file, ec)) {
        if (!report.empty()) std::fprintf(stderr, "pcnc: no HTML report: the program did not run (see above)\n");
      } else {
        try {
          pcnc::finish_run_outputs(summary_file, trace_file, report, !summary.empty(), three);
          if (!report.empty()) std::printf("  html report       %s\n", report.c_str());
        } catch (const std::exception& e) {
          std::fprintf(stderr, "pcnc: %s: %s\n", report.empty() ? "the summary's time_by_cause was not written" : "the HTML report was not written", e.what());
          if (exit_code == 0) exit_code = 1;
        }
      }
    }
    if (!scratch.empty()) {
      std::error_code ec;
      std::filesystem::remove_all(scratch, ec);
    }
  });

  // ---- check ----
  pcnc::add_check_subcommand(app, exit_code);
  pcnc::add_config_subcommand(app, exit_code);

  // ---- ctl, serve: the control socket of pcnc-host --serve ----
  pcnc::add_ctl_subcommand(app, exit_code);
  pcnc::add_serve_subcommand(app, exit_code);
  pcnc::add_grbl_subcommand(app, exit_code);
  pcnc::add_soak_subcommand(app, exit_code);
  pcnc::add_nurbs_subcommand(app, exit_code);
  pcnc::add_surface_subcommand(app, exit_code);
  pcnc::add_measure_subcommand(app, exit_code);
  pcnc::add_biarc_subcommand(app, exit_code);
  pcnc::add_ruled_subcommand(app, exit_code);
  pcnc::add_five_axis_examples_subcommand(app, exit_code);

  pcnc::add_exit_status_help(app);
  if (const int parse_status = pcnc::parse_command_line(app, argc, argv); parse_status >= 0) return parse_status;
  return exit_code;
}

}  // namespace pcnc
