// rotary_move.hpp — what the pipeline's stages ask of a move on a machine with rotary joints:
// does it turn a joint or run under TCP (then it is never merged, smoothed or compensated; the rt
// passes its junctions at the joint-space junction speed), does it only turn the tool (an "angular" move, whose path parameter and feed
// are an angle), and that angle. Pure.
#pragma once

#include "config/config.hpp"
#include "gcode/move.hpp"

namespace pcnc {

/// A straight move that turns a rotary joint or runs under tool-centre-point control.
bool moves_rotary(const Move& m);

/// A straight move whose linear axes (TCP off) or tool tip (TCP on) stand still while the tool
/// turns: its length is angular_length().
bool angular_move(const Move& m);

/// The angle an angular move turns through (rad): TCP off, the Euclidean length of the joints'
/// travel; TCP on, the angle between the tool axes at its ends.
double angular_length(const Move& m, const MachineConfig& cfg);

/// The unit tool axis the rotary joints `rot` give (workpiece coordinates).
Vec3 tool_axis_of(const MachineConfig& cfg, const Rot3& rot);

}  // namespace pcnc
