// jog.hpp — manual axis moves (kJogIncrement, kJogContinuous with deadman keep-alives,
// kJogStop): one axis at a time along a straight line, with the same stop-within-distance
// speed law as program blocks (junction.hpp), at jog_accel_fraction of the axis's
// acceleration and at most its maximum velocity. Targets are clamped to the soft limits, so
// a jog never commands a position outside the travel; a continuous jog heads for the travel
// end and stops when keep-alives stop arriving (process.jog_deadman_s). Axes 3, 4, 5 are the
// rotary joints A, B, C the machine declares (rad, rad/s; a continuous joint has no end).
#pragma once

#include "config/config.hpp"
#include "ipc/rotary_joints.hpp"

namespace pcnc {

class Jog {
 public:
  explicit Jog(const MachineConfig& config);

  /// Starts (or redirects, on the same axis) an incremental jog. Returns false when refused
  /// (bad axis, non-finite or non-positive feed, another axis is moving).
  bool start_increment(const Vec3& from, int axis, double distance_mm, double feed_mm_s);
  bool start_continuous(const Vec3& from, int axis, double direction, double feed_mm_s);
  void keep_alive() { since_keepalive_ = 0.0; }
  void stop() { stopping_ = true; }
  /// Abandons the jog at once (amplifiers off).
  void cancel() {
    active_ = false;
    v_ = 0.0;
    a_ = 0.0;
  }

  /// One cycle. Returns true while moving; at rest it becomes inactive.
  bool step();

  bool active() const { return active_; }
  const Vec3& position() const { return pos_; }
  /// The rotary joints (rad): where they stand, set_rotary() while no jog is active.
  const Rot3& rotary() const { return rot_; }
  void set_rotary(const Rot3& r) {
    if (!active_) rot_ = r;
  }
  Rot3 rotary_velocity() const;
  Rot3 rotary_acceleration() const;
  Vec3 velocity() const;
  Vec3 acceleration() const;
  double speed() const { return v_ < 0.0 ? -v_ : v_; }

 private:
  struct Limits {
    double min, max, vmax, amax;
  };
  bool begin(const Vec3& from, int axis, double target, double feed_mm_s);
  bool valid_axis(int axis) const;
  Limits limits(int axis) const;
  double& coord(int axis);

  MachineConfig cfg_;
  double dt_;
  bool active_ = false, continuous_ = false, stopping_ = false;
  int axis_ = 0;
  double target_ = 0.0, feed_ = 0.0, accel_ = 0.0;
  double v_ = 0.0, a_ = 0.0;  // signed axis speed and acceleration of the last cycle
  double since_keepalive_ = 0.0;
  Vec3 pos_{};
  Rot3 rot_{};
};

}  // namespace pcnc
