// servo_pid.cpp — the discrete PID step (see servo_pid.hpp; tuning in docs/servo-tuning.md).
#include "drive/servo_pid.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace pcnc {

PidGains pid_gains(const AxisConfig& a) {
  PidGains g;
  g.kp = a.kp_a_per_mm;
  g.ki = a.ki_a_per_mm_s;
  g.kd = a.kd_a_s_per_mm;
  g.derivative_filter_hz = a.derivative_filter_hz;
  g.kvff = a.velocity_ff_a_s_per_mm;
  g.kaff = a.accel_ff_a_s2_per_mm;
  g.kfric = a.friction_ff_a;
  g.integrator_limit_a = a.integrator_limit_a;
  g.current_limit_a = a.current_limit_a;
  return g;
}

PidGains pid_gains(const RotaryAxisConfig& j) {
  PidGains g;
  g.kp = j.kp_a_per_rad;
  g.ki = j.ki_a_per_rad_s;
  g.kd = j.kd_a_s_per_rad;
  g.derivative_filter_hz = j.derivative_filter_hz;
  g.kvff = j.velocity_ff_a_s_per_rad;
  g.kaff = j.accel_ff_a_s2_per_rad;
  g.kfric = j.friction_ff_a;
  g.integrator_limit_a = j.integrator_limit_a;
  g.current_limit_a = j.current_limit_a;
  return g;
}

AxisPid::AxisPid(const PidGains& g, double cycle_s)
    : kp_(g.kp),
      ki_(g.ki),
      kd_(g.kd),
      kvff_(g.kvff),
      kaff_(g.kaff),
      kfric_(g.kfric),
      ilim_(g.integrator_limit_a),
      imax_(g.current_limit_a),
      dt_(cycle_s) {
  // First-order low-pass on the derivative, corner derivative_filter_hz, exact discretisation.
  alpha_ = 1.0 - std::exp(-2.0 * std::numbers::pi * g.derivative_filter_hz * cycle_s);
}

void AxisPid::reset(double integral_a) {
  integral_ = std::clamp(integral_a, -ilim_, ilim_);
  derivative_ = 0.0;
  prev_error_ = 0.0;
  primed_ = false;
  saturated_ = false;
}

double AxisPid::update(double command_mm, double measured_mm, double velocity_mm_s, double accel_mm_s2) {
  const double e = command_mm - measured_mm;
  if (!primed_) {
    prev_error_ = e;
    primed_ = true;
  }
  derivative_ += alpha_ * ((e - prev_error_) / dt_ - derivative_);
  prev_error_ = e;

  const double friction = velocity_mm_s > 0.0 ? kfric_ : (velocity_mm_s < 0.0 ? -kfric_ : 0.0);
  const double ff = kvff_ * velocity_mm_s + kaff_ * accel_mm_s2 + friction;
  const double unsat_wo_i = kp_ * e + kd_ * derivative_ + ff;
  // Conditional integration: do not integrate further into a saturated output.
  const double candidate = std::clamp(integral_ + ki_ * e * dt_, -ilim_, ilim_);
  const double out_candidate = unsat_wo_i + candidate;
  const bool pushes_further = (out_candidate > imax_ && e > 0.0) || (out_candidate < -imax_ && e < 0.0);
  if (!pushes_further) integral_ = candidate;

  const double out = unsat_wo_i + integral_;
  saturated_ = std::abs(out) > imax_;
  return std::clamp(out, -imax_, imax_);
}

}  // namespace pcnc
