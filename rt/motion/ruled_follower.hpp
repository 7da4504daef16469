// ruled_follower.hpp — real-time interpolation of a ruled-surface piece (issue 17, pcnc-rt,
// every 500 µs cycle): the tool's pose and its first- and second-order motion from the
// curvature theory (geometry/ruled_motion.hpp), then the joints and their velocity and
// acceleration feed-forward through the inverse kinematics and the Jacobian
// (geometry/kinematics.hpp, kinematics_rates.hpp).
//
// Each cycle of period T the follower picks the tip's speed along the directrix: the piece's
// feed schedule at the current parameter, reached at the piece's acceleration, never more than
// what still slows to the end speed within the remaining length (as NurbsFollower does). With
// the speed F at the cycle's start and F+ at its end, the tip travels (F + F+)/2 T: the
// parameter advances by the second-order Taylor step u' T + u'' T^2/2 with u' = F/|c_u|,
// u'' = (dF/dt - (c_u . c_uu/|c_u|) u'^2)/|c_u|, dF/dt = (F+ - F)/T, and Newton steps on the
// chord correct it (advance_parameter), so the chord per cycle is the programmed feed's to
// far better than 0.1 %. The last cycle ends exactly at the piece's end (u = segment_count)
// and never beyond it.
//
// At the new parameter the sample holds the pose (tip, axis), v, a, omega, alpha, the axis's
// own rates dA/dt and d2A/dt2 (all analytic), and the joints q (the inverse solution nearest
// the last cycle's), dq/dt and d2q/dt2 (the Jacobian applied to v, dA/dt and to a, d2A/dt2):
// the PIDs' position command and their velocity and acceleration feed-forward.
// Trivially copyable state, no allocation, no I/O, bounded time (at most six directrix
// evaluations: the Taylor step and up to three Newton corrections, one ruled jet, one inverse).
#pragma once

#include "geometry/kinematics.hpp"
#include "geometry/ruled_motion.hpp"
#include "ipc/block_ruled.hpp"

namespace pcnc {

/// One cycle's output.
struct RuledSample {
  double u = 0.0;
  double feed = 0.0;        // tip speed along the directrix at the sample, mm/s
  double dfeed = 0.0;       // its rate over the last cycle, mm/s^2
  double target = 0.0;      // length the last cycle was to travel, mm
  double chord = 0.0;       // length it travelled (chord), mm
  ToolMotion motion{};      // pose, frame, v, a, omega, alpha, dA/dt, d2A/dt2 at u
  Joints q{};               // joints (mm, rad)
  Joints dq{};              // joint velocity feed-forward (mm/s, rad/s)
  Joints ddq{};             // joint acceleration feed-forward (mm/s^2, rad/s^2)
  /// (chord - target)/target of the last cycle; 0 on the last, shortened, cycle of the piece.
  double feed_error() const { return target > 0.0 && !last ? (chord - target) / target : 0.0; }
  bool last = false;        // this cycle reached the piece's end
};

/// The schedule's speed cap at u (linear between points, constant beyond the ends). `hint`
/// is kept by the caller so that a monotone walk costs O(1); start it at 0.
double ruled_schedule_speed(const RuledGeometry& g, double u, int& hint);

/// The pose, its motion and the joints at u for tip speed `feed` changing at `dfeed`, with
/// the inverse solution nearest `previous` within `travel`. Pure: what each cycle calls.
RuledSample ruled_sample_at(const RuledGeometry& g, const Kinematics& kin, const RotaryTravel& travel,
                            const Joints& previous, double u, double feed, double dfeed);

class RuledFollower {
 public:
  /// Starts at u = 0 with the piece's start speed; `q_now` are the joints where the machine
  /// stands (for the choice among inverse solutions). `carry` (mm) is the length the cycle
  /// that ended the piece before still had to travel (its leftover()): the piece starts that
  /// far along its directrix, so a run of pieces keeps the feed across their joins.
  /// `speed` (mm/s): the tip speed it starts with; negative: the piece's start_speed (the
  /// executor passes the speed the cycle before ran at, 0 from rest).
  void start(const RuledGeometry& g, const Kinematics& kin, const RotaryTravel& travel, const Joints& q_now,
             double carry = 0.0, double speed = -1.0);

  /// One cycle of period T (s). After the end, done() is true and the sample stays there.
  const RuledSample& step(const RuledGeometry& g, double period_s) { return step(g, period_s, g.end_speed, 1.0); }
  /// The same with the end speed the executor allows this cycle (0 when nothing flows on from
  /// the piece's end; never above g.end_speed) and `scale` times the schedule (the feed
  /// override, at most 1; 0 is a feed hold: the speed ramps down at the piece's acceleration
  /// and the parameter stands still at rest, without the floor that otherwise keeps it moving).
  const RuledSample& step(const RuledGeometry& g, double period_s, double end_speed, double scale);

  bool done() const { return done_; }
  double travelled() const { return s_; }  // sum of the chords so far, mm
  /// What the last cycle still had to travel beyond the piece's end (mm): 0 before the end.
  double leftover() const { return leftover_; }
  const RuledSample& sample() const { return sample_; }

 private:
  Kinematics kin_{};
  RotaryTravel travel_{};
  RuledSample sample_{};
  double s_ = 0.0;
  double top_speed_ = 0.0;  // the schedule's largest speed
  double leftover_ = 0.0;
  int hint_ = 0;
  bool done_ = false;
};

}  // namespace pcnc
