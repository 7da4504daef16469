// ruled_move.hpp — a ruled-surface move (G5.4 ... G5.5, issue 17) in the front-end pipeline
// (gcode/pipeline.hpp): the piece sampled through the inverse kinematics as the rt will run it
// (the interpreter's joints after the group, the preflight's soft limits along it), the feed
// the joints' velocity and acceleration limits allow, and its ring blocks (kRuled, one per
// part of at most kMaxRuledSegments segments; the parts of one piece flow into each other).
//
// The piece arrives from the interpreter in workpiece coordinates (the tool tip after the
// offsets and --fit) with unit tool vectors, under TCP with the move's tool length. Pure.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "config/config.hpp"
#include "gcode/move.hpp"
#include "geometry/kinematics.hpp"
#include "geometry/ruled_model.hpp"
#include "ipc/block.hpp"

namespace pcnc {

/// Samples per Ferguson segment when walking a piece through the inverse kinematics.
constexpr int kRuledSamplesPerSegment = 16;
/// A rotary joint turning more than this (rad) between two samples is a jump (the pole).
constexpr double kRuledJointJump = 0.1;
/// The feed keeps this share of each joint's velocity and acceleration limit (as TCP moves).
constexpr double kRuledLimitShare = 0.95;

/// At most this share of a joint's kRuledLimitShare of its acceleration limit goes to the tip's
/// tangential acceleration (the term q' s̈ of q̈ = q' s̈ + q'' ṡ²); the rest is the path's (q'' ṡ²).
constexpr double kRuledTangentialShare = 0.5;

/// The piece walked through the inverse kinematics from the joints `q0`.
struct RuledJointWalk {
  std::string error;        // empty: every sample reached
  Joints q_end{};           // the joints at the piece's end
  Joints q_min{}, q_max{};  // their extremes over the samples
  // Each joint's |q'| = |dq/ds| and |q''| = |d²q/ds²| at every sample (kRuledSamplesPerSegment
  // per segment, and the end; s the tip's arc length, mm): a joint's speed is q' ṡ and its
  // acceleration q' s̈ + q'' ṡ².
  std::vector<Joints> rate, bend;
  // Set by cap_ruled_feed for a tangential acceleration A (mm/s^2): the largest constant tip
  // speed (mm/s) at which every joint keeps kRuledLimitShare of its velocity limit and, with
  // |s̈| up to A, of its acceleration limit (|q'| A + |q''| ṡ² <= share a_max) at every sample
  double feed_cap = 0.0;
  int speed_joint = -1;     // the joint (0..4: x y z tilt rotary) that sets it, -1: none does
  std::vector<double> sample_caps;  // that cap at each sample
};
RuledJointWalk walk_ruled_piece(const RuledModel& model, const MachineConfig& cfg, double tool_length, const Joints& q0);

/// The tip's tangential acceleration for a walked piece (mm/s^2): kRuledLimitShare of the
/// slowest linear axis's acceleration, and no more than leaves every joint at every sample
/// kRuledTangentialShare of its budget for the path's term (|q'| A <= share' share a_max).
double ruled_tangential_accel(const RuledJointWalk& w, const MachineConfig& cfg);

/// Sets w.feed_cap, w.speed_joint and w.sample_caps for the tangential acceleration `accel`.
void cap_ruled_feed(RuledJointWalk& w, const MachineConfig& cfg, double accel);

/// The joints (kinematics order) where a move's rotary joints stand and its start tip lies.
Joints ruled_start_joints(const Move& m, const MachineConfig& cfg);

/// A part's feed schedule, one speed per set point (u = 0 .. n): the feed, capped at each point
/// by the joints' limits over the segments on either side (`sample_caps` of its walk), then a
/// backward pass so that every drop is reachable at half of `accel` (mm/s^2) along the arc length.
std::vector<double> ruled_feed_schedule(const RuledModel& part, const std::vector<double>& sample_caps, double feed,
                                        double accel);

/// A ruled block's fields that follow from its piece (`b.ruled`, its schedule set): start and
/// end (the tip), length, speed (the schedule's largest), the end tangents, the motion class
/// and driving axis (ruled_extent), TCP on with the end axes. The caller sets the line, accel,
/// the tool length and the joints (rotary start and end, joint_end).
void set_ruled_block_fields(Block& b);

/// The blocks of a ruled move (seq 0: the pipeline numbers them), or an error sentence.
struct RuledMoveBlocks {
  std::string error;
  std::vector<Block> blocks;
  double feed = 0.0;  // the largest speed of the blocks' schedules (the programmed feed, or less where the joints cap it)
  int speed_joint = -1;  // the joint that caps the piece somewhere, -1: none
};
RuledMoveBlocks plan_ruled_move(const Move& m, const MachineConfig& cfg);

}  // namespace pcnc
