// safety.cpp — the following-error test (see safety.hpp).
#include "loop/safety.hpp"

#include <cmath>

namespace pcnc {

int following_error_axis(const Vec3& ferr, const MachineConfig& cfg) {
  for (int i = 0; i < kAxes; ++i) {
    if (!(std::abs(ferr[i]) <= cfg.axes[i].following_error_limit_mm)) return i;
  }
  return -1;
}

}  // namespace pcnc
