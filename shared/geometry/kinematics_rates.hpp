// kinematics_rates.hpp — first and second order of the kinematics: the analytic Jacobian of the
// forward kinematics, and the joint rates that follow a tool pose moving along a parameter
// (dq/du from the pose's d/du, d²q/du² from its d²/du²). The host's joint-limit planning
// (tcp_path.hpp) and the rt's velocity and acceleration feed-forward use them. Pure.
#pragma once

#include <array>

#include "geometry/kinematics.hpp"
#include "geometry/vec3.hpp"

namespace pcnc {

/// ∂(tip, axis)/∂q: rows tip x, y, z, axis x, y, z; columns the joints x, y, z, tilt, rotary.
using Jacobian = std::array<std::array<double, kJoints>, 6>;

/// The analytic Jacobian of forward(kin, q).
Jacobian jacobian(const Kinematics& kin, const Joints& q);

/// A derivative of a tool pose along some parameter u: d tip/du (mm per unit of u) and
/// d axis/du (per unit of u; only its part across the axis matters).
struct PoseRate {
  Vec3 tip{0.0, 0.0, 0.0};
  Vec3 axis{0.0, 0.0, 0.0};
};

/// dq/du at joints q for a pose moving at `d1` = d pose/du. The tilt rate is the axis's rate
/// along the tilt direction; the rotary rate is its rate across it divided by sin(tilt), so it
/// grows as 1/sin(tilt) near the singularity and is 0 at it (|sin tilt| < kSingularSin), where
/// the inverse holds C still. For kTrivial only the tip counts.
Joints joint_rates(const Kinematics& kin, const Joints& q, const PoseRate& d1);

/// d²q/du² at joints q with rates dq = dq/du for a pose whose second derivative is `d2`
/// = d² pose/du² (the same parameter).
Joints joint_accels(const Kinematics& kin, const Joints& q, const Joints& dq, const PoseRate& d2);

}  // namespace pcnc
