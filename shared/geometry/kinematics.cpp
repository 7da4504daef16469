// kinematics.cpp — forward and inverse kinematics of the trivial, table-table (XYZAC) and
// head-table (XYZBC) machines, through the decomposition in kinematics_frame.hpp.
#include "geometry/kinematics.hpp"

#include <cmath>
#include <numbers>

#include "geometry/kinematics_frame.hpp"

namespace pcnc {

using kin_detail::rot_x;
using kin_detail::rot_y;
using kin_detail::rot_z;
using kin_detail::rot_z_t;
using kin_detail::tilt_frame;

double unwrap_near(double angle, double reference) {
  constexpr double kTurn = 2.0 * std::numbers::pi;
  return angle + kTurn * std::round((reference - angle) / kTurn);
}

ToolPose forward(const Kinematics& kin, const Joints& q) {
  const kin_detail::TiltFrame f = tilt_frame(kin, q);
  const Vec3& c = kin.rotary_pivot;
  if (kin.kind == KinematicsKind::kTrivial) return {f.h, f.n};
  return {c + rot_z(f.cc, f.sc, f.h - c), rot_z(f.cc, f.sc, f.n)};
}

namespace {

/// The tilt and rotary angles for a unit axis, solution with sin(tilt) >= 0, or the rotary
/// kept at `keep` when the axis lies on the C axis (then tilt is what reaches it best).
struct TiltRotary {
  double tilt, rotary;
};

TiltRotary tilt_rotary(KinematicsKind kind, const Vec3& v, double keep, bool* singular) {
  const double s = std::hypot(v[0], v[1]);
  *singular = s < kSingularSin;
  if (*singular) {
    // v ≈ ±ez: keep C; the tilt is the angle that turns the axis at that C towards v.
    const double cc = std::cos(keep), sc = std::sin(keep);
    const Vec3 local = rot_z_t(cc, sc, v);  // v in the C table's frame: n(T) must match it
    const double t = kind == KinematicsKind::kTableTable ? std::atan2(-local[1], local[2])
                                                          : std::atan2(local[0], local[2]);
    return {t, keep};
  }
  const double t = std::atan2(s, v[2]);
  // table-table: v = (sA·sC, −sA·cC, cA); head-table: v = (sB·cC, sB·sC, cB)
  const double r = kind == KinematicsKind::kTableTable ? std::atan2(v[0], -v[1]) : std::atan2(v[1], v[0]);
  return {t, r};
}

/// The angle equal to `angle` modulo 2π nearest `reference` inside [lo, hi], or nearest
/// `reference` when no turn lies inside.
double turn_within(double angle, double reference, double lo, double hi) {
  constexpr double kTurn = 2.0 * std::numbers::pi;
  const double near = unwrap_near(angle, reference);
  double best = near;
  bool inside = near >= lo && near <= hi;
  for (double alt : {near - kTurn, near + kTurn})
    if (alt >= lo && alt <= hi && (!inside || std::abs(alt - reference) < std::abs(best - reference))) {
      best = alt;
      inside = true;
    }
  return best;
}

}  // namespace

Joints inverse(const Kinematics& kin, const ToolPose& pose, const Joints& previous) {
  return inverse(kin, pose, previous, RotaryTravel{});
}

Joints inverse(const Kinematics& kin, const ToolPose& pose, const Joints& previous, const RotaryTravel& travel) {
  const Vec3 ez{0.0, 0.0, 1.0};
  if (kin.kind == KinematicsKind::kTrivial) {
    const Vec3 xyz = pose.tip + kin.tool_length * ez;
    return {xyz[0], xyz[1], xyz[2], 0.0, 0.0};
  }
  const Vec3 v = normalized(pose.axis);
  bool singular = false;
  const TiltRotary tr = tilt_rotary(kin.kind, v, previous[kRotary], &singular);
  double tilt = tr.tilt;
  double rot = singular ? tr.rotary : turn_within(tr.rotary, previous[kRotary], travel.rotary_min, travel.rotary_max);
  if (!singular) {
    // the other solution: (−tilt, rotary + π); take the one inside the travel, and of two
    // inside (or two outside) the one nearer the previous joints
    const double rot2 =
        turn_within(tr.rotary + std::numbers::pi, previous[kRotary], travel.rotary_min, travel.rotary_max);
    const double d1 = std::abs(tilt - previous[kTilt]) + std::abs(rot - previous[kRotary]);
    const double d2 = std::abs(-tilt - previous[kTilt]) + std::abs(rot2 - previous[kRotary]);
    auto inside = [&](double t, double r) {
      return t >= travel.tilt_min && t <= travel.tilt_max && r >= travel.rotary_min && r <= travel.rotary_max;
    };
    const bool in1 = inside(tilt, rot), in2 = inside(-tilt, rot2);
    if (in1 != in2 ? in2 : d2 < d1) {
      tilt = -tilt;
      rot = rot2;
    }
  }
  // h: the tip in the C table's frame; then x y z from h.
  const double cc = std::cos(rot), sc = std::sin(rot), ct = std::cos(tilt), st = std::sin(tilt);
  const Vec3& c = kin.rotary_pivot;
  const Vec3 h = c + rot_z_t(cc, sc, pose.tip - c);
  Vec3 xyz;
  if (kin.kind == KinematicsKind::kTableTable) {
    const Vec3& a = kin.tilt_pivot;
    xyz = a + rot_x(ct, -st, h - a) + kin.tool_length * ez;  // h = a + Rx(T)(xyz − L·ez − a)
  } else {
    const Vec3 r = kin.tilt_pivot + kin.tool_length * ez;
    xyz = h - kin.tilt_pivot + rot_y(ct, st, r);  // h = xyz + d − Ry(T)(d + L·ez)
  }
  return {xyz[0], xyz[1], xyz[2], tilt, rot};
}

}  // namespace pcnc
