// tangential_budget.hpp — how much path (tangential) acceleration the axes leave at a point of
// a curve once the normal (centripetal) part of the motion is paid for.
//
// Moving along a curve with unit tangent t and curvature vector k (κ·n, 1/mm) at path speed v
// with path acceleration a_t, axis i accelerates at t_i·a_t + k_i·v². Every axis must stay
// within its limit A_i:  |t_i·a_t + k_i·v²| ≤ A_i.  For a given v² this is an interval of a_t
// per axis and their intersection is the range allowed at the point; its symmetric part
// (the same bound for speeding up and braking) is
//     budget(v²) = min over axes with t_i ≠ 0 of (A_i − |k_i|·v²) / |t_i|,
// linear and falling in v². The NURBS feed schedule (host/gcode/nurbs_schedule) plans its
// ramps with it sample by sample, and the rt's block check verifies a block's schedule with it.
// Pure; no config, no block.
#pragma once

#include "geometry/axis_caps.hpp"
#include "geometry/nurbs.hpp"
#include "geometry/vec3.hpp"

namespace pcnc {

/// The tangential accelerations a_t (mm/s²) that keep every axis within its limit at path
/// speed² v2: [lo, hi]. Empty (lo > hi) when the normal part alone exceeds some axis's limit.
/// An axis the path does not move along tangentially (|t_i| <= kAxisShareEps) bounds v² only.
struct AccelRange {
  double lo = 0.0;
  double hi = 0.0;
};
AccelRange tangential_accel_range(const Vec3& t, const Vec3& k, double v2, const AxisLimits& accel);

/// The symmetric part of that range: min(hi, −lo) = min over axes of (A_i − |k_i|·v2)/|t_i|
/// (+infinity when no axis moves tangentially; negative when v2 is too high for the curve).
double tangential_budget(const Vec3& t, const Vec3& k, double v2, const AxisLimits& accel);

/// The largest v² at a point (tangent t, curvature vector k) that can be reached from v2_from
/// over the path length ds with a tangential acceleration of at most `share` times that
/// point's budget at the v² reached:  x ≤ v2_from + 2·ds·share·budget(x), solved per axis in
/// closed form (budget is linear in x). Used forward (speeding up towards the point) and
/// backward (braking from the point). +infinity when no axis moves tangentially.
double reachable_v2(double v2_from, double ds, const Vec3& t, const Vec3& k, const AxisLimits& accel, double share);

/// The point p, unit tangent t and curvature vector k = (C'' − (C''·t)t)/|C'|² of a NURBS curve at u. Where
/// the parametric speed vanishes (a doubled control point) the curve a 1e-7 of the domain
/// beside u is used. `ok` is false when there is no tangent even there.
struct CurveFrame {
  bool ok = false;
  Vec3 p{};  // C(u) (always set)
  Vec3 t{};
  Vec3 k{};
};
CurveFrame nurbs_frame(const NurbsView& c, double u);
/// The same, with the knot span tried first and updated (nurbs_eval's span hint).
CurveFrame nurbs_frame(const NurbsView& c, double u, int& span_hint);
/// nurbs_frame at two parameters (nurbs_eval_pair: two of one span at once), bit for bit.
void nurbs_frame_pair(const NurbsView& c, double ua, double ub, int& span_hint, CurveFrame& fa, CurveFrame& fb);

}  // namespace pcnc
