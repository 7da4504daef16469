// path.hpp — a validated motion block as the executor sees it: a curve parameterised by
// path length s in [0, length], evaluated to a point, unit tangent and curvature vector,
// plus the machine's own speed and acceleration caps for that curve.
//
// NURBS blocks are stepped by the executor along their exact curve (chord length s, see
// executor.cpp); here they get their caps and end tangents only.
//
// Lines: p(s) = start + (end − start)·s/L. Arcs and helices: the angle and the in-plane
// radius advance linearly with s (u = s/L: θ = θ0 + sweep·u, r = r0 + (r1 − r0)·u) and the
// normal axis moves linearly, so the path joins start and end exactly even when the end
// radius differs from the start radius by the G-code tolerance.
#pragma once

#include <cstdint>
#include <limits>

#include "geometry/arc_limits.hpp"
#include "geometry/nurbs.hpp"
#include "ipc/block.hpp"
#include "config/config.hpp"
#include "motion/junction.hpp"

namespace pcnc {

struct PathPoint {
  Vec3 p{};          // mm
  Vec3 tangent{};    // unit
  Vec3 curvature{};  // d(tangent)/ds, 1/mm (points to the centre of an arc)
};

struct PreparedBlock {
  BlockKind kind = BlockKind::kLine;
  bool motion = false;      // has a path to travel (line, rapid, arc of nonzero length)
  bool contouring = false;  // may pass its end junction without stopping
  double path_tolerance = 0.0;  // mm, the block's path tolerance (junction-deviation speed at its end)
  double length = 0.0;      // mm
  double speed = 0.0;       // block's path speed limit (before override), mm/s
  double v_machine = 0.0;   // what the axes allow on this curve (override cannot exceed), mm/s
  double accel = 0.0;       // path acceleration used, mm/s²
  Vec3 start{}, end{};
  Vec3 dir_start{}, dir_end{};  // unit tangents from the geometry
  // speed caps where the block starts and ends (NURBS: its feed schedule's first and last
  // values; +infinity for lines and arcs, whose caps are uniform)
  double v_first = 0.0, v_last = 0.0;
  // the acceleration the stop rules may count on when braking through the whole block: accel,
  // but for NURBS the mean of its schedule's accelerations (block_brake_capacity / length)
  double brake_accel = 0.0;
  // the largest path acceleration the block ramps at (NURBS: its schedule's largest), mm/s², and
  // the curvature vector d²p/ds² at its two ends, 1/mm (the corner blend, corner_blend.hpp)
  double ramp_accel = 0.0;
  Vec3 curv_start{}, curv_end{};
  // arc only
  int a1 = 0, a2 = 1, an = 2;   // in-plane first, second axis; normal axis
  double c1 = 0.0, c2 = 0.0;    // centre in the plane
  double theta0 = 0.0, sweep = 0.0, r0 = 0.0, r1 = 0.0;
  // arc only: what arc_path_accel shares by speed: the smaller plane axis's acceleration, the
  // in-plane share q of the path speed, the smallest radius, the path acceleration the normal
  // axis allows (+inf without a helix) and the spiral's factor (parameter speed / true speed)
  double arc_a_plane = 0.0, arc_q = 0.0, arc_r = 0.0, arc_a_normal = 0.0, arc_f = 1.0;
  // rotary joints (lines and rapids on a machine with rotary joints, ipc/block.hpp RotaryMotion)
  bool rotary = false;   // the block moves a rotary joint or runs under TCP
  bool tcp = false;      // start/end are the tool tip in workpiece coordinates
  bool angular = false;  // s is an angle (rad): only the tool turns
  Rot3 rot_start{}, rot_end{};
  Vec3 land{};           // where the linear axes end (end, or the TCP block's joint_end)
  // The path's rate in the machine's joints at its ends, dq/ds and d²q/ds² (junction.hpp
  // joint_junction_speed): (tangent, 0) and no curvature for a block that turns no joint,
  // (Δxyz, Δrot)/length for a TCP-off rotary line, and under TCP the inverse kinematics' rates
  // (tcp_end_rates, which needs the joints the block starts from). Not set for angular blocks
  // (their path parameter is an angle: they start and end at rest).
  JointRate jrate_start{}, jrate_end{}, jcurv_start{}, jcurv_end{};
};

/// Builds the executor's view of a block that passed check_block(). Pure. A block that moves a
/// rotary joint or runs under TCP flows into the next only at the joint-space junction speed
/// (executor.cpp, junction.hpp; an angular block never flows); without TCP its speed and
/// acceleration are also capped by the rotary joints' limits, under TCP the block's own (the
/// host's joint-space plan, tcp_path_caps) are the cap: the feed override cannot raise them.
PreparedBlock prepare_block(const Block& block, const MachineConfig& config);

/// Under TCP (not angular): the joints' rates dq/ds and d²q/ds² at the block's two ends, from
/// the analytic kinematics rates at the joints it starts from (`start_xyz`, the previous block's
/// linear axes, and its rotary start) and at its end joints. Pure, no allocation.
void tcp_end_rates(PreparedBlock& pb, const Block& block, const MachineConfig& config, const Vec3& start_xyz);

/// An arc's tangential path acceleration at path speed v (geometry/arc_limits.hpp arc_accel_at
/// with kArcAccelMargin): at least what its constant `accel` is at the top speed, more below it.
/// 0 for a block that is not an arc.
double arc_path_accel(const PreparedBlock& b, double v);

/// The stretch [s, s + ds] a cycle covers on an arc: its two ends, evaluate(b, s) and
/// evaluate(b, s + ds), evaluated once for arc_stretch_accel at any number of speeds (the
/// executor asks at two each cycle, and has `here` from its last cycle's step).
struct ArcStretch {
  PathPoint here, land;
};

/// An arc's tangential path acceleration at path speed v over a stretch a cycle covers: the
/// larger of arc_path_accel (the plane's smaller limit, the same everywhere on the arc: what the
/// stop rules count on) and, at both ends of the stretch, each axis carrying its own share
/// (point_tangential_accel): on a G18/G19 arc the faster plane axis takes the centripetal part
/// where the normal points along it. Both keep every axis within its limit.
double arc_stretch_accel(const PreparedBlock& b, const ArcStretch& stretch, const MachineConfig& config, double v);

/// The stretch of an arc from path length `from` to its end, as its in-plane axes see it: the
/// shares of the radius direction each sweeps, and bounds on the tangent's shares and the
/// curvature that hold at every point of it (evaluate), a spiral's and a helix's included. Built
/// once per question for arc_sweep_accel at any number of speeds.
struct ArcSweep {
  ArcPlane plane{};        // the shares of the radius direction, and kArcAccelMargin · each limit
  double q = 0.0;          // the in-plane share of the unit tangent, at most
  double phi = 0.0;        // a spiral's tangent turns from the circle's by at most atan(phi)
  double curvature = 0.0;  // 1/mm, at most
  double normal = std::numeric_limits<double>::infinity();  // what the normal axis leaves (helix)
};
ArcSweep arc_sweep(const PreparedBlock& b, const MachineConfig& config, double from);

/// The least tangential path acceleration the axes leave at path speed v anywhere on the swept
/// stretch, each axis carrying its own share (the least over the stretch of arc_stretch_accel's
/// per-axis rule, in closed form: geometry/arc_limits.hpp plane_axis_tangential_room). It falls
/// as v rises. On a G18/G19 arc it is larger than the plane rule (arc_path_accel) where the rest
/// of the arc runs along the faster axis.
double arc_sweep_accel(const PreparedBlock& b, const ArcSweep& sweep, double v);

/// The stop rule on the rest of an arc (`sweep` = arc_sweep over its last `distance`) asked at
/// speed v: the speed from which the rule brakes within `distance` to `v_exit` at the
/// acceleration the arc keeps at every speed up to v there (the largest of the block's constant,
/// arc_path_accel and arc_sweep_accel). `exact`: stop_speed_exact's rule (a stop at rest with
/// no junction-restricted cycle left), else stop_speed's with its margin `k`; `dt` the cycle.
double arc_stop_rule(const PreparedBlock& b, const ArcSweep& sweep, double distance, double v_exit, bool exact,
                     double dt, double k, double v);

/// The stop rule on an arc whose tangential acceleration falls as its speed rises: the largest V
/// up to `cap` (infinite: the arc's v_machine) with arc_stop_rule(V) >= V, to 1e-8 of the cap,
/// by regula falsi (the rule's speed rises with the acceleration, which falls with V); the V
/// returned always has arc_stop_rule(V) >= V. Pure.
double arc_stop_speed(const PreparedBlock& b, const MachineConfig& config, double distance, double v_exit, bool exact,
                      double cap, double dt, double k);

/// What the axes leave for a curve's tangential acceleration at a point `e` (p, dp/du, d²p/du²)
/// at path speed v: each axis keeps |a_t·T_i + v²·κ_i| within kArcAccelMargin of its limit, so
/// a_t <= (m·A_i − v²·|κ_i|)/|T_i| (T the unit tangent, κ the curvature vector); 0 where the normal
/// part alone takes an axis's share. The executor ramps NURBS blocks by it below their schedule.
double curve_tangential_accel(const NurbsEval& e, const MachineConfig& config, double v);
/// The same at a point given by its unit tangent `t` and curvature vector `k` (1/mm): an arc's
/// point (evaluate) or a curve's.
double point_tangential_accel(const Vec3& t, const Vec3& k, const MachineConfig& config, double v);

/// Point, tangent and curvature at path length s (clamped to [0, length]).
PathPoint evaluate(const PreparedBlock& b, double s);


}  // namespace pcnc
