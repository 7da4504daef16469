// axis_caps.hpp — the one rule by which a path rate is capped so that no axis exceeds its own
// limit. When axis i moves at |share[i]| times the path speed (a unit tangent, a direction
// change, a curvature vector, ...), the path speed (or acceleration) may be at most
//   min over the moving axes of limit[i] / |share[i]|.
// The host's preprocessor and NURBS schedule plan blocks with it; the rt's executor
// re-derives the same caps from its own config (it trusts no block) and its junction rules
// use it for the velocity step and the corner acceleration. Pure; no config, no block.
#pragma once

#include <array>
#include <cmath>
#include <limits>

#include "geometry/vec3.hpp"

namespace pcnc {

/// One limit per axis (mm/s, mm/s², or any per-axis bound).
using AxisLimits = std::array<double, kAxes>;

/// An axis whose share is at most this does not count as moving.
constexpr double kAxisShareEps = 1e-12;

/// min over axes with |share[i]| > kAxisShareEps of limit[i] / |share[i]|; +infinity when
/// no axis moves.
inline double axis_cap(const Vec3& share, const AxisLimits& limit) {
  double cap = std::numeric_limits<double>::infinity();
  for (int i = 0; i < kAxes; ++i) {
    const double s = std::abs(share[i]);
    if (s > kAxisShareEps) cap = std::fmin(cap, limit[i] / s);
  }
  return cap;
}

}  // namespace pcnc
