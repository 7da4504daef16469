// block_check.hpp — what a valid block is: the one check that the rt runs on every block it
// takes from the ring and that `pcnc check` runs on every block the front end makes, so that
// what check accepts is exactly what the rt executes. Pure, allocation-free.
//
//  * check_block: a block is refused (kBadBlock / kSequence) when it is
//    corrupt or impossible: non-finite numbers, unknown kind, a sequence gap or repeat, a start
//    that does not continue from the previous end, a length inconsistent with its geometry,
//    points (or an arc's bulge) outside the travel, speed/accel <= 0 on a motion, arc radius
//    or angle mismatch, direction cosines that are not the path's tangents, or a plan that
//    disagrees with the path: the seed's driving-axis plan (driving_axis, driving_dir,
//    driving_speed, driving_accel, decel_start), an arc's angular plan (angular_speed,
//    angular_accel, decel_start_angle) and the motion class are recomputed from the
//    path-length plan the executor runs (length, speed, accel, geometry) with the host's
//    rules, and the reason names the field that disagrees ("driving axis plan disagrees with
//    the path: decel_start"). The reason is a static string (no allocation in the cycle).
//  * outside_travel: soft-limit test of a point.
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

/// The rotary joints' part (block_check_rotary.cpp): `tail_rot` is where the previous block left
/// the rotary joints (rad). Refuses non-finite values, a joint the machine does not have, rotary
/// motion or TCP on anything but a straight move or a ruled block (always under TCP), a start that does not continue, an end outside
/// a joint's travel, a TCP block whose end joints do not give its end tip and axis (forward
/// kinematics) or end outside the travel, and an angular block whose length is not its turn.
/// Run after check_block, which it does not repeat.
BlockVerdict check_rotary(const Block& block, const Rot3& tail_rot, const MachineConfig& config);

/// The ruled block's own part (block_check_ruled.cpp), called by check_block: the piece's data
/// (counts, finite numbers, the Ferguson chains joining, the schedule), its agreement with the
/// block's start, end, length, speed, accel, end tangents, TCP axes and driving-axis rule, and
/// a machine with 5-axis kinematics. The joints are check_rotary's.
BlockVerdict check_ruled(const Block& block, const MachineConfig& config, double tol_mm);

/// Where a block must start: `xyz` (the linear axes where the previous block left them), or, for
/// a block under TCP, the tool tip the joints (xyz, rot) give with the block's tool length.
Vec3 expected_block_start(const Block& block, const Vec3& xyz, const Rot3& rot, const MachineConfig& config);

/// Where a block leaves the linear axes (machine mm) and the rotary joints (rad); unchanged for
/// a block that does not move.
void block_tail(const Block& block, Vec3& xyz, Rot3& rot);

/// Soft limits of the rotary joints with a travel: the first joint (0 A, 1 B, 2 C) outside
/// [min − tol, max + tol], or −1.
int outside_rotary_travel(const Rot3& r, const MachineConfig& config, double tol_rad);

/// Soft limits: returns the first axis outside [travel_min − tol, travel_max + tol], or −1.
int outside_travel(const Vec3& p, const MachineConfig& config, double tol_mm);


}  // namespace pcnc
