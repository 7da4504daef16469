// kinematics_rates.cpp — the analytic Jacobian and the joint rates, from
//   tip = c + Rz(C)(h − c),  axis = Rz(C)·n   (kinematics_frame.hpp), with dRz/dC = Rz·K:
//   tip'  = Rz[h' + K(h − c)C'],                 h'  = ∂h/∂xyz·xyz' + h_T·T'
//   tip'' = Rz[h'' + 2K·h'·C' + K²(h − c)C'² + K(h − c)C'']
//           h'' = ∂h/∂xyz·xyz'' + h_T·T'' + 2·∂²h/∂xyz∂T·xyz'·T' + h_TT·T'²
//   axis' = Rz[n_T·T' + K·n·C']
//   axis''= Rz[n_T·T'' + K·n·C'' + n_TT·T'² + 2K·n_T·T'·C' + K²·n·C'²]
// n_T is a unit vector and K·n (length |sin T|) is orthogonal to it, so the tilt and rotary
// rates are projections of the axis's rate; x, y, z then follow from the tip's rate through
// the rotation ∂h/∂xyz.
#include "geometry/kinematics_rates.hpp"

#include "geometry/kinematics_frame.hpp"

namespace pcnc {

using kin_detail::k_z;
using kin_detail::rot_z;
using kin_detail::rot_z_t;
using kin_detail::TiltFrame;
using kin_detail::tilt_frame;

Jacobian jacobian(const Kinematics& kin, const Joints& q) {
  const TiltFrame f = tilt_frame(kin, q);
  const Vec3& c = kin.rotary_pivot;
  std::array<Vec3, kJoints> tip_col{};
  std::array<Vec3, kJoints> axis_col{};
  for (int i = 0; i < 3; ++i) {
    Vec3 e{0.0, 0.0, 0.0};
    e[i] = 1.0;
    tip_col[i] = rot_z(f.cc, f.sc, f.lin(e));
  }
  if (kin.kind != KinematicsKind::kTrivial) {
    tip_col[kTilt] = rot_z(f.cc, f.sc, f.h_t);
    tip_col[kRotary] = rot_z(f.cc, f.sc, k_z(f.h - c));
    axis_col[kTilt] = rot_z(f.cc, f.sc, f.n_t);
    axis_col[kRotary] = rot_z(f.cc, f.sc, k_z(f.n));
  }
  Jacobian j{};
  for (int col = 0; col < kJoints; ++col)
    for (int row = 0; row < 3; ++row) {
      j[row][col] = tip_col[col][row];
      j[3 + row][col] = axis_col[col][row];
    }
  return j;
}

namespace {

/// The tilt and rotary components of a rate `u` of the axis in the C table's frame (Rzᵀ·axis').
void split_axis_rate(const TiltFrame& f, const Vec3& u, double* tilt, double* rot) {
  *tilt = dot(u, f.n_t);
  const Vec3 kn = k_z(f.n);
  const double s2 = dot(kn, kn);
  *rot = s2 < kSingularSin * kSingularSin ? 0.0 : dot(u, kn) / s2;
}

}  // namespace

Joints joint_rates(const Kinematics& kin, const Joints& q, const PoseRate& d1) {
  if (kin.kind == KinematicsKind::kTrivial) return {d1.tip[0], d1.tip[1], d1.tip[2], 0.0, 0.0};
  const TiltFrame f = tilt_frame(kin, q);
  double dt = 0.0, dc = 0.0;
  split_axis_rate(f, rot_z_t(f.cc, f.sc, d1.axis), &dt, &dc);
  const Vec3 hc = f.h - kin.rotary_pivot;
  const Vec3 dh = rot_z_t(f.cc, f.sc, d1.tip) - dc * k_z(hc);  // h'
  const Vec3 dxyz = f.lin_t(dh - dt * f.h_t);
  return {dxyz[0], dxyz[1], dxyz[2], dt, dc};
}

Joints joint_accels(const Kinematics& kin, const Joints& q, const Joints& dq, const PoseRate& d2) {
  if (kin.kind == KinematicsKind::kTrivial) return {d2.tip[0], d2.tip[1], d2.tip[2], 0.0, 0.0};
  const TiltFrame f = tilt_frame(kin, q);
  const Vec3 dxyz{dq[0], dq[1], dq[2]};
  const double dt = dq[kTilt], dc = dq[kRotary];
  // axis'' in the table frame minus the terms of the known first rates
  const Vec3 axis_rest =
      dt * dt * f.n_tt + (2.0 * dt * dc) * k_z(f.n_t) + (dc * dc) * k_z(k_z(f.n));
  double ddt = 0.0, ddc = 0.0;
  split_axis_rate(f, rot_z_t(f.cc, f.sc, d2.axis) - axis_rest, &ddt, &ddc);
  const Vec3 hc = f.h - kin.rotary_pivot;
  const Vec3 dh = f.lin(dxyz) + dt * f.h_t;
  // h'' = Rzᵀ·tip'' − 2K·h'·C' − K²(h − c)C'² − K(h − c)C''
  const Vec3 ddh = rot_z_t(f.cc, f.sc, d2.tip) - (2.0 * dc) * k_z(dh) - (dc * dc) * k_z(k_z(hc)) - ddc * k_z(hc);
  // ∂h/∂xyz·xyz'' = h'' − h_T·T'' − 2·∂²h/∂xyz∂T·xyz'·T' − h_TT·T'²
  const Vec3 ddxyz = f.lin_t(ddh - ddt * f.h_t - (2.0 * dt) * f.lin_tilt(dxyz) - (dt * dt) * f.h_tt);
  return {ddxyz[0], ddxyz[1], ddxyz[2], ddt, ddc};
}

}  // namespace pcnc
