// servo_pid.hpp — one axis's position loop: PID on the following error with velocity and
// acceleration feed-forward, a first-order filtered derivative, integrator anti-windup
// (clamp plus conditional integration) and output saturation at the amplifier's current
// limit. Output is the current asked of the amplifier, A. Gains come from the config, per mm
// for a linear axis and per rad for a rotary joint (PidGains): the same loop for both.
#pragma once

#include "config/config.hpp"

namespace pcnc {

/// The loop's gains in the axis's position unit u (mm or rad): kp A/u, ki A/(u·s), kd A·s/u,
/// kvff A·s/u, kaff A·s²/u; friction feed-forward, integrator limit and current limit in A.
struct PidGains {
  double kp = 0.0, ki = 0.0, kd = 0.0;
  double derivative_filter_hz = 500.0;
  double kvff = 0.0, kaff = 0.0, kfric = 0.0;
  double integrator_limit_a = 1.0;
  double current_limit_a = 1.0;
};

/// The gains of a linear axis (per mm) and of a rotary joint (per rad) from the config.
PidGains pid_gains(const AxisConfig& axis);
PidGains pid_gains(const RotaryAxisConfig& joint);

class AxisPid {
 public:
  AxisPid(const PidGains& gains, double cycle_s);
  AxisPid(const AxisConfig& config, double cycle_s) : AxisPid(pid_gains(config), cycle_s) {}

  /// Clears the loop's memory; the integrator starts at `integral_a` (e.g. the current that
  /// holds a gravity load, so the axis does not sag when the amplifier comes on).
  void reset(double integral_a = 0.0);

  /// One servo period. `command_mm`: setpoint; `measured_mm`: encoder; feed-forward from the
  /// setpoint's velocity (mm/s) and acceleration (mm/s²). Returns the saturated current.
  /// A rotary joint: the same in rad, rad/s, rad/s².
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
