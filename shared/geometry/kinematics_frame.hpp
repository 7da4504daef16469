// kinematics_frame.hpp — the one decomposition both machines share, used by kinematics.cpp
// (forward, inverse) and kinematics_rates.cpp (Jacobian, joint rates); not for other callers.
//
// Every kind is written as   tip  = c + Rz(C) (h(q) − c),   axis = Rz(C) n(T)
// with T the tilt joint, C the rotary joint, c the C axis's point, and h, n the tool tip and
// axis in the C table's frame, which depend on x, y, z and T only:
//   table-table (A tilts the table):  h = a + Rx(T)(p − a),  p = xyz − L·ez,  n = Rx(T)·ez
//   head-table  (B tilts the head):   h = xyz + d − Ry(T)(d + L·ez),          n = Ry(T)·ez
//   trivial:                          h = xyz − L·ez,                         n = ez, C = 0
// This header gives h, n and their derivatives in T (analytic), and the action of ∂h/∂xyz
// (a rotation: Rx(T) or the identity) and of ∂²h/∂xyz∂T on a vector.
#pragma once

#include <cmath>

#include "geometry/kinematics.hpp"
#include "geometry/vec3.hpp"

namespace pcnc::kin_detail {

/// Rz(C)·v for C given by its cosine and sine.
inline Vec3 rot_z(double c, double s, const Vec3& v) { return {c * v[0] - s * v[1], s * v[0] + c * v[1], v[2]}; }
/// Rz(C)ᵀ·v.
inline Vec3 rot_z_t(double c, double s, const Vec3& v) { return {c * v[0] + s * v[1], -s * v[0] + c * v[1], v[2]}; }
/// K·v = ez × v, the derivative of Rz in C: dRz/dC = Rz·K.
inline Vec3 k_z(const Vec3& v) { return {-v[1], v[0], 0.0}; }
/// Rx(T)·v and Ry(T)·v.
inline Vec3 rot_x(double c, double s, const Vec3& v) { return {v[0], c * v[1] - s * v[2], s * v[1] + c * v[2]}; }
inline Vec3 rot_y(double c, double s, const Vec3& v) { return {c * v[0] + s * v[2], v[1], -s * v[0] + c * v[2]}; }

/// h, n and their T-derivatives at one joint vector.
struct TiltFrame {
  KinematicsKind kind;
  double ct, st;  // cos, sin of the tilt
  double cc, sc;  // cos, sin of the rotary (1, 0 for kTrivial)
  Vec3 h, h_t, h_tt;
  Vec3 n, n_t, n_tt;

  /// ∂h/∂xyz · v
  Vec3 lin(const Vec3& v) const { return kind == KinematicsKind::kTableTable ? rot_x(ct, st, v) : v; }
  /// (∂h/∂xyz)ᵀ · v (its inverse: a rotation)
  Vec3 lin_t(const Vec3& v) const { return kind == KinematicsKind::kTableTable ? rot_x(ct, -st, v) : v; }
  /// ∂²h/∂xyz∂T · v (Rx(T)·(ex × v) for table-table, zero otherwise)
  Vec3 lin_tilt(const Vec3& v) const {
    return kind == KinematicsKind::kTableTable ? rot_x(ct, st, Vec3{0.0, -v[2], v[1]}) : Vec3{0.0, 0.0, 0.0};
  }
};

inline TiltFrame tilt_frame(const Kinematics& kin, const Joints& q) {
  TiltFrame f{};
  f.kind = kin.kind;
  const Vec3 xyz{q[0], q[1], q[2]};
  const Vec3 ez{0.0, 0.0, 1.0};
  const double tilt = kin.kind == KinematicsKind::kTrivial ? 0.0 : q[kTilt];
  const double rot = kin.kind == KinematicsKind::kTrivial ? 0.0 : q[kRotary];
  f.ct = std::cos(tilt);
  f.st = std::sin(tilt);
  f.cc = std::cos(rot);
  f.sc = std::sin(rot);
  switch (kin.kind) {
    case KinematicsKind::kTrivial:
      f.h = xyz - kin.tool_length * ez;
      f.n = ez;
      break;
    case KinematicsKind::kTableTable: {
      const Vec3 p = xyz - kin.tool_length * ez - kin.tilt_pivot;
      const Vec3 rp = rot_x(f.ct, f.st, p);
      f.h = kin.tilt_pivot + rp;
      f.h_t = {0.0, -rp[2], rp[1]};  // Rx'(T) p = ex × (Rx p)
      f.h_tt = {0.0, -rp[1], -rp[2]};
      f.n = {0.0, -f.st, f.ct};
      f.n_t = {0.0, -f.ct, -f.st};
      f.n_tt = {0.0, f.st, -f.ct};
      break;
    }
    case KinematicsKind::kHeadTable: {
      const Vec3 r = kin.tilt_pivot + kin.tool_length * ez;  // from the pivot's view, the tip is at −r
      const Vec3 rr = rot_y(f.ct, f.st, r);
      f.h = xyz + kin.tilt_pivot - rr;
      f.h_t = {-rr[2], 0.0, rr[0]};  // −Ry'(T) r = −ey × (Ry r)
      f.h_tt = {rr[0], 0.0, rr[2]};
      f.n = {f.st, 0.0, f.ct};
      f.n_t = {f.ct, 0.0, -f.st};
      f.n_tt = {-f.st, 0.0, -f.ct};
      break;
    }
  }
  return f;
}

}  // namespace pcnc::kin_detail
