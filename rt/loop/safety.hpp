// safety.hpp — what the rt trips on each cycle, besides the block check it shares with the
// host (ipc/block_check.hpp): the following-error limit per axis.
#pragma once

#include "config/config.hpp"
#include "geometry/vec3.hpp"

namespace pcnc {

/// Returns the first axis with |ferr| > its following_error_limit_mm, or −1.
int following_error_axis(const Vec3& ferr, const MachineConfig& config);

}  // namespace pcnc
