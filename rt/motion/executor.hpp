// executor.hpp — the block executor: turns the ring's blocks into one setpoint per cycle.
//
// Scheme: a path-length parameter per block. The seed paper advances the driving axis (for
// lines) or the angle (for arcs) with the block's speed and acceleration and derives the
// other axes from the line equation or from sin/cos. Here every motion block is a curve p(s)
// parameterised by its path length s (path.hpp); s advances each cycle by v·dt, and for a
// line s is exactly the driving axis coordinate scaled by 1/|dir_driving|, for an arc it is
// the angle scaled by the radius. The schemes give the same setpoints; the path parameter
// lets one look-ahead pass treat lines, rapids, arcs and helices alike and carry the
// distance left over at a flowing junction into the next block of any kind.
//
// Speed law each cycle (junction.hpp), in order:
//   1. look-ahead over the blocks already in the ring (the current one and up to 3 more):
//      each junction either flows (M21 on the block, turn < contouring angle) with a speed
//      cap (per-axis velocity step <= f·a_i·dt, f = junction_velocity_step_fraction) or
//      stops; the chain's last known block ends at rest. Next to a block that turns a rotary
//      joint or runs under TCP the cap is also the joint-space rule (joint_junction_speed: every
//      joint's velocity step, X Y Z and A B C, within f of its acceleration over a cycle); an
//      angular block always stops. A backward pass gives the speed the current block may have
//      at its end;
//   2. v_allow = min(block speed × feed override (capped by what the axes allow on the curve),
//      stop_speed(distance to the end of the current block, its exit speed)); when the
//      block ends in a stop and no junction-restricted cycle is left, stop_speed_exact, the
//      exact discrete rule (braking starts at the last possible cycle, no creeping tail);
//   3. v = clamp(v_allow, v − a·dt, v + a·dt), v >= 0; in the cycles around a flowing
//      junction the path acceleration is limited to (1 − f)·a so that path acceleration plus
//      the corner's velocity step stays within each axis's acceleration;
//   4. s += v·dt; past the end of the block, the remainder continues in the next block when
//      the junction flows; otherwise the block lands exactly at its end (the last cycles
//      approach it at <= a·dt per cycle), the machine holds one cycle at rest, and the next
//      block starts from rest.
// Corner blending: a flowing junction passed at the junction-deviation speed (a real corner
// between lines, arcs or NURBS blocks with a path tolerance) is rounded over a short arc-length
// window around it (geometry/corner_blend.hpp), planned when its second block is prepared and
// added as an offset to the blocks' own path each cycle; s still runs on the speed law above, so
// the timing is unchanged (docs/rt-executor.md, "Corner blending").
// NURBS blocks (G5.2/G06.2) run in the same scheme: s is the chord length along the exact
// curve, advanced with the NURBS engineer's Taylor + Newton parameter step; the block's feed
// schedule (shared/nurbs_schedule) at the current and the predicted parameter caps the speed.
// Ruled blocks (G5.4 ... G5.5, issue 17) run by their own law: the RuledFollower
// (ruled_follower.hpp) advances the piece's parameter by the Taylor step with its correction at
// the piece's schedule times the feed override (at most 1, as the NURBS schedule caps it), and
// the cycle's setpoints are the joints of its sample, with the analytic joint velocity and
// acceleration as feed-forward. A ruled block ends at rest unless the next block in the ring is
// a ruled one that starts where it ends at speed (the parts of one piece split by the host,
// end_speed > 0): then it flows, the cycle's leftover length carried into the next.
// Feed hold / stop: all caps become 0, so the speed ramps down at the block's acceleration
// along the path; resuming ramps up again from where it stood.
// A block that starts from rest a hair away from where the machine stands (within the block
// check's tolerance: a resumed program's first block) is reached first by a straight move from
// rest to rest within the axes' limits (start_gap.hpp), not by a setpoint step.
#pragma once

#include <array>
#include <cstdint>

#include "ipc/block.hpp"
#include "config/config.hpp"
#include "motion/junction.hpp"
#include "geometry/corner_blend.hpp"
#include "geometry/nurbs.hpp"
#include "geometry/axis_slerp.hpp"
#include "geometry/kinematics.hpp"
#include "motion/nurbs_follower.hpp"
#include "motion/path.hpp"
#include "motion/ruled_follower.hpp"
#include "motion/start_gap.hpp"
#include "ipc/segment.hpp"
#include "ipc/status.hpp"

namespace pcnc {

struct ExecInput {
  bool hold = false;          // feed hold, stop or host lost: decelerate to rest on the path
  double feed_override = 1.0; // 0 .. 2
  bool resume_pause = false;  // leave an M00/M01 block
  bool probe_input = false;   // the probe's input as sensed in the last cycle (docs/probe.md)
};

struct ExecResult {
  FaultCode fault = FaultCode::kNone;  // a block was refused
  const char* reason = "";
  std::uint8_t fault_axis = 0;
  std::uint32_t fault_line = 0;
  double fault_value = 0.0;
  bool starved = false;       // nothing to execute and the ring is empty
  bool program_end = false;   // the End block completed this cycle
  bool at_pause = false;      // waiting on an M00/M01 block
  int blocks_done = 0;
  int junction_stops = 0;
  int junction_flows = 0;
  // A probing block finished this cycle (docs/probe.md): how, and the position latched.
  bool probe_done = false;
  ProbeOutcome probe_outcome = ProbeOutcome::kNone;
  Vec3 probe_latched{};
  std::uint32_t probe_line = 0;
  std::uint64_t probe_seq = 0;
  bool probe_wait = false;  // starved right after a probing block: the host is at its sync point
};

/// The share of a block's path tolerance a corner blend may take (the rest is left to the host,
/// whose curves and merged lines keep up to 90 % of the tolerance from the programmed points).
constexpr double kBlendToleranceShare = 0.35;

class Executor {
 public:
  explicit Executor(const MachineConfig& config);

  /// The machine stands at `p` at rest (start-up, after a jog or a reset). Forgets any block.
  void set_position(const Vec3& p);
  /// The rotary joints stand at `r` (rad; with set_position, at rest).
  void set_rotary(const Rot3& r);
  /// A new program starts: sequence numbers restart at 1.
  void start_program() { expected_seq_ = 1; }
  /// Drops everything in the ring and the block in execution; stays where it is (at rest
  /// expected — the machine calls this only at rest, or after amplifiers went off).
  void flush(MotionRing& ring);

  /// One cycle: validates new blocks, advances along the path, pops finished blocks.
  void step(MotionRing& ring, const ExecInput& in, ExecResult& out);

  const Vec3& position() const { return pos_; }
  const Vec3& velocity() const { return vel_; }
  const Vec3& acceleration() const { return acc_; }
  /// The rotary joints' setpoint, rad, rad/s, rad/s² (A B C by index).
  const Rot3& rotary() const { return rot_; }
  const Rot3& rotary_velocity() const { return rot_vel_; }
  const Rot3& rotary_acceleration() const { return rot_acc_; }
  /// The block in execution runs under tool-centre-point control.
  bool tcp() const { return prepared_ > 0 && prep_[0].tcp; }
  double speed() const { return v_; }
  std::uint32_t line() const { return line_; }
  std::uint64_t seq() const { return seq_; }
  bool contouring() const { return contouring_; }
  /// The last cycle's setpoint was inside a corner blend's window (docs/rt-executor.md).
  bool blending() const { return blended_; }
  /// Has a block in execution (possibly between blocks within a cycle).
  bool busy() const { return prepared_ > 0; }
  /// The motion block in execution and the path length reached on it (for the contour
  /// error), or nullptr; the motion block finished last (nullptr after a non-motion block).
  const PreparedBlock* current_motion() const { return prepared_ > 0 && prep_[0].motion ? &prep_[0] : nullptr; }
  double progress() const { return s_; }
  const PreparedBlock* previous_motion() const { return has_prev_ ? &prev_ : nullptr; }
  /// A probing block began moving this cycle along `dir`: the probe is to be armed (read once).
  bool take_probe_arm(Vec3& dir) {
    if (!probe_arm_) return false;
    probe_arm_ = false;
    dir = probe_dir_;
    return true;
  }

 private:
  bool prepare_visible(const MotionRing& ring, ExecResult& out);
  void pop(MotionRing& ring, ExecResult& out);
  void motion_step(MotionRing& ring, const ExecInput& in, ExecResult& out);
  double cap_of(const PreparedBlock& b, const ExecInput& in) const;
  double exit_speed_of_current(const ExecInput& in);
  double compute_exit_speed(const ExecInput& in) const;
  bool flows_after(std::size_t i) const;                      // geometric: junction i|i+1 flows
  double junction_cap(std::size_t i, const ExecInput& in) const;  // speed cap there (0: stop)
  void hold_still();
  /// Moves along the current block's path by ds (NURBS: chord length); sets pos_ and the
  /// tangent and curvature there. Returns true when the block's end was reached, with the
  /// distance left over past it in `leftover`.
  bool advance(const Block& blk, double ds, double& leftover);
  /// s_ = 0 (NURBS: parameter at its start); from rest, last cycle's setpoints are where it stands.
  void begin_block(const Block& blk, bool from_rest);
  /// The rotary joints (and under TCP the linear axes) at path length s_ of the current block.
  void place_joints(const Block& blk);
  /// Velocity and acceleration of the joints of a rotary block this cycle (ds = v·dt): TCP off,
  /// the path's times each joint's share; under TCP from the analytic kinematics rates.
  void joint_rates(double v_new, double v_old);
  /// Pops the finished block at a flowing junction and begins the next one (returned).
  const Block& flow_into_next(MotionRing& ring, ExecResult& out);
  /// One cycle of the ruled block in execution (see the header comment).
  void ruled_step(MotionRing& ring, const ExecInput& in, ExecResult& out);
  /// The speed the ruled block in execution may end with: > 0 only when the next block is
  /// prepared, ruled, flows on from it and can stop within its own length.
  double ruled_exit_speed(const MotionRing& ring, const ExecInput& in) const;
  /// The setpoints from the follower's sample: joints, their rates, speed and progress.
  void put_ruled(const RuledSample& s);
  /// This cycle's linear joints become last cycle's (the seed of the TCP inverse continues across
  /// a flowing junction from whatever block came before).
  void remember_cycle();
  /// Plans the corner blend of junction i (between prep_[i] and prep_[i + 1], just prepared, its
  /// speed cap `cap`); may widen the window of junction i − 1 to span a short block between them
  /// (docs/rt-executor.md, "Corner blending"). Off when the junction does not qualify.
  void plan_blend(std::size_t i, double cap);
  /// Adds the offsets of the corner windows around the path position reached to pos_, tangent_
  /// and curvature_ (the block's own path there).
  void apply_blend();
  /// Before a block that starts from rest a hair away from where the machine stands (a resumed
  /// program, start_gap.hpp): this cycle of the gap move, true when it took the cycle.
  bool start_gap_cycle(const Block& blk, const ExecInput& in);
  /// Ends the probing block in execution where the machine stands (executor_probe.cpp).
  void finish_probe(MotionRing& ring, ExecResult& out, ProbeOutcome outcome);

  MachineConfig cfg_;
  double dt_;
  double f_;               // junction velocity-step fraction, clamped to [0, 1]
  JunctionRules junction_;  // contouring angle, step fraction, corner tolerance, axis limits
  JointRate joint_accel_{};  // each joint's acceleration limit, X Y Z mm/s² then A B C rad/s²

  std::array<PreparedBlock, kRingSlots> prep_{};  // prep_[i] describes ring.peek(i)
  // corner_[i]: the speed cap of the junction between prep_[i] and prep_[i + 1] from the
  // geometry alone (0: it does not flow), computed once when prep_[i + 1] is prepared.
  std::array<double, kRingSlots> corner_{};
  // turn_[i]: how the share of a cycle's acceleration junction i's turn takes grows with the
  // speed it is crossed at (junction.hpp TurnShare: a velocity step, or a corner window's turn;
  // the whole fraction f_ next to a rotary block); crossed_share_: the junction crossed last's,
  // at the speed it was crossed at
  std::array<TurnShare, kRingSlots> turn_{};
  double crossed_share_ = 0.0;
  // blend_[i]: the corner blend of junction i (on: its window replaces the sharp corner; its `at`
  // is the corner's position in path_base_'s coordinate); entered_: the junction crossed into the
  // block in execution, whose window may still reach into it
  std::array<CornerBlend, kRingSlots> blend_{};
  CornerBlend entered_{};
  double path_base_ = 0.0;  // path length run before the block in execution (since set_position)
  bool blended_ = false;
  // exit_speed_of_current() depends only on the prepared blocks and the input: it is kept
  // until a block is prepared or popped, or the hold or the override changes.
  bool exit_valid_ = false;
  bool exit_hold_ = false;
  double exit_override_ = 0.0;
  double exit_speed_ = 0.0;
  PreparedBlock prev_{};  // the motion block finished last
  bool has_prev_ = false;
  std::size_t prepared_ = 0;
  std::uint64_t expected_seq_ = 1;
  Vec3 tail_{};  // where the last validated block ends

  double s_ = 0.0;       // progress in the current block, mm
  double v_ = 0.0;       // path speed of the last cycle, mm/s
  double dwell_ = 0.0;   // time spent in the current dwell, s
  int crossed_ = 0;      // cycles left with reduced acceleration after a flowing junction
  bool rest_cycle_ = false;     // hold one cycle at rest after landing at a stop
  bool ended_at_rest_ = false;  // the last motion block ended stopped (junction counting)
  bool after_motion_ = false;   // the last finished block was a motion
  bool fresh_ = true;           // the current block has not moved yet
  StartGap gap_{};              // the gap move before it (start_gap.hpp)

  // NURBS block in execution: curve parameter, curve there, schedule search hint
  double nurbs_u_ = 0.0;
  NurbsEval nurbs_at_{};
  int nurbs_hint_ = 0;
  int nurbs_span_ = 0;  // knot-span hint of its evaluations
  BrakeCapacity nurbs_brake_{};
  Vec3 tangent_{}, curvature_{};
  // A line or arc in execution: the block's own path at s_ as advance() evaluated it (the next
  // cycle's arc ramp starts there); valid until the block or s_ changes.
  PathPoint here_{};
  double here_s_ = 0.0;
  bool here_valid_ = false;

  // ruled block in execution: the follower, and what a flowing join hands to the next block
  RuledFollower ruled_{};
  double ruled_carry_ = 0.0;  // mm left over past the previous ruled block's end
  double ruled_speed_ = 0.0;  // the tip speed it ended with (0: from rest)

  // probing block in execution (docs/probe.md)
  bool probe_tripped_ = false;  // the input reached the state sought: braking
  Vec3 probe_latched_{};        // the position sensed in the cycle it did
  bool probe_arm_ = false;
  Vec3 probe_dir_{};
  bool probe_sync_ = false;     // the last block was a probing one and nothing follows yet

  Vec3 pos_{}, vel_{}, acc_{};
  // rotary joints (rad) and the tail the next block must continue from; TCP: the kinematics,
  // the joints' travel for the inverse's choice, the tool axis's arc of the block in execution,
  // and last cycle's linear joints (with rot_, the inverse's seed)
  Rot3 rot_{}, rot_vel_{}, rot_acc_{};
  Rot3 rot_tail_{};
  Kinematics kin_{};
  RotaryTravel travel_{};
  AxisSlerp slerp_{};
  Vec3 last_pos_{};
  std::uint32_t line_ = 0;
  std::uint64_t seq_ = 0;
  bool contouring_ = false;
};

}  // namespace pcnc
