// serve.cpp — the `pcnc serve` subcommand (see serve.hpp).
#include "serve.hpp"

#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>
#include <string>

#include "config/config.hpp"
#include "config/exit_status.hpp"
#include "config/output_path.hpp"
#include "launcher.hpp"

namespace pcnc {

bool check_serve_inputs(const char* who, const std::string& config_path, const std::string& trace) {
  try {
    (void)load_config(config_path);
    check_output_paths({{trace, "--trace"}});
  } catch (const ConfigError& e) {
    for (const auto& p : e.problems) std::fprintf(stderr, "%s: %s\n", who, p.c_str());
    return false;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: %s\n", who, e.what());
    return false;
  }
  return true;
}

LaunchOptions serve_launch_options(const std::string& config_path, const std::string& clock, const std::string& trace,
                                   const std::string& tool_table, const std::string& surface, const std::string& tolerance) {
  LaunchOptions lo;
  const std::string dir = executable_dir();
  lo.rt_path = dir + "/../rt/pcnc-rt";
  lo.host_path = dir + "/../host/pcnc-host";
  if (access((dir + "/pcnc-rt").c_str(), X_OK) == 0) lo.rt_path = dir + "/pcnc-rt";
  if (access((dir + "/pcnc-host").c_str(), X_OK) == 0) lo.host_path = dir + "/pcnc-host";
  lo.rt_args = {"--config", config_path, "--clock", clock};
  if (!trace.empty()) lo.rt_args.insert(lo.rt_args.end(), {"--trace", trace});
  lo.host_args = {"--config", config_path, "--serve"};
  if (!tool_table.empty()) {
    std::error_code ec;
    const std::string abs = std::filesystem::absolute(tool_table, ec).string();
    lo.host_args.insert(lo.host_args.end(), {"--tool-table", ec ? tool_table : abs});
  }
  if (!surface.empty()) {
    std::error_code ec;
    const std::string abs = std::filesystem::absolute(surface, ec).string();
    lo.host_args.insert(lo.host_args.end(), {"--surface", ec ? surface : abs});
  }
  if (!tolerance.empty()) lo.host_args.insert(lo.host_args.end(), {"--tolerance", tolerance});
  lo.supervise = true;  // a process that dies on its own is started again; the other stays up
  return lo;
}

void add_serve_subcommand(CLI::App& app, int& exit_code) {
  auto* serve = app.add_subcommand("serve", "start pcnc-rt and pcnc-host --serve, then serve the control socket until Ctrl-C "
                                            "(use `pcnc ctl ...` from another terminal)");
  static std::string config_path = default_config_path(), clock = "real", trace, tool_table, surface, tolerance;
  serve->add_option("--config", config_path, "machine configuration (TOML)")->capture_default_str();
  serve->add_option("--clock", clock, "real: 2 kHz in real time; virtual: as fast as possible, same cycles")
      ->check(CLI::IsMember({"real", "virtual"}))
      ->capture_default_str();
  serve->add_option("--trace", trace, "pcnc-rt writes the per-cycle trace (CSV) to this file");
  serve->add_option("--tool-table", tool_table,
                    "tool table for the service's programs (LinuxCNC format, mm); default: the config's gcode.tool_table");
  serve->add_option("--surface", surface,
                    "correct Z of the service's programs by this measured surface (docs/surface.md); default: the config's gcode.surface");
  serve->add_option("--tolerance", tolerance,
                    "path tolerance in mm for the service's programs (smoothing, merging, corner speed); default: the "
                    "config's motion.path_tolerance_mm, changed by G64 P")
      ->check(CLI::Range(0.0, 1.0));
  serve->callback([&exit_code] {
    if (!check_serve_inputs("pcnc serve", config_path, trace)) {
      exit_code = kExitBadInput;
      return;
    }
    const LaunchOptions lo = serve_launch_options(config_path, clock, trace, tool_table, surface, tolerance);
    exit_code = launch_pair(lo);
  });
}

}  // namespace pcnc
