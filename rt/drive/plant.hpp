// plant.hpp — the simulated desktop mill, one linear axis at a time (DESIGN.md "The simulated
// mill"): a moving mass driven by a current-controlled motor (force constant, amplifier
// current limit), viscous and Coulomb friction, a constant gravity load, and a linear-scale
// encoder with finite resolution. The servo's current is held over the cycle (zero-order
// hold) and the motion in between is integrated in closed form, so the only approximation is
// the cycle's ZOH itself: sub-steps exist only to re-evaluate Coulomb friction and stiction.
#pragma once

#include "config/config.hpp"

namespace pcnc {

class AxisPlant {
 public:
  /// `cycle_s`: servo period; `substeps`: pieces the period is integrated in (>= 1).
  AxisPlant(const AxisConfig& config, double cycle_s, int substeps, double position_mm);

  /// Advances one servo period with the amplifier asked for `current_a` (clamped to the
  /// current limit). With the amplifier off the motor gives no force; an axis with a gravity
  /// load then holds on its brake (a vertical axis never drops on a fault).
  void step(double current_a, bool amplifier_on);

  double position() const { return x_; }   // true position, mm
  double velocity() const { return v_; }   // mm/s
  double encoder() const;                  // quantized position the servo reads, mm
  double applied_current() const { return i_; }  // after saturation, A

  /// Fault injection for tests: a blocked axis (crash, jammed guide) does not move.
  void set_blocked(bool blocked) { blocked_ = blocked; }
  /// Places the axis at rest (start-up, tests).
  void place(double position_mm) { x_ = position_mm; v_ = 0.0; }

 private:
  void advance(double force_n, double h);           // closed-form, constant force, no crossing
  void substep(double drive_n, double h);           // friction logic around advance()

  double mass_kg_, kf_, imax_, b_, fc_, fg_, res_;
  double h_;       // sub-step, s
  double e_h_;     // exp(-b/m·h), precomputed for whole sub-steps
  double accel_per_n_;  // 1000/m: mm/s² per newton
  double lambda_;       // b/m, 1/s
  int substeps_;
  double x_ = 0.0, v_ = 0.0, i_ = 0.0;
  bool blocked_ = false;
};

}  // namespace pcnc
