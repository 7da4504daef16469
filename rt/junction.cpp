// junction.cpp — the look-ahead speed rules (see junction.hpp).
#include "junction.hpp"

#include <cmath>
#include <limits>

namespace pcnc {

double stop_speed(double distance_mm, double v_end_mm_s, double a, double dt, double k) {
  const double d = distance_mm > 0.0 ? distance_mm : 0.0;
  // v²/(2a) + k·dt·v − (d + v_end²/(2a)) = 0, positive root.
  const double kd = k * dt * a;
  const double disc = kd * kd + 2.0 * a * d + v_end_mm_s * v_end_mm_s;
  const double v = std::sqrt(disc) - kd;
  return v > 0.0 ? v : 0.0;
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
  double cap = std::numeric_limits<double>::infinity();
  for (int i = 0; i < kAxes; ++i) {
    const double jump = std::abs(dir_start[i] - dir_end[i]);
    if (jump > 1e-12) cap = std::fmin(cap, fraction * axis_accel[i] * dt / jump);
  }
  return cap;
}

}  // namespace pcnc
