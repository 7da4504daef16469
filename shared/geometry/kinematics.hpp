// kinematics.hpp — the machine's kinematics: joints (x, y, z, tilt, rotary) to the tool tip and
// tool axis in workpiece coordinates (forward) and back (inverse), for the trivial XYZ mill, the
// XYZAC table-table trunnion and the XYZBC head-table machine. Pure; radians and mm inside.
// The directions of +A, +B, +C, the tool axis at zero and the formulas are in docs/kinematics.md.
// The rt's tool-centre-point control and the host's joint limits call these; the Jacobian and
// the joint rates along a path are in kinematics_rates.hpp.
#pragma once

#include <array>
#include <limits>

#include "geometry/vec3.hpp"

namespace pcnc {

enum class KinematicsKind {
  kTrivial,     // X Y Z only: the tool axis is +Z; tilt and rotary are ignored (kept at 0)
  kTableTable,  // XYZAC: the table tilts about A (parallel to X) and turns about C on the cradle
  kHeadTable,   // XYZBC: the spindle head tilts about B (parallel to Y), the table turns about C
};

/// Joint values in the machine's order: x, y, z (mm), tilt (A or B), rotary (C) (rad).
using Joints = std::array<double, 5>;
constexpr int kJoints = 5;
constexpr int kTilt = 3;
constexpr int kRotary = 4;

/// The machine's kinematic constants (machine mm). Workpiece coordinates are the machine's when
/// the tilt and rotary joints are at 0: the frame is fixed to the C table and turns with it.
struct Kinematics {
  KinematicsKind kind = KinematicsKind::kTrivial;
  /// kTableTable: a point on the A axis (machine coordinates).
  /// kHeadTable: the B axis's point relative to the spindle's gauge point at B = 0 (it moves with
  /// X Y Z; usually {0, 0, pivot length}).
  Vec3 tilt_pivot{0.0, 0.0, 0.0};
  /// A point on the C axis (machine coordinates, with the tilt at 0); the C axis is parallel to Z.
  Vec3 rotary_pivot{0.0, 0.0, 0.0};
  /// From the spindle's gauge point to the tool tip, along the tool axis (mm, >= 0).
  double tool_length = 0.0;
};

/// The tool in workpiece coordinates: its tip (mm) and its unit axis, pointing from the tip
/// into the spindle (+Z at zero joints).
struct ToolPose {
  Vec3 tip{0.0, 0.0, 0.0};
  Vec3 axis{0.0, 0.0, 1.0};
};

/// Below this sin(tilt) the rotary axis is at its singularity (the tool axis on the C axis):
/// the inverse keeps C where it was and the rates give it no speed.
constexpr double kSingularSin = 1e-9;

/// Forward kinematics: joints to the tool pose in workpiece coordinates.
ToolPose forward(const Kinematics& kin, const Joints& q);

/// Inverse kinematics: the joints that put the tool at `pose` (axis need not be exactly unit;
/// it is normalised). Of the two solutions (tilt, rotary) and (−tilt, rotary + π) it returns the
/// one nearest `previous` (rotary unwrapped to the turn nearest previous[kRotary], so a
/// continuous C never jumps by 2π). At the singularity (|sin tilt| < kSingularSin) the rotary
/// joint keeps previous[kRotary]. For kTrivial the axis is ignored and tilt, rotary are 0.
Joints inverse(const Kinematics& kin, const ToolPose& pose, const Joints& previous);

/// The travel of the rotary joints (rad), for choosing among the inverse's solutions.
/// Unbounded by default: a continuous C.
struct RotaryTravel {
  double tilt_min = -std::numeric_limits<double>::infinity();
  double tilt_max = std::numeric_limits<double>::infinity();
  double rotary_min = -std::numeric_limits<double>::infinity();
  double rotary_max = std::numeric_limits<double>::infinity();
};

/// As above, but within the travel where it can: C takes the turn nearest previous[kRotary]
/// that lies inside its travel (C limited to −200°..+200°, now at 190°, reaches 210° as
/// −150°), and a solution inside the travel is preferred to one outside it (of two inside, or
/// two outside, the nearer one): a tilt of −30°..+110° reaches an axis tilted 60° only at +60°,
/// whatever the previous joints. The caller still checks the result.
Joints inverse(const Kinematics& kin, const ToolPose& pose, const Joints& previous, const RotaryTravel& travel);

/// The angle nearest `reference` that equals `angle` modulo 2π.
double unwrap_near(double angle, double reference);

}  // namespace pcnc
