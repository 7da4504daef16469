// cusp.hpp — the path interval between neighbouring passes of a ball-end mill for a given
// cusp (scallop) height, the seed paper's eq. (1): P = 2 sqrt(h (2R - h)), the chord of the
// ball's circle of radius R at depth h. Exact on a plane; the seed applies it to the part
// surface as it is. Pure.
#pragma once

#include <cmath>
#include <limits>

namespace pcnc {

/// P(h, R) in mm for cusp height 0 <= h <= R and ball radius R > 0; NaN otherwise.
inline double pass_interval(double cusp_height, double tool_radius) {
  const double h = cusp_height, r = tool_radius;
  if (!(r > 0.0) || !(h >= 0.0) || h > r) return std::numeric_limits<double>::quiet_NaN();
  return 2.0 * std::sqrt(h * (2.0 * r - h));
}

/// The inverse: the cusp height left by passes P apart, h = R - sqrt(R^2 - P^2/4), for
/// 0 <= P <= 2R; NaN otherwise.
inline double cusp_height(double interval, double tool_radius) {
  const double p = interval, r = tool_radius;
  if (!(r > 0.0) || !(p >= 0.0) || p > 2.0 * r) return std::numeric_limits<double>::quiet_NaN();
  return r - std::sqrt(r * r - 0.25 * p * p);
}

}  // namespace pcnc
