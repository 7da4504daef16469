// safety.cpp — the soft-limit clamp and the following-error test (see safety.hpp).
#include "loop/safety.hpp"

#include <cmath>

namespace pcnc {

void clamp_onto_travel(Vec3& cmd, const MachineConfig& cfg) {
  const double tol = cfg.motion.block_tolerance_mm;
  for (int i = 0; i < kAxes; ++i) {
    const AxisConfig& a = cfg.axes[i];
    if (cmd[i] < a.travel_min_mm && cmd[i] >= a.travel_min_mm - tol) cmd[i] = a.travel_min_mm;
    if (cmd[i] > a.travel_max_mm && cmd[i] <= a.travel_max_mm + tol) cmd[i] = a.travel_max_mm;
  }
}

int following_error_axis(const Vec3& ferr, const MachineConfig& cfg) {
  for (int i = 0; i < kAxes; ++i) {
    if (!(std::abs(ferr[i]) <= cfg.axes[i].following_error_limit_mm)) return i;
  }
  return -1;
}

}  // namespace pcnc
