// safety.hpp — what the rt trips on each cycle, besides the block check it shares with the
// host (ipc/block_check.hpp): setpoints outside the travel (soft limits) and the
// following-error limit per axis. Pure functions; the cycle (cycle.cpp) decides what trips.
#pragma once

#include "config/config.hpp"
#include "geometry/vec3.hpp"

namespace pcnc {

/// Blocks may touch the travel's ends within motion.block_tolerance_mm (rounding, accepted
/// by check_block): such setpoint coordinates are put onto the limit. Anything further out
/// is left as it is, for outside_travel (ipc/block_check.hpp) to trip on.
void clamp_onto_travel(Vec3& setpoint, const MachineConfig& config);

/// Returns the first axis with |ferr| > its following_error_limit_mm, or −1.
int following_error_axis(const Vec3& ferr, const MachineConfig& config);

}  // namespace pcnc
