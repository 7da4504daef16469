// start_gap.hpp — closing the small gap between where the machine stands and where a block
// that starts from rest begins.
//
// pcnc-rt accepts a block whose start lies within motion.block_tolerance_mm of where the last
// one ended (ipc/block_check). The host's blocks chain exactly, but a program resumed after a
// lost host (docs/reliability.md, "Resume inside any block") may begin a hair away: the block the
// machine stood at the end of is skipped and the next one starts at that end (up to half the
// block tolerance away), a NURBS block cut where the machine stands starts at the curve's point
// nearest to it, and a machine held inside a corner blend's window stands off the blocks' own
// path. Jumping the gap in one cycle would step the setpoint: 0.2 µm in one 0.5 ms cycle is
// 800 mm/s² on top of the block's own ramp (the soak saw 1.4 × Y's limit). The executor instead
// moves the gap first, in a straight line from rest to rest, each axis within its velocity and
// acceleration limits, by the same discrete law that lands a block at a stop (junction.hpp
// stop_speed_exact): a few cycles for a micron.
#pragma once

#include "config/config.hpp"
#include "geometry/vec3.hpp"

namespace pcnc {

/// Gaps up to this long are jumped (a 1 nm step is 4 mm/s² at 2 kHz): the blocks of one
/// program chain within rounding, so a program that never resumes never takes a gap move.
constexpr double kStartGapMm = 1e-6;

class StartGap {
 public:
  /// Starts the move from `from` to `to` (at rest at both ends) with the axes' limits in
  /// `config` and the cycle `dt`.
  void begin(const Vec3& from, const Vec3& to, const MachineConfig& config, double dt);
  /// One cycle; returns true on the cycle that lands on `to` (the move is then over).
  bool step();
  bool active() const { return active_; }
  void clear() { active_ = false; }

  const Vec3& position() const { return pos_; }
  const Vec3& velocity() const { return vel_; }
  const Vec3& acceleration() const { return acc_; }
  double speed() const { return v_; }

 private:
  bool active_ = false;
  Vec3 from_{}, to_{}, dir_{};
  double length_ = 0.0, s_ = 0.0, v_ = 0.0;
  double accel_ = 0.0, vmax_ = 0.0, dt_ = 0.0;
  Vec3 pos_{}, vel_{}, acc_{};
};

}  // namespace pcnc
