// run_report.hpp — the short report printed after `pcnc run`: how long the program took on
// the machine, how much was run, where the tool ended, and how well the servo followed.
//
// May include: shared/, gcode/program.hpp (the check result), report/. Nothing from service/.
#pragma once

#include <string>

#include "gcode/program.hpp"
#include "report/job_result.hpp"

namespace pcnc {

struct RunReport {
  std::string program;
  CheckResult check;
  JobResult job;
  double path_tolerance_mm = 0.0;  // motion.path_tolerance_mm of the run (0: off)
};

/// Plain text for the terminal.
std::string format_run_report(const RunReport& report);

/// Final tool position in program coordinates: (machine - offset) / scale.
Vec3 to_program_coordinates(const Vec3& machine, const Transform& t);

}  // namespace pcnc
