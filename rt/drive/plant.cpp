// plant.cpp — closed-form integration of m·dv/dt = F − b·v under constant force F, with
// Coulomb friction and stiction handled exactly at velocity zero crossings.
//
// Units: x in mm, v in mm/s, F in N, m in kg, b in N·s/m. Then dv/dt = 1000·F/m − (b/m)·v.
#include "drive/plant.hpp"

#include <algorithm>
#include <cmath>

namespace pcnc {

AxisPlant::AxisPlant(const AxisConfig& c, double cycle_s, int substeps, double position_mm)
    : mass_kg_(c.moving_mass_kg),
      kf_(c.force_constant_n_per_a),
      imax_(c.current_limit_a),
      b_(c.viscous_friction_n_s_per_m),
      fc_(c.coulomb_friction_n),
      fg_(c.gravity_load_n),
      res_(c.encoder_resolution_mm),
      h_(cycle_s / std::max(1, substeps)),
      substeps_(std::max(1, substeps)),
      x_(position_mm) {
  accel_per_n_ = 1000.0 / mass_kg_;
  lambda_ = b_ / mass_kg_;
  e_h_ = std::exp(-lambda_ * h_);
}

double AxisPlant::encoder() const {
  if (res_ <= 0.0) return x_;
  return std::nearbyint(x_ / res_) * res_;
}

// Exact solution over h for constant net force `force_n` (viscous part included in the ODE).
void AxisPlant::advance(double force_n, double h) {
  const double a_force = accel_per_n_ * force_n;  // mm/s² from the force
  const double lambda = lambda_;
  if (lambda * h < 1e-12) {
    x_ += v_ * h + 0.5 * a_force * h * h;
    v_ += a_force * h;
    return;
  }
  const double v_inf = a_force / lambda;
  const double e = h == h_ ? e_h_ : std::exp(-lambda * h);
  x_ += v_inf * h + (v_ - v_inf) * (1.0 - e) / lambda;
  v_ = v_inf + (v_ - v_inf) * e;
}

// One sub-step: at rest, stiction holds unless the drive force beats Coulomb friction;
// moving, friction opposes the velocity until the velocity reaches zero, where the
// sub-step is split and the rest is re-decided from rest.
void AxisPlant::substep(double drive_n, double h) {
  if (v_ == 0.0) {
    if (std::abs(drive_n) <= fc_) return;  // stuck
    advance(drive_n - std::copysign(fc_, drive_n), h);
    return;
  }
  const double friction = -std::copysign(fc_, v_);
  const double f = drive_n + friction;
  // Would the velocity cross zero within h? Find the crossing time in closed form.
  const double a_force = accel_per_n_ * f;
  const double lambda = lambda_;
  double t_zero = -1.0;
  if (lambda * h < 1e-12) {
    if (a_force != 0.0 && (v_ > 0.0) != (a_force > 0.0)) t_zero = -v_ / a_force;
  } else {
    const double v_inf = a_force / lambda;
    if ((v_ > 0.0 && v_inf < 0.0) || (v_ < 0.0 && v_inf > 0.0)) {
      // v(t) = v_inf + (v0 - v_inf) e^{-λt} runs monotonically toward v_inf: it crosses zero
      // within h only if v(h) has left v0's sign; then the crossing is at
      // t = ln((v0 - v_inf)/(-v_inf))/λ.
      const double e = h == h_ ? e_h_ : std::exp(-lambda * h);
      const double v_h = v_inf + (v_ - v_inf) * e;
      if ((v_ > 0.0) ? v_h <= 0.0 : v_h >= 0.0) t_zero = std::log((v_ - v_inf) / (-v_inf)) / lambda;
    }
  }
  if (t_zero >= 0.0 && t_zero < h) {
    advance(f, t_zero);
    v_ = 0.0;
    substep(drive_n, h - t_zero);  // from rest: stick or move off the other way
    return;
  }
  advance(f, h);
}

void AxisPlant::step(double current_a, bool amplifier_on) {
  i_ = amplifier_on ? std::clamp(current_a, -imax_, imax_) : 0.0;
  if (blocked_ || (!amplifier_on && fg_ != 0.0)) {
    v_ = 0.0;  // jammed, or the vertical axis's brake holds it
    return;
  }
  const double drive = kf_ * i_ - fg_;
  for (int k = 0; k < substeps_; ++k) substep(drive, h_);
}

}  // namespace pcnc
