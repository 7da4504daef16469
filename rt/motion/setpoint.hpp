// setpoint.hpp — what motion hands the drive each cycle: the commanded position of every
// axis with its velocity and acceleration (the servo's feed-forward). Plain value type.
#pragma once

#include "geometry/vec3.hpp"

namespace pcnc {

struct Setpoint {
  Vec3 pos{};  // mm, machine coordinates
  Vec3 vel{};  // mm/s
  Vec3 acc{};  // mm/s²
};

}  // namespace pcnc
