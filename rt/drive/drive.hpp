// drive.hpp — the drive: per axis the PID servo (servo_pid.hpp), the amplifier and the
// simulated axis with its encoder (plant.hpp), as one part the cycle steps once per period.
//
// Role in the rt: the cycle hands it a setpoint (position, velocity and acceleration for the
// feed-forward) and the encoder reading it took before; the drive runs one PID step per axis
// and advances the plant by one period. Allocation-free after construction. Includes only the
// config and the two drive parts: never loop/ or motion/.
#pragma once

#include <array>

#include "config/config.hpp"
#include "drive/plant.hpp"
#include "drive/servo_pid.hpp"
#include "ipc/rotary_joints.hpp"

namespace pcnc {

class Drive {
 public:
  /// The axes stand at their home positions, the servo integrators hold any gravity load.
  explicit Drive(const MachineConfig& config);

  /// The encoders: the quantised positions the servo reads, mm.
  Vec3 encoder() const { return {plant_[0].encoder(), plant_[1].encoder(), plant_[2].encoder()}; }
  /// The axes' true positions (not quantised), mm.
  Vec3 true_position() const { return {plant_[0].position(), plant_[1].position(), plant_[2].position()}; }

  /// The rotary joints' encoders and true angles (rad; joints the machine lacks read 0).
  Rot3 rotary_encoder() const;
  Rot3 rotary_true_position() const;
  RotaryMask rotary_mask() const { return mask_; }

  /// Clears the servo loops; the integrators start holding any gravity load, as a drive does
  /// when enabled (start-up, reset after a fault).
  void reset_servo();

  /// One servo period: PID on `command` against `measured` with velocity and acceleration
  /// feed-forward, then the plant. With the amplifiers off no current flows.
  void step(const Vec3& command, const Vec3& measured, const Vec3& velocity, const Vec3& accel, bool amps_on);
  /// The same for the rotary joints the machine declares (rad, rad/s, rad/s²).
  void step_rotary(const Rot3& command, const Rot3& measured, const Rot3& velocity, const Rot3& accel, bool amps_on);

  /// The axes stand at rest at `at` (mm; a restarted rt takes up the position its
  /// predecessor last measured) and the servo loops start afresh.
  void place(const Vec3& at);
  void place_rotary(const Rot3& at);

  /// Fault injection: the axis stops moving (a crash or a jammed guide).
  void set_blocked(int axis, bool blocked);

 private:
  std::array<double, kAxes> hold_a_{};  // current that holds each axis's gravity load, A
  std::array<AxisPid, kAxes> pid_;
  std::array<AxisPlant, kAxes> plant_;
  RotaryMask mask_ = 0;
  std::array<AxisPid, kRotaryJoints> rpid_;      // undeclared joints: never stepped
  std::array<AxisPlant, kRotaryJoints> rplant_;
};

}  // namespace pcnc
