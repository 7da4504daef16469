// preprocessor.hpp — pipeline stage after the preflight and the segment merge (gcode/pipeline.hpp):
// one Move to one self-contained ring Block (pure functions).
//
// The seed paper's per-move plan: motion class, driving axis and its direction flag, the
// programmed feed projected so that no axis exceeds its velocity or acceleration limit anywhere
// on the move, the deceleration-start coordinate, unit tangents at both ends; for arcs also the
// plane geometry and angular speed/acceleration. Rules (docs/gcode.md, "Preprocessing"):
//   lines: speed = min(F, min_i vmax_i/|u_i|), accel = min_i amax_i/|u_i| (u = unit direction);
//   rapids: the same with F = motion.rapid_speed_mm_s (0: unlimited, i.e. the axis maxima);
//   arcs: a per-axis bound from the largest velocity component over the swept angles, and the
//   centripetal acceleration v^2 * r / rho^2 kept within kArcCentripetalShare of the smallest
//   in-plane axis acceleration; the tangential part gets the rest of that acceleration's
//   magnitude at the block's top speed (shared/arc_limits.hpp).
#pragma once

#include "geometry/arc_limits.hpp"
#include "ipc/block.hpp"
#include "config/config.hpp"
#include "gcode/move.hpp"

namespace pcnc {


/// The Block for one move (seq left 0: the ring feeder numbers blocks).
Block make_block(const Move& move, const MachineConfig& config);
/// The same written into `out` without touching its NURBS arrays (a Block is ~2.5 kB, mostly
/// NURBS storage): every other field is set, and the NURBS counts are zeroed, so the arrays
/// mean nothing for a non-NURBS block. For streaming without clearing 2.5 kB per move.
void make_block_into(const Move& move, const MachineConfig& config, Block& out);

/// Distance needed to stop from `speed` at `accel`, or half of `length` when the move is too
/// short to reach `speed` and stop again (triangular profile). Returns the distance from the
/// start at which deceleration must begin.
double decel_start_distance(double length, double speed, double accel);

/// The driving-axis plan of a straight block (driving_speed, driving_accel, decel_start) restated
/// from its speed, accel and length after they were lowered (rotary joints, TCP), on the driving
/// axis it has; an angular block (no linear travel) gets 0, 0 and the start coordinate.
void restate_line_plan(const Move& move, Block& b);

}  // namespace pcnc
