// servo_pid.hpp — one axis's position loop: PID on the following error with velocity and
// acceleration feed-forward, a first-order filtered derivative, integrator anti-windup
// (clamp plus conditional integration) and output saturation at the amplifier's current
// limit. Output is the current asked of the amplifier, A. Gains come from the config.
#pragma once

#include "config/config.hpp"

namespace pcnc {

class AxisPid {
 public:
  AxisPid(const AxisConfig& config, double cycle_s);

  /// Clears the loop's memory; the integrator starts at `integral_a` (e.g. the current that
  /// holds a gravity load, so the axis does not sag when the amplifier comes on).
  void reset(double integral_a = 0.0);

  /// One servo period. `command_mm`: setpoint; `measured_mm`: encoder; feed-forward from the
  /// setpoint's velocity (mm/s) and acceleration (mm/s²). Returns the saturated current.
  double update(double command_mm, double measured_mm, double velocity_mm_s, double accel_mm_s2);

  double integral() const { return integral_; }
  bool saturated() const { return saturated_; }

 private:
  double kp_, ki_, kd_, kvff_, kaff_, kfric_, ilim_, imax_, dt_, alpha_;
  double integral_ = 0.0;
  double derivative_ = 0.0;  // filtered d(error)/dt, mm/s
  double prev_error_ = 0.0;
  bool primed_ = false;
  bool saturated_ = false;
};

}  // namespace pcnc
