// five_axis_examples_tool.cpp — `pcnc examples-5axis`: the command line around
// five_axis_examples.hpp. See five_axis_examples_tool.hpp.
#include "five_axis_examples_tool.hpp"

#include <CLI/CLI.hpp>

#include <iostream>
#include <memory>

#include "config/atomic_file.hpp"
#include "config/config.hpp"
#include "config/exit_status.hpp"
#include "five_axis_examples.hpp"

namespace pcnc {

int run_five_axis_examples_tool(const std::string& config_path, const std::string& dir, std::ostream& out,
                                std::ostream& err) {
  MachineConfig cfg;
  try {
    cfg = load_config(config_path.empty() ? default_config_path() : config_path);
  } catch (const std::exception& e) {
    err << "pcnc examples-5axis: " << e.what() << "\n";
    return kExitBadInput;
  }
  if (cfg.kinematics.kind == KinematicsKind::kTrivial || cfg.tilt_joint() == nullptr) {
    err << "pcnc examples-5axis: " << cfg.name
        << " has no rotary kinematics; expected a 5-axis config such as configs/desktop-5axis.toml\n";
    return kExitBadInput;
  }
  Joints home{cfg.axes[0].home_mm, cfg.axes[1].home_mm, cfg.axes[2].home_mm, cfg.tilt_joint()->home_rad,
              cfg.rotary_joint() ? cfg.rotary_joint()->home_rad : 0.0};
  for (const FiveAxisExample& e : five_axis_examples()) {
    std::string text;
    for (const std::string& line : five_axis_program_lines(e, cfg.kinematics, cfg.rotary_travel(),
                                                           cfg.gcode.work_offsets[0], home))
      text += line + "\n";
    const std::string path = dir + "/" + e.file;
    std::string why;
    if (!write_file_atomically(path, text, &why)) {
      err << "pcnc examples-5axis: " << why << "\n";
      return kExitBadInput;
    }
    out << path << ": " << e.poses.size() << " poses\n";
  }
  return kExitOk;
}

void add_five_axis_examples_subcommand(CLI::App& app, int& exit_code) {
  auto config = std::make_shared<std::string>();
  auto dir = std::make_shared<std::string>();
  auto* sub = app.add_subcommand(
      "examples-5axis",
      "write the project's 5-axis test programs (an impeller-like blade, a tilted helix in G93, passes through the "
      "singularity) in the M428 ... M429, G1 X Y Z A C dialect of LinuxCNC's XYZAC demos, the angles from the "
      "config's kinematics (examples/5axis/README.md)");
  sub->add_option("--config", *config, "machine configuration with rotary kinematics (TOML)");
  sub->add_option("-o,--output-dir", *dir, "the directory to write the .ngc files into")
      ->required()
      ->check(CLI::ExistingDirectory);
  sub->callback([config, dir, &exit_code] { exit_code = run_five_axis_examples_tool(*config, *dir, std::cout, std::cerr); });
}

}  // namespace pcnc
