// axis_slerp.hpp — the tool-axis orientation between two unit axes of a 5-axis move with
// tool-centre-point control: the great-circle arc from one to the other at a constant angular
// rate (not the joint angles linearly), with its first and second derivatives in the
// parameter. Degenerate ends: equal axes give a constant axis; opposite axes (no unique great
// circle) turn through a fixed perpendicular (docs/kinematics.md). Pure.
#pragma once

#include "geometry/vec3.hpp"

namespace pcnc {

/// v(t) = cos(t·angle)·from + sin(t·angle)·across, t in [0, 1]; `from` and `across` are
/// orthonormal, so v(t) is a unit vector and turns at the constant rate `angle` per unit t.
struct AxisSlerp {
  Vec3 from{0.0, 0.0, 1.0};
  Vec3 across{1.0, 0.0, 0.0};
  double angle = 0.0;  // rad, in [0, π]
};

/// The arc from `a` to `b` (normalised here; neither may be zero). When b = −a (within 1e-12),
/// `across` is the unit part of the coordinate axis least aligned with a (X on ties) that is
/// perpendicular to a.
AxisSlerp make_axis_slerp(const Vec3& a, const Vec3& b);

/// v(t), dv/dt and d²v/dt² (= −angle²·v(t)).
Vec3 slerp_axis(const AxisSlerp& s, double t);
Vec3 slerp_axis_d1(const AxisSlerp& s, double t);
Vec3 slerp_axis_d2(const AxisSlerp& s, double t);

}  // namespace pcnc
