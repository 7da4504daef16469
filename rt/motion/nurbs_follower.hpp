// nurbs_follower.hpp — real-time NURBS interpolation (pcnc-rt, every 500 µs cycle): the
// block's feed schedule read at a parameter, and the per-block speed follower.
//
// The parameter step itself (a chord of given length along the curve) is pure geometry:
// geometry/nurbs_step.hpp.
//
// NurbsFollower is the per-block state the rt executor keeps for a running NURBS block:
// each cycle it picks the path speed (the block's feed schedule at the current parameter,
// scaled by the feed override, never more than one cycle's acceleration above the last
// speed, and never more than what still allows reaching the required end speed within the
// remaining path), then steps the parameter by the trapezoid distance (v + v+)/2 T.
// Everything here is trivially copyable and allocation-free.
#pragma once

#include "ipc/block.hpp"
#include "ipc/block_nurbs.hpp"
#include "geometry/nurbs.hpp"
#include "geometry/nurbs_step.hpp"
#include "geometry/vec3.hpp"

namespace pcnc {

/// The block schedule's speed at u (linear between points). `hint` is a schedule index kept
/// by the caller between calls so that a monotone walk costs O(1); start it at 0.
double block_schedule_speed(const NurbsGeometry& g, double u, int& hint);

/// How much the block can still brake from arc length s (from its start) to its end: the
/// integral of the schedule's acceleration over that stretch (each interval between two points
/// at the smaller of their two), in mm²/s²: a speed v can be brought down to v_end over it
/// when v² <= v_end² + 2·capacity. Every speed up to the schedule may brake at these
/// accelerations (the block check verifies them against the axes).
double block_brake_capacity(const NurbsGeometry& g, double s);

/// block_brake_capacity along one block in execution, each cycle's answer the same bit for bit:
/// the schedule's whole intervals summed once at start() (from the end, as that function adds
/// them), so that a cycle adds only the part of the interval it is in, found from the last
/// one's (a walk along the block costs O(1) a cycle instead of O(intervals left)). A schedule
/// whose arc lengths do not rise (never sent by the host) is left to block_brake_capacity.
class BrakeCapacity {
 public:
  void start(const NurbsGeometry& g);
  double at(const NurbsGeometry& g, double s);

 private:
  double tail_[kMaxFeedSchedule + 1]{};  // tail_[i]: the whole intervals i .. n−1 (interval i: s[i−1] .. s[i])
  int interval_ = 0;                     // the last answer's interval (0: before the first point)
  bool rising_ = false;
};

/// The tangential acceleration the block schedule allows at u: the smaller of the two points
/// around u (the point itself at or beyond the ends). `hint` as for block_schedule_speed.
double block_schedule_accel(const NurbsGeometry& g, double u, int& hint);

class NurbsFollower {
 public:
  /// Starts at the beginning of the block's curve with path speed v_start (mm/s).
  void start(const Block& block, double v_start);

  /// One interpolation cycle of period T. `v_end` is the speed the block must end with
  /// (0 to stop at its end, the junction speed when the next block continues it);
  /// `feed_scale` is the feed override (0 holds the feed: the motion decelerates along the
  /// path and waits; values above 1 have no effect since the schedule sits at the machine's
  /// limits). Returns the new setpoint. After the end is reached, done() turns true and the
  /// setpoint stays at the block end.
  Vec3 step(const Block& block, double period_s, double v_end, double feed_scale);

  bool done() const { return done_; }
  double u() const { return u_; }
  double speed() const { return v_; }            // path speed of the last cycle, mm/s
  double travelled() const { return s_; }        // path length so far (sum of chords), mm
  double remaining() const { return length_ - s_ > 0.0 ? length_ - s_ : 0.0; }
  /// Path length by which the last cycle's step overshot the block end (to be carried into
  /// the next block in the same cycle); 0 before the end.
  double leftover() const { return leftover_; }
  const NurbsEval& at() const { return at_; }    // curve at u(): point, C', C''

 private:
  double u_ = 0.0;
  double s_ = 0.0;
  double v_ = 0.0;
  double length_ = 0.0;
  double leftover_ = 0.0;
  NurbsEval at_{};
  int hint_ = 0;
  bool done_ = false;
};

}  // namespace pcnc
