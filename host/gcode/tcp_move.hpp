// tcp_move.hpp — the host's joint-space plan of one straight move under tool-centre-point
// control (M428/G43.4): the tool tip on the line from start to end in workpiece coordinates,
// the tool axis on the great circle between the end orientations (geometry/tcp_path.hpp),
// sampled through the inverse kinematics as the rt will run it every cycle. From the samples:
// the joints at the end (the block's joint_end), their extremes (the preflight's soft limits
// along the move), and the path speed and acceleration that keep every joint within its
// velocity and acceleration limits (tcp_path_caps; LinuxCNC plans in Cartesian space only and
// overshoots them, its issue #1738). Pure.
#pragma once

#include <string>

#include "config/config.hpp"
#include "gcode/move.hpp"
#include "geometry/kinematics.hpp"
#include "geometry/tcp_path.hpp"
#include "ipc/block.hpp"

namespace pcnc {

struct TcpMovePlan {
  std::string error;     // empty: the move can run as programmed
  bool angular = false;  // the tip stands still: the path parameter is the tool axis's turn (rad)
  double length = 0.0;   // mm (tip) or rad (angular)
  Vec3 axis_start{}, axis_end{};
  Vec3 joint_end{};      // the linear axes at the end, machine mm
  Rot3 rot_end{};        // the rotary joints at the end, rad
  double speed = 0.0;    // path speed cap (mm/s or rad/s)
  double accel = 0.0;    // path acceleration cap
  int speed_joint = -1;  // the joint (0..4: x y z tilt rotary) that sets each cap, -1: the feed
  int accel_joint = -1;
  Joints q_min{}, q_max{};  // the joints' extremes over the samples
  int samples = 0;
};

/// Samples along the move: one every this many mm of tip travel (or of the angle, in degrees,
/// for an angular move), at least kTcpMinSamples.
constexpr double kTcpSampleStep = 0.1;
constexpr int kTcpMinSamples = 32;
constexpr int kTcpMaxSamples = 4000;
/// The caps keep this share of each joint's limit (the rt's cycles fall between the samples).
constexpr double kTcpLimitShare = 0.95;

/// Each joint's velocity and acceleration limit (x y z tilt rotary: mm, rad); a joint the machine
/// lacks gets 1.
JointLimits joint_limits(const MachineConfig& cfg);

/// `feed`: the programmed path speed (mm/s, rad/s for an angular move; a rapid: what the
/// linear axes allow along the tip's line). A null move (no tip travel, the joints where they
/// stand) is no error: length 0, the joints where they stand, nothing to run. Errors: a move that
/// only turns C on the pole (no tip travel, no turn of the tool axis, C turns), a move that leaves the pole towards another C than the one
/// C stands at, an orientation the great circle reaches at other joint values than the
/// programmed ones (the other solution, or C a turn away).
TcpMovePlan plan_tcp_move(const Move& m, const MachineConfig& cfg, double feed);

/// Writes the plan into a block made by make_block_into for `m`: TCP fields, length, speed and
/// acceleration (and the driving-axis plan restated for them).
void apply_tcp_plan(const Move& m, const TcpMovePlan& plan, Block& b);

}  // namespace pcnc
