// plant.hpp — the simulated machine, one axis at a time (DESIGN.md "The simulated mill"): an
// inertia driven by a current-controlled motor (force or torque constant, amplifier current
// limit), viscous and Coulomb friction, a constant load, and an encoder with finite resolution.
// One model for both axis kinds (PlantModel): a linear axis (mass, N/A, positions in mm) and a
// rotary joint (J·dω/dt = Kt·i − b·ω − Tc·sign(ω), positions in rad, a rotary encoder in rad).
// The servo's current is held over the cycle (zero-order hold) and the motion in between is
// integrated in closed form, so the only approximation is the cycle's ZOH itself: sub-steps
// exist only to re-evaluate Coulomb friction and stiction.
#pragma once

#include "config/config.hpp"

namespace pcnc {

/// One axis's plant in its own units: inertia·d²x/dt² = gain·i − viscous·ẋ − coulomb·sign(ẋ) −
/// load, with x in mm (linear: kg, N/A, N·s/m, N) or rad (rotary: kg·m², N·m/A, N·m·s/rad, N·m).
struct PlantModel {
  double inertia = 1.0;             // kg or kg·m²
  double gain_per_a = 1.0;          // force constant N/A or torque constant N·m/A
  double current_limit_a = 1.0;
  double viscous = 0.0;             // N·s/m or N·m·s/rad
  double coulomb = 0.0;             // N or N·m
  double load = 0.0;                // constant force or torque along −axis (Z's weight)
  double encoder_resolution = 0.0;  // mm or rad; 0: ideal
  double units_per_si = 1.0;        // position units per SI unit: 1000 (mm per m) or 1 (rad)
};

/// The plant of a linear axis (mm) and of a rotary joint (rad) from the config.
PlantModel plant_model(const AxisConfig& axis);
PlantModel plant_model(const RotaryAxisConfig& joint);

class AxisPlant {
 public:
  /// `cycle_s`: servo period; `substeps`: pieces the period is integrated in (>= 1);
  /// `position`: where it starts at rest (mm or rad).
  AxisPlant(const PlantModel& model, double cycle_s, int substeps, double position);
  /// A linear axis (the 3-axis mill's X, Y, Z).
  AxisPlant(const AxisConfig& config, double cycle_s, int substeps, double position_mm)
      : AxisPlant(plant_model(config), cycle_s, substeps, position_mm) {}

  /// Advances one servo period with the amplifier asked for `current_a` (clamped to the
  /// current limit). With the amplifier off the motor gives no force; an axis with a gravity
  /// load then holds on its brake (a vertical axis never drops on a fault).
  void step(double current_a, bool amplifier_on);

  double position() const { return x_; }   // true position, mm (rad)
  double velocity() const { return v_; }   // mm/s (rad/s)
  double encoder() const;                  // quantized position the servo reads, mm (rad)
  double applied_current() const { return i_; }  // after saturation, A

  /// Fault injection for tests: a blocked axis (crash, jammed guide) does not move.
  void set_blocked(bool blocked) { blocked_ = blocked; }
  /// Places the axis at rest (start-up, tests).
  void place(double position) { x_ = position; v_ = 0.0; }

 private:
  void advance(double force_n, double h);           // closed-form, constant force, no crossing
  void substep(double drive_n, double h);           // friction logic around advance()

  double mass_kg_, kf_, imax_, b_, fc_, fg_, res_;
  double h_;       // sub-step, s
  double e_h_;     // exp(-b/m·h), precomputed for whole sub-steps
  double accel_per_n_;  // units_per_si/inertia: mm/s² per N (1000/m), rad/s² per N·m (1/J)
  double lambda_;       // b/m, 1/s
  int substeps_;
  double x_ = 0.0, v_ = 0.0, i_ = 0.0;
  bool blocked_ = false;
};

}  // namespace pcnc
