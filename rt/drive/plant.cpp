// plant.cpp — closed-form integration of m·dv/dt = F − b·v under constant force F, with
// Coulomb friction and stiction handled exactly at velocity zero crossings.
//
// Units: linear x in mm, v in mm/s, F in N, m in kg, b in N·s/m: dv/dt = 1000·F/m − (b/m)·v.
// Rotary x in rad, v in rad/s, F a torque in N·m, m = J in kg·m², b in N·m·s/rad:
// dv/dt = F/J − (b/J)·v. The same equation with units_per_si 1000 or 1.
#include "drive/plant.hpp"

#include <algorithm>
#include <cmath>

namespace pcnc {

PlantModel plant_model(const AxisConfig& a) {
  PlantModel m;
  m.inertia = a.moving_mass_kg;
  m.gain_per_a = a.force_constant_n_per_a;
  m.current_limit_a = a.current_limit_a;
  m.viscous = a.viscous_friction_n_s_per_m;
  m.coulomb = a.coulomb_friction_n;
  m.load = a.gravity_load_n;
  m.encoder_resolution = a.encoder_resolution_mm;
  m.units_per_si = 1000.0;  // mm per m
  return m;
}

PlantModel plant_model(const RotaryAxisConfig& j) {
  PlantModel m;
  m.inertia = j.inertia_kg_m2;
  m.gain_per_a = j.torque_constant_nm_per_a;
  m.current_limit_a = j.current_limit_a;
  m.viscous = j.viscous_friction_nm_s_per_rad;
  m.coulomb = j.coulomb_friction_nm;
  m.load = 0.0;  // a balanced cradle and a horizontal table: no gravity torque
  m.encoder_resolution = j.encoder_resolution_rad;
  m.units_per_si = 1.0;  // rad
  return m;
}

AxisPlant::AxisPlant(const PlantModel& m, double cycle_s, int substeps, double position)
    : mass_kg_(m.inertia),
      kf_(m.gain_per_a),
      imax_(m.current_limit_a),
      b_(m.viscous),
      fc_(m.coulomb),
      fg_(m.load),
      res_(m.encoder_resolution),
      h_(cycle_s / std::max(1, substeps)),
      substeps_(std::max(1, substeps)),
      x_(position) {
  accel_per_n_ = m.units_per_si / mass_kg_;
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
