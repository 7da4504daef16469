// tcp_path.hpp — the joints along one 5-axis move under tool-centre-point control, and the
// path speed and acceleration that keep every joint within its limits (issue 16, item 4).
// The tool tip runs on the straight line from start to end in workpiece coordinates, the tool
// axis on the great circle between the end axes (axis_slerp.hpp), both at the same fraction
// u = s / length of the path parameter s in [0, length]. Sampled at evenly spaced s, each
// sample holds the joints (inverse kinematics, each nearest the one before) and dq/ds,
// d²q/ds² (kinematics_rates.hpp). Pure.
#pragma once

#include <vector>

#include "geometry/axis_slerp.hpp"
#include "geometry/kinematics.hpp"

namespace pcnc {

/// One move: tip on a line, axis on a great circle.
struct TcpMove {
  ToolPose start, end;
};

/// The pose at fraction u in [0, 1] of the move.
ToolPose tcp_pose(const TcpMove& move, const AxisSlerp& axes, double u);

struct JointSample {
  double s = 0.0;   // path parameter (the caller's length unit, mm for the tip's length)
  Joints q{};       // joints (mm, rad)
  Joints dq{};      // dq/ds
  Joints ddq{};     // d²q/ds²
};

/// The joints at the start of `move` coming from `previous`: the inverse nearest them, except
/// when the move starts with the tool axis on the C axis (the singularity) and leaves it: then C
/// is the one the axis leaves the pole with (of the two, the nearer previous C), so that C does
/// not jump at the move's first step. It may differ from previous[kRotary]: the caller turns C
/// there before the move (the tool pose does not change while it does; x, y follow the tip).
Joints tcp_start_joints(const Kinematics& kin, const TcpMove& move, const Joints& previous,
                        const RotaryTravel& travel = {});

/// `samples` (>= 2) evenly spaced samples from s = 0 to s = length (> 0), plus one where the
/// tool axis comes nearest the C axis (+Z or −Z) inside the move, where C's rate peaks; the
/// caller chooses the length (the tip's travel, or an angular length for a move that only
/// turns the tool). The first sample's joints are tcp_start_joints, each next one the inverse
/// nearest the sample before, so C never jumps a turn and a path through the singularity
/// keeps C.
std::vector<JointSample> sample_tcp_move(const Kinematics& kin, const TcpMove& move, double length,
                                         const Joints& previous, int samples, const RotaryTravel& travel = {});

/// Per-joint limits: speed (mm/s, rad/s) and acceleration (mm/s², rad/s²), all > 0.
struct JointLimits {
  Joints velocity{};
  Joints acceleration{};
};

/// The path speed and acceleration a move may be planned with (path units/s, /s²), and which
/// joint sets each (-1: none, the requested value stands).
struct PathCaps {
  double speed = 0.0;
  double accel = 0.0;
  int speed_joint = -1;
  int accel_joint = -1;
};

/// The path speed at one sample that keeps every joint within its limits there: the smallest
/// of `feed`, v_j/|q'_j| and sqrt(a_j / (2|q''_j|)); the joint that sets it in *joint (-1: the
/// feed stands; may be null). Over the samples of a move it is the speed profile a planner may
/// follow where a joint needs a lower speed than the rest of the move.
double joint_speed_cap(const JointSample& js, const JointLimits& limits, double feed, int* joint);

/// Caps such that at every sample, for every joint j, with |ds/dt| <= speed and |d²s/dt²| <= accel:
///   |q'_j|·speed <= v_j   and   |q'_j|·accel + |q''_j|·speed² <= a_j,
/// which bound the joint's speed q'·ṡ and its acceleration q'·s̈ + q''·ṡ². The speed is
/// the smallest of `feed`, v_j/|q'_j| and sqrt(a_j / (2|q''_j|)) (so that at least half of each
/// joint's acceleration is left for speeding up and slowing down along the path); the
/// acceleration is the smallest of `accel` and (a_j − |q''_j|·speed²)/|q'_j|.
PathCaps tcp_path_caps(const std::vector<JointSample>& samples, const JointLimits& limits, double feed,
                       double accel);

}  // namespace pcnc
