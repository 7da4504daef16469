// setpoint.hpp — what motion hands the drive each cycle: the commanded position of every
// axis with its velocity and acceleration (the servo's feed-forward). Plain value type.
#pragma once

#include "geometry/vec3.hpp"
#include "ipc/rotary_joints.hpp"

namespace pcnc {

struct Setpoint {
  Vec3 pos{};  // mm, machine coordinates
  Vec3 vel{};  // mm/s
  Vec3 acc{};  // mm/s²
  Rot3 rot{};      // rotary joints, rad (A B C by index; joints the machine lacks stay 0)
  Rot3 rot_vel{};  // rad/s
  Rot3 rot_acc{};  // rad/s²
};

}  // namespace pcnc
