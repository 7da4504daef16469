// rotary_config.hpp — the config of a rotary joint (A, B or C): travel or continuous, motion
// limits, the simulated direct drive (rotary inertia, torque constant, friction, encoder) and
// its servo gains. The TOML keys are in degrees ([axis.a] travel_min_deg, kp_a_per_deg, ...,
// docs/configuration.md); these values are in radians, converted once when the file is read,
// so the kinematics (geometry/kinematics.hpp), the plant and the servo (rt/drive) never see a
// degree. Part of MachineConfig (config.hpp).
#pragma once

#include <numbers>

namespace pcnc {

constexpr double kRadPerDeg = std::numbers::pi / 180.0;
constexpr double kDegPerRad = 180.0 / std::numbers::pi;

/// Rotary joints by letter: index 0 A (about X), 1 B (about Y), 2 C (about Z).
constexpr int kRotaryAxes = 3;

struct RotaryAxisConfig {
  char letter = 'A';
  // travel and limits (rad, rad/s, rad/s^2); a continuous axis has no travel limits
  bool continuous = false;
  double travel_min_rad = 0.0;
  double travel_max_rad = 0.0;
  double home_rad = 0.0;  // where the joint stands when pcnc-rt starts (inside the travel)
  double max_velocity_rad_s = 1.0;
  double max_accel_rad_s2 = 10.0;
  double following_error_limit_rad = 0.01;

  // simulated direct drive (plant): J·dω/dt = Kt·i − b·ω − Tc·sign(ω)
  double inertia_kg_m2 = 1e-3;
  double torque_constant_nm_per_a = 1.0;
  double current_limit_a = 5.0;
  double viscous_friction_nm_s_per_rad = 0.0;
  double coulomb_friction_nm = 0.0;
  double encoder_resolution_rad = 0.0;

  // servo (PID on the angle error, output = amplifier current in A), per radian
  double kp_a_per_rad = 0.0;
  double ki_a_per_rad_s = 0.0;
  double kd_a_s_per_rad = 0.0;
  double derivative_filter_hz = 500.0;
  double velocity_ff_a_s_per_rad = 0.0;
  double accel_ff_a_s2_per_rad = 0.0;
  double friction_ff_a = 0.0;
  double integrator_limit_a = 1.0;
};

}  // namespace pcnc
