// safety.hpp — what the rt refuses or trips on, as pure checks the machine calls each cycle:
//
//  * check_block: a block from the ring is refused (kBadBlock / kSequence) when it is
//    corrupt or impossible: non-finite numbers, unknown kind, a sequence gap or repeat, a start
//    that does not continue from the previous end, a length inconsistent with its geometry,
//    points (or an arc's bulge) outside the travel, speed/accel <= 0 on a motion, arc radius
//    or angle mismatch. The reason is a static string (no allocation in the cycle).
//  * outside_travel: soft-limit test of a setpoint.
//  * following_error_axis: the first axis whose following error exceeds its limit.
#pragma once

#include <cstdint>

#include "ipc/block.hpp"
#include "config/config.hpp"
#include "ipc/status.hpp"

namespace pcnc {

struct BlockVerdict {
  FaultCode fault = FaultCode::kNone;  // kNone: accepted
  const char* reason = "";             // static text naming the defect
  std::uint8_t axis = 0;               // axis concerned, when one is
  double value = 0.0;                  // the offending number, when one is
};

/// `expected_start`: where the previous block ended (or the machine stands);
/// `expected_seq`: the sequence number this block must carry.
BlockVerdict check_block(const Block& block, const Vec3& expected_start, std::uint64_t expected_seq,
                         const MachineConfig& config);

/// Soft limits: returns the first axis outside [travel_min − tol, travel_max + tol], or −1.
int outside_travel(const Vec3& p, const MachineConfig& config, double tol_mm);

/// Returns the first axis with |ferr| > its following_error_limit_mm, or −1.
int following_error_axis(const Vec3& ferr, const MachineConfig& config);

}  // namespace pcnc
