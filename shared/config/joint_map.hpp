// joint_map.hpp — the machine's joints as the contract carries them (linear axes X Y Z in mm and
// the rotary joints A B C by index, rad) to and from the kinematics' order (x, y, z, tilt, rotary;
// geometry/kinematics.hpp): the tilt is A on a table-table machine, B on a head-table one; the
// rotary is C. A joint the kinematics do not use reads 0. Pure.
#pragma once

#include "config/config.hpp"
#include "geometry/kinematics.hpp"
#include "ipc/rotary_joints.hpp"

namespace pcnc {

/// Index (0 A, 1 B, 2 C) of the kinematics' tilt joint, or -1 (trivial kinematics).
inline int tilt_index(const MachineConfig& cfg) {
  switch (cfg.kinematics.kind) {
    case KinematicsKind::kTableTable: return 0;
    case KinematicsKind::kHeadTable: return 1;
    default: return -1;
  }
}
/// Index of the kinematics' rotary joint (C), or -1.
inline int rotary_index(const MachineConfig& cfg) { return cfg.kinematics.kind == KinematicsKind::kTrivial ? -1 : 2; }

inline Joints to_joints(const MachineConfig& cfg, const Vec3& xyz, const Rot3& rot) {
  Joints q{xyz[0], xyz[1], xyz[2], 0.0, 0.0};
  if (const int t = tilt_index(cfg); t >= 0) q[kTilt] = rot[static_cast<std::size_t>(t)];
  if (const int c = rotary_index(cfg); c >= 0) q[kRotary] = rot[static_cast<std::size_t>(c)];
  return q;
}

/// Writes q's joints into xyz and the kinematics' joints of rot (others in rot are kept).
inline void from_joints(const MachineConfig& cfg, const Joints& q, Vec3& xyz, Rot3& rot) {
  xyz = {q[0], q[1], q[2]};
  if (const int t = tilt_index(cfg); t >= 0) rot[static_cast<std::size_t>(t)] = q[kTilt];
  if (const int c = rotary_index(cfg); c >= 0) rot[static_cast<std::size_t>(c)] = q[kRotary];
}

/// The machine's kinematics with a tool of `tool_length` mm.
inline Kinematics kinematics_with_tool(const MachineConfig& cfg, double tool_length) {
  Kinematics k = cfg.kinematics;
  k.tool_length = tool_length;
  return k;
}

}  // namespace pcnc
