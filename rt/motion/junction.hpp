// junction.hpp — the speed rules of the block executor's look-ahead, as pure functions:
//
//  * stop_speed: the fastest speed this cycle may use so that the machine can still slow to
//    a target speed within the path it knows (the "never commit to a speed from which you
//    cannot stop within the path already in the ring" rule);
//  * junction_flows: the seed's contouring test (M21 on and a turn under the contouring angle);
//  * junction_speed_cap: how fast a flowing corner may be passed so that the velocity step
//    on every axis stays within `fraction` of that axis's acceleration times one cycle;
//  * joint_junction_speed: the same rule in joint space, for junctions next to a block that
//    turns a rotary joint or runs under tool-centre-point control (docs/kinematics.md).
// docs/machine-model.md and docs/servo-tuning.md cite these; the rules are explained in
// the executor's header.
#pragma once

#include <array>

#include "geometry/junction_deviation.hpp"
#include "geometry/vec3.hpp"
#include "ipc/rotary_joints.hpp"

namespace pcnc {

/// Largest v >= 0 with  k·v·dt + (v² − v_end²)/(2a) <= distance : moving v·dt this cycle
/// and then braking at `accel` still reaches `v_end` (or less) before `distance` runs out.
/// k >= 1 keeps a margin for the discrete braking and for cycles whose acceleration is
/// restricted at flowing junctions (executor.hpp).
double stop_speed(double distance_mm, double v_end_mm_s, double accel_mm_s2, double dt_s, double k);

/// The exact discrete rule for a stop at rest: the largest v such that moving v·dt this
/// cycle and then braking by a·dt per cycle (each cycle moving at its new speed, the last
/// one landing at the end with a speed <= a·dt) covers exactly `distance`. Used for the last
/// block before a stop when no junction restricts the acceleration; it starts braking
/// later than stop_speed's margin would, and reaches the end without a slow creeping tail.
double stop_speed_exact(double distance_mm, double accel_mm_s2, double dt_s);

/// The continuous-time entry speed of a block of `length_mm` that must exit at `v_exit`.
double entry_speed(double length_mm, double v_exit_mm_s, double accel_mm_s2);

/// Contouring test between a block ending with tangent `dir_end` and the next starting with
/// `dir_start` (unit vectors): flows when contouring is on and the turn is under the angle
/// whose cosine is `cos_limit`.
bool junction_flows(bool contouring, const Vec3& dir_end, const Vec3& dir_start, double cos_limit);

/// Junction speed cap: per axis i, v·|dir_start_i − dir_end_i| <= fraction·a_i·dt.
/// Returns +infinity for a straight (tangent) junction.
double junction_speed_cap(const Vec3& dir_end, const Vec3& dir_start, const std::array<double, kAxes>& axis_accel,
                          double dt_s, double fraction);

/// How the share of a cycle's acceleration a flowing junction's turn takes, on its busiest axis,
/// grows with the speed v it is crossed at: coef·v for a velocity step within one cycle
/// (max_i |Δu_i| / (a_i·dt)), coef·v² where a corner window of half-length h carries the turn
/// (its peak turn acceleration, 1.5·max_i |Δu_i| / (2h·a_i)); power 0: always the whole fraction.
struct TurnShare {
  double coef = 0.0;
  int power = 0;
};

/// The TurnShare of the junction between `dir_end` and `dir_start` (unit vectors); `window_half`
/// 0 for a velocity step, else the corner window's half-length h (mm).
TurnShare turn_share(const Vec3& dir_end, const Vec3& dir_start, const std::array<double, kAxes>& axis_accel, double dt_s,
                     double window_half_mm);

/// The share at speed v, at most `fraction` (junction_velocity_step_fraction): the cycles around
/// the junction keep (1 − share)·a for the path (executor.cpp, docs/rt-executor.md).
double turn_share_at(const TurnShare& share, double v_mm_s, double fraction);

/// The rules a junction is judged by, from the config.
struct JunctionRules {
  double cos_limit = 1.0;             // cos(contouring angle)
  double step_fraction = 0.0;         // junction_velocity_step_fraction, in [0, 1]
  double path_tolerance_mm = 0.0;   // the block's (Block::path_tolerance_mm); 0: off
  double dt = 0.0;                    // cycle period, s
  std::array<double, kAxes> axis_accel{};
};

/// The speed cap of the junction between a motion block ending with `dir_end` (M21 on it:
/// `contouring`) and the next starting with `dir_start`, from the geometry alone; 0 means
/// it stops. Under M21 a turn under the contouring angle flows with junction_speed_cap;
/// with a corner tolerance every junction may also flow at junction_deviation_speed; the
/// larger cap applies.
double corner_speed(bool contouring, const Vec3& dir_end, const Vec3& dir_start, const JunctionRules& rules);

// junction_deviation_speed: geometry/junction_deviation.hpp (shared with the host's ideal planner).

/// A path's rate in the machine's joints: dq/ds for X Y Z (mm per unit of path) then A B C (rad
/// per unit of path), or d²q/ds² in the same order.
constexpr int kMachineJoints = kAxes + kRotaryJoints;
using JointRate = std::array<double, kMachineJoints>;

/// The joint-space junction rule. At path speed v a junction steps joint j's velocity by
/// v·|rate_start_j − rate_end_j| in one cycle, while the path's curvature in joint space takes
/// |curv_j|·v² of its acceleration (curv_j the larger |d²q_j/ds²| of the two ends). The largest v
/// with, for every joint,
///   v·|rate_start_j − rate_end_j| <= fraction·(accel_j − |curv_j|·v²)·dt
/// (so that the step, the curvature and the (1 − fraction) of the path acceleration the executor
/// leaves in the cycles around a junction stay within the joint's acceleration). +infinity when
/// no joint's rate changes and no joint's path is curved; a joint whose rate reverses is allowed
/// only the speed at which its whole reversal fits in fraction·accel_j·dt, practically a stop.
double joint_junction_speed(const JointRate& rate_end, const JointRate& curv_end, const JointRate& rate_start,
                            const JointRate& curv_start, const JointRate& joint_accel, double dt_s, double fraction);

}  // namespace pcnc
