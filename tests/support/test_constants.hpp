// test_constants.hpp — constants many tests share, defined once (test files compiled together
// in one unity batch must not each define their own): π, one degree in radians, and the
// shipped configs' G54 program zero.
#pragma once

#include <numbers>

#include "geometry/vec3.hpp"

namespace pcnc {

inline constexpr double kPi = std::numbers::pi;
inline constexpr double kDeg = std::numbers::pi / 180.0;  // radians per degree
// [offsets] g54 of configs/desktop-mill.toml and desktop-5axis.toml: centre of X/Y, top of Z
inline constexpr Vec3 kG54{12.5, 12.5, 25.0};

}  // namespace pcnc
