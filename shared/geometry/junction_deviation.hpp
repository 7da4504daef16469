// junction_deviation.hpp — the junction-deviation speed (grbl, Klipper) as one pure function:
// the rt's look-ahead passes real corners at it (rt/motion/junction.hpp corner_speed) and the
// ideal planner that issue 14 measures machine time against uses it at every junction
// (host/report/ideal_planner.hpp).
#pragma once

#include <cmath>
#include <limits>

#include "geometry/axis_caps.hpp"
#include "geometry/vec3.hpp"

namespace pcnc {

/// Junction-deviation speed: the speed at which a virtual arc tangent to both directions,
/// passing within `tolerance_mm` of the corner, would be run at the acceleration the axes
/// allow along the direction of the velocity change:
///   R = δ·sin(θ/2)/(1 − sin(θ/2)),  θ the angle between −dir_end and dir_start,
///   a_j = min_i a_i/|u_i|,  u = normalized(dir_start − dir_end),  v = sqrt(a_j·R).
/// +infinity for a straight junction, 0 for a reversal or a tolerance of 0.
inline double junction_deviation_speed(const Vec3& dir_end, const Vec3& dir_start, const AxisLimits& axis_accel,
                                       double tolerance_mm) {
  if (!(tolerance_mm > 0.0)) return 0.0;
  const double cos_theta = -dot(dir_end, dir_start);  // θ: the angle the corner encloses
  if (cos_theta <= -1.0 + 1e-12) return std::numeric_limits<double>::infinity();  // straight on
  if (cos_theta >= 1.0 - 1e-12) return 0.0;                                        // reversal
  const double sin_half = std::sqrt(0.5 * (1.0 - cos_theta));
  const double radius = tolerance_mm * sin_half / (1.0 - sin_half);
  const Vec3 change = dir_start - dir_end;
  const double n = norm(change);
  const double a = axis_cap({change[0] / n, change[1] / n, change[2] / n}, axis_accel);
  return std::sqrt(a * radius);
}

}  // namespace pcnc
