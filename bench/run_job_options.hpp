// run_job_options.hpp — the job options of `pcnc run FILE [--fit] --contouring on|off` as the
// benches that re-check a program need them: the same --fit transform and start (the machine at
// its home position, where pcnc run starts), so their figures line up with the run's trace.
#pragma once

#include <cstddef>

#include "config/config.hpp"
#include "gcode/program.hpp"

namespace pcnc {

inline JobOptions run_job_options(const MachineConfig& c, bool fit, bool contouring) {
  JobOptions o;
  o.fit = fit;
  o.contouring = contouring;
  Vec3 home{};
  for (std::size_t i = 0; i < static_cast<std::size_t>(kAxes); ++i) home[i] = c.axes[i].home_mm;
  o.start_position = home;
  return o;
}

}  // namespace pcnc
