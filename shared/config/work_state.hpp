// work_state.hpp — PROVISIONAL (replaced by the wt-state branch): the persistent work-coordinate state.
#pragma once

#include <array>
#include <string>

#include "config/config.hpp"
#include "geometry/vec3.hpp"

namespace pcnc {

struct WorkState {
  std::array<Vec3, 9> g5x{};
  int active = 0;
  Vec3 g92{};
  bool g92_applied = false;
  Vec3 g28{}, g30{};
};

inline WorkState default_work_state(const MachineConfig& c) {
  WorkState w;
  for (std::size_t i = 0; i < 6; ++i) w.g5x[i] = c.gcode.work_offsets[i];
  for (std::size_t k = 0; k < 3; ++k) w.g28[k] = w.g30[k] = c.axes[k].home_mm;
  return w;
}

}  // namespace pcnc
