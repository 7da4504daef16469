// junction.cpp — the look-ahead speed rules (see junction.hpp).
#include "motion/junction.hpp"

#include <cmath>
#include <limits>

#include "geometry/axis_caps.hpp"

namespace pcnc {

double stop_speed(double distance_mm, double v_end_mm_s, double a, double dt, double k) {
  const double d = distance_mm > 0.0 ? distance_mm : 0.0;
  // v²/(2a) + k·dt·v − (d + v_end²/(2a)) = 0, positive root.
  const double kd = k * dt * a;
  const double disc = kd * kd + 2.0 * a * d + v_end_mm_s * v_end_mm_s;
  const double v = std::sqrt(disc) - kd;
  return v > 0.0 ? v : 0.0;
}

double stop_speed_exact(double distance_mm, double a, double dt) {
  if (!(distance_mm > 0.0) || !(a > 0.0) || !(dt > 0.0)) return 0.0;
  // Braking from v = (n + φ)·a·dt one a·dt per cycle, moving v·dt in this cycle and each
  // one after, covers (n + 1)(n/2 + φ)·a·dt² before the speed reaches φ·a·dt < a·dt, and the
  // last cycle lands (executor.cpp). Solve (n + 1)(n/2 + φ) = q for n (integer) and φ ∈ [0, 1).
  const double q = distance_mm / (a * dt * dt);
  double n = std::floor(0.5 * (std::sqrt(8.0 * q + 1.0) - 1.0));
  if (n < 0.0) n = 0.0;
  if ((n + 1.0) * (n + 2.0) * 0.5 <= q) n += 1.0;      // rounding of the square root
  if (n > 0.0 && n * (n + 1.0) * 0.5 > q) n -= 1.0;
  double phi = q / (n + 1.0) - 0.5 * n;
  phi = phi < 0.0 ? 0.0 : (phi > 1.0 ? 1.0 : phi);
  return (n + phi) * a * dt;
}

double entry_speed(double length_mm, double v_exit_mm_s, double a) {
  return std::sqrt(v_exit_mm_s * v_exit_mm_s + 2.0 * a * (length_mm > 0.0 ? length_mm : 0.0));
}

bool junction_flows(bool contouring, const Vec3& dir_end, const Vec3& dir_start, double cos_limit) {
  if (!contouring) return false;
  // strictly under the contouring angle: cos(turn) > cos(limit)
  return dot(dir_end, dir_start) > cos_limit;
}

double junction_speed_cap(const Vec3& dir_end, const Vec3& dir_start, const std::array<double, kAxes>& axis_accel,
                          double dt, double fraction) {
  // the velocity step each axis may take in one cycle
  AxisLimits step{};
  for (int i = 0; i < kAxes; ++i) step[i] = fraction * axis_accel[i] * dt;
  return axis_cap(dir_start - dir_end, step);
}

TurnShare turn_share(const Vec3& dir_end, const Vec3& dir_start, const std::array<double, kAxes>& axis_accel, double dt,
                     double window_half) {
  const double worst = 1.0 / axis_cap(dir_start - dir_end, axis_accel);  // max_i |Δu_i| / a_i (0 if tangent)
  if (window_half > 0.0) return {1.5 * worst / (2.0 * window_half), 2};
  return {worst / dt, 1};
}

double turn_share_at(const TurnShare& share, double v, double fraction) {
  if (share.power == 0) return fraction;
  const double s = share.coef * (share.power == 2 ? v * v : v);
  return s < fraction ? s : fraction;
}

double joint_junction_speed(const JointRate& rate_end, const JointRate& curv_end, const JointRate& rate_start,
                            const JointRate& curv_start, const JointRate& joint_accel, double dt, double fraction) {
  double v = std::numeric_limits<double>::infinity();
  for (int j = 0; j < kMachineJoints; ++j) {
    const auto k = static_cast<std::size_t>(j);
    const double step = std::fabs(rate_start[k] - rate_end[k]);
    const double curv = std::fmax(std::fabs(curv_end[k]), std::fabs(curv_start[k]));
    const double budget = fraction * joint_accel[k] * dt;  // the velocity step allowed at rest
    if (!(step > 0.0) && !(curv > 0.0)) continue;
    if (!(budget > 0.0)) return 0.0;
    // fraction·curv·dt·v² + step·v − budget = 0, positive root (the stable form)
    const double c = fraction * curv * dt;
    v = std::fmin(v, 2.0 * budget / (step + std::sqrt(step * step + 4.0 * c * budget)));
  }
  return v;
}

double corner_speed(bool contouring, const Vec3& dir_end, const Vec3& dir_start, const JunctionRules& r) {
  if (!contouring) return 0.0;
  double cap = 0.0;
  if (junction_flows(contouring, dir_end, dir_start, r.cos_limit)) {
    cap = junction_speed_cap(dir_end, dir_start, r.axis_accel, r.dt, r.step_fraction);
  }
  if (r.path_tolerance_mm > 0.0) {
    cap = std::fmax(cap, junction_deviation_speed(dir_end, dir_start, r.axis_accel, r.path_tolerance_mm));
  }
  return cap;
}

}  // namespace pcnc
