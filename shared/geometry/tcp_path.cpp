// tcp_path.cpp — joints, dq/ds and d²q/ds² along a tool-centre-point move, and the path speed
// and acceleration caps they impose (tcp_path.hpp). With u = s/length:
//   tip(s) = start + u·(end − start):  d tip/ds = (end − start)/length,  d² tip/ds² = 0
//   axis(s) = slerp(u):                 d axis/ds = slerp'(u)/length,    d² axis/ds² = slerp''(u)/length²
#include "geometry/tcp_path.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "geometry/kinematics_rates.hpp"

namespace pcnc {

ToolPose tcp_pose(const TcpMove& move, const AxisSlerp& axes, double u) {
  return {move.start.tip + u * (move.end.tip - move.start.tip), slerp_axis(axes, u)};
}

namespace {

/// The fractions u in (0, 1) at which the great circle comes nearest +Z or −Z (the C axis, where
/// the rotary rate peaks): vz = cos(uθ)·a_z + sin(uθ)·w_z is extreme at uθ = atan2(w_z, a_z) (+π).
std::vector<double> nearest_to_pole(const AxisSlerp& axes) {
  std::vector<double> out;
  if (axes.angle <= 0.0 || std::hypot(axes.from[2], axes.across[2]) == 0.0) return out;
  const double phi = std::atan2(axes.across[2], axes.from[2]);
  for (double p : {phi - std::numbers::pi, phi, phi + std::numbers::pi})
    if (p > 0.0 && p < axes.angle) out.push_back(p / axes.angle);
  return out;
}

}  // namespace

Joints tcp_start_joints(const Kinematics& kin, const TcpMove& move, const Joints& previous,
                        const RotaryTravel& travel) {
  const Joints at = inverse(kin, move.start, previous, travel);
  const Vec3 v = normalized(move.start.axis);
  const AxisSlerp axes = make_axis_slerp(move.start.axis, move.end.axis);
  if (kin.kind == KinematicsKind::kTrivial || std::hypot(v[0], v[1]) >= kSingularSin || axes.angle == 0.0) return at;
  // on the pole: C is the one the axis leaves it with, constant along the great circle from the
  // pole (a meridian); taken at the move's end (its middle if the end is the other pole), of
  // the two the one inside the travel there, or the nearer the previous C
  const double u = axes.angle < std::numbers::pi - 1e-6 ? 1.0 : 0.5;
  const Joints leaving = inverse(kin, tcp_pose(move, axes, u), previous, travel);
  Joints seed = previous;
  seed[kRotary] = leaving[kRotary];
  return inverse(kin, move.start, seed, travel);
}

std::vector<JointSample> sample_tcp_move(const Kinematics& kin, const TcpMove& move, double length,
                                         const Joints& previous, int samples, const RotaryTravel& travel) {
  const AxisSlerp axes = make_axis_slerp(move.start.axis, move.end.axis);
  const Vec3 dtip = (1.0 / length) * (move.end.tip - move.start.tip);
  std::vector<double> us;
  for (int i = 0; i < samples; ++i) us.push_back(static_cast<double>(i) / (samples - 1));
  for (double u : nearest_to_pole(axes)) us.push_back(u);
  std::sort(us.begin(), us.end());
  us.erase(std::unique(us.begin(), us.end()), us.end());
  std::vector<JointSample> out;
  out.reserve(us.size());
  Joints prev = tcp_start_joints(kin, move, previous, travel);
  for (double u : us) {
    JointSample js;
    js.s = u * length;
    js.q = inverse(kin, tcp_pose(move, axes, u), prev, travel);
    js.dq = joint_rates(kin, js.q, {dtip, (1.0 / length) * slerp_axis_d1(axes, u)});
    js.ddq = joint_accels(kin, js.q, js.dq, {{0.0, 0.0, 0.0}, (1.0 / (length * length)) * slerp_axis_d2(axes, u)});
    prev = js.q;
    out.push_back(js);
  }
  return out;
}

double joint_speed_cap(const JointSample& js, const JointLimits& limits, double feed, int* joint) {
  constexpr double kEps = 1e-12;
  double speed = feed;
  if (joint) *joint = -1;
  for (int j = 0; j < kJoints; ++j) {
    const double d1 = std::abs(js.dq[j]), d2 = std::abs(js.ddq[j]);
    const double by_speed = d1 > kEps ? limits.velocity[j] / d1 : feed;
    const double by_accel = d2 > kEps ? std::sqrt(limits.acceleration[j] / (2.0 * d2)) : feed;
    if (std::fmin(by_speed, by_accel) < speed) {
      speed = std::fmin(by_speed, by_accel);
      if (joint) *joint = j;
    }
  }
  return speed;
}

PathCaps tcp_path_caps(const std::vector<JointSample>& samples, const JointLimits& limits, double feed,
                       double accel) {
  constexpr double kEps = 1e-12;
  PathCaps caps{feed, accel, -1, -1};
  for (const JointSample& js : samples) {
    int joint = -1;
    const double v = joint_speed_cap(js, limits, caps.speed, &joint);
    if (joint >= 0) {
      caps.speed = v;
      caps.speed_joint = joint;
    }
  }
  for (const JointSample& js : samples)
    for (int j = 0; j < kJoints; ++j) {
      const double d1 = std::abs(js.dq[j]), d2 = std::abs(js.ddq[j]);
      if (d1 <= kEps) continue;
      const double a = (limits.acceleration[j] - d2 * caps.speed * caps.speed) / d1;
      if (a < caps.accel) {
        caps.accel = a;
        caps.accel_joint = j;
      }
    }
  return caps;
}

}  // namespace pcnc
