// arc_limits.hpp — how an arc shares its plane axes' acceleration between the centripetal
// part v²/r and the tangential part. The host's preprocessor plans every arc block with it
// and the rt's executor re-derives the same caps from its own config (it trusts no block).
//
// The in-plane acceleration vector is a_t·T + (v²/r)·N; keeping its magnitude within the
// smaller plane axis's limit a keeps every in-plane axis within it. The speed cap keeps the
// centripetal part within kArcCentripetalShare·a; the tangential part gets what is left at
// the fastest speed the block can ever run (feed override included):
//   a_t = sqrt(a² − (v_top²/r)²) >= sqrt(1 − share²)·a   (0.31·a for share 0.95).
// The share was 0.5 until 2026-11-26, then 0.7 while the executor ramped every arc at the
// constant (tools/bench_surfacing.sh: a larger share lost more on the ramps than it won at the
// cap). Since the executor ramps and brakes by speed (below), 0.95: with 0.7 / 0.9 / 0.95 / 0.97
// LHchips4 took 80.61 / 80.00 / 79.96 / 79.94 s, rgh 9.31 / 8.65 / 8.53 / 8.49 s,
// Gates_combined_R12 133.49 / 129.57 / 128.84 / 128.60 s (docs/smoothing.md, "Arcs by speed").
// A slow arc on a large radius thus brakes and accelerates almost at the axis limit, where
// a fixed split would leave half of it unused. That constant is the block's: what the host plans
// with and the stop rules can count on at every speed. The rt's executor also ramps and brakes
// by speed (arc_accel_at): below the top speed the tangential part gets what the centripetal
// part leaves at the speed the machine has.
//
// Each axis may also carry its own share along the angles the arc sweeps (since 2026-11-27):
// the radius direction lies at most max|cos θ| along the first plane axis and max|sin θ| along
// the second, so the cap's `a` is arc_centripetal_limit, min(A1/max|cos θ|, A2/max|sin θ|) >=
// min(A1, A2), and the block's tangential constant the larger of the vector rule above and each
// axis's least share over the sweep (arc_plane_tangential_accel). A short G18/G19 arc whose normal
// stays near the faster axis runs faster; one sweeping through both axes' normals as before.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

namespace pcnc {

/// Share of what the plane axes allow for the centripetal part along the sweep
/// (arc_centripetal_limit) that an arc's speed cap uses.
constexpr double kArcCentripetalShare = 0.95;
/// The largest feed override (FeedOverride::kMax): the top speed an arc block can be run at
/// is min(what the axes allow, this times its programmed speed).
constexpr double kArcMaxFeedOverride = 2.0;

/// Largest |sin| and |cos| over the angles from `start` through `start + sweep` (sweep signed):
/// how much of an arc's in-plane speed its second and first plane axis carry at most, as the
/// in-plane velocity is r·(−sin θ, cos θ).
inline double max_abs_trig(double start, double sweep, double peak_offset, double (*f)(double)) {
  constexpr double kPi = 3.14159265358979323846;
  const double lo = std::min(start, start + sweep);
  const double hi = std::max(start, start + sweep);
  const double k = std::ceil((lo - peak_offset) / kPi);  // the first peak at or after lo
  if (peak_offset + k * kPi <= hi) return 1.0;
  return std::max(std::fabs(f(lo)), std::fabs(f(hi)));
}
inline double max_abs_sin(double start, double sweep) {
  return max_abs_trig(start, sweep, 3.14159265358979323846 / 2.0, [](double x) { return std::sin(x); });
}
inline double max_abs_cos(double start, double sweep) {
  return max_abs_trig(start, sweep, 0.0, [](double x) { return std::cos(x); });
}

/// The least tangential acceleration one in-plane axis leaves on a stretch of an arc, each axis
/// carrying its own share: where the radius direction has a share x of the axis (|cos θ| for the
/// first plane axis, |sin θ| for the second), the centripetal part takes c·x of the axis's
/// `limit` (c = v²·κ, κ at most the arc's curvature) and the tangent has at most
/// q·(√(1−x²) + φ·x) of it (q the in-plane share of the unit tangent; φ bounds how far a
/// spiral's tangent turns from the circle's), so the tangential acceleration may be
///   g(x) = (limit − c·x) / (q·(√(1−x²) + φ·x)).
/// Returns the least g over x in [x_lo, x_hi] (the shares the stretch sweeps): g falls and then
/// rises, its least value where x − φ·√(1−x²) = c/limit, so that point clamped into the range.
/// 0 where the centripetal part alone takes the axis's whole limit somewhere in the range;
/// +infinity where the axis never moves along the tangent. Pure.
inline double plane_axis_tangential_room(double limit, double c, double q, double phi, double x_lo, double x_hi) {
  if (c * x_hi >= limit) return 0.0;
  if (!(q > 1e-12)) return std::numeric_limits<double>::infinity();
  // x − φ·√(1−x²) = c/limit, with x = sin α: √(1+φ²)·sin(α − β) = c/limit, tan β = φ; at
  // c >= limit g falls all the way to x = 1
  const double n = std::sqrt(1.0 + phi * phi);
  const double y = c / limit / n;
  double x = c >= limit ? 1.0 : (y + phi * std::sqrt(1.0 - y * y)) / n;
  x = std::clamp(x, x_lo, x_hi);
  const double along = q * (std::sqrt(std::max(0.0, 1.0 - x * x)) + phi * x);
  if (!(along > 1e-12)) return std::numeric_limits<double>::infinity();
  return (limit - c * x) / along;
}

/// Share of what the plane leaves beside the centripetal part that the rt's executor ramps and
/// brakes an arc at (the NURBS schedule's kTangentialAccelMargin): room for the cycle's linear
/// steps of speed.
constexpr double kArcAccelMargin = 0.95;

/// An arc's tangential path acceleration at path speed `v`, shared by speed as the rt's executor
/// runs it: what the smaller plane axis limit `a_plane` leaves beside the centripetal part of the
/// in-plane speed q·v on radius `r_mm` (the vector sum within a_plane), times `margin`, over q;
/// at most `a_normal_path` (the normal axis's share on a helix; +inf without one). It falls as v
/// rises; 0 where the centripetal part alone would take the whole of a_plane.
inline double arc_accel_at(double a_plane, double r_mm, double q, double a_normal_path, double margin, double v) {
  if (!(q > 1e-12) || !(r_mm > 0.0)) return a_normal_path;
  const double vp = q * v;
  const double an = vp * vp / r_mm;
  const double rest = a_plane * a_plane - an * an;
  const double at = rest > 0.0 ? margin * std::sqrt(rest) / q : 0.0;
  return std::min(at, a_normal_path);
}

/// An arc's plane as its two axes see the angles it sweeps: their accelerations and the shares
/// of the radius direction (the centripetal part's direction) each carries, |cos θ| for the first
/// plane axis and |sin θ| for the second, least and most over the sweep.
struct ArcPlane {
  double a1 = 0.0, a2 = 0.0;                 // the plane axes' acceleration limits, mm/s²
  double n1_lo = 0.0, n1_hi = 1.0, n2_lo = 0.0, n2_hi = 1.0;
};

/// The plane of an arc from `start` over `sweep` (radians, signed) with plane axis limits a1, a2.
/// |cos θ| reaches 1 at kπ and 0 at π/2 + kπ, |sin θ| the other way round; elsewhere both lie
/// between their values at the two ends (one cos and one sin at each end).
inline ArcPlane arc_plane(double a1, double a2, double start, double sweep) {
  constexpr double kPi = 3.14159265358979323846;
  const double lo = std::min(start, start + sweep), hi = std::max(start, start + sweep);
  auto holds = [&](double offset) { return offset + std::ceil((lo - offset) / kPi) * kPi <= hi; };
  const bool along1 = holds(0.0), along2 = holds(0.5 * kPi);  // the radius along axis 1 / axis 2
  const double c0 = std::fabs(std::cos(start)), c1 = std::fabs(std::cos(start + sweep));
  const double s0 = std::fabs(std::sin(start)), s1 = std::fabs(std::sin(start + sweep));
  ArcPlane p;
  p.a1 = a1;
  p.a2 = a2;
  p.n1_hi = along1 ? 1.0 : std::max(c0, c1);
  p.n1_lo = along2 ? 0.0 : std::min(c0, c1);
  p.n2_hi = along2 ? 1.0 : std::max(s0, s1);
  p.n2_lo = along1 ? 0.0 : std::min(s0, s1);
  return p;
}

/// The centripetal acceleration an arc may count on in its plane, each axis carrying its own
/// share along the sweep: min(a1 / max|cos θ|, a2 / max|sin θ|). At least the smaller of a1 and a2
/// (the whole plane's rule, which an arc sweeping through both axes' normals meets), more where
/// the arc keeps its normal away from the slower axis (a short G18/G19 arc along the faster one).
inline double arc_centripetal_limit(const ArcPlane& p) {
  double a = std::numeric_limits<double>::infinity();
  if (p.n1_hi > 0.0) a = std::min(a, p.a1 / p.n1_hi);
  if (p.n2_hi > 0.0) a = std::min(a, p.a2 / p.n2_hi);
  return std::isfinite(a) ? a : std::min(p.a1, p.a2);
}

/// The in-plane tangential acceleration an arc keeps at every angle of its sweep while its
/// in-plane centripetal part is `an` (v²/r): the larger of the whole plane's rule (the vector
/// sum within the smaller limit, sqrt(a² − an²), while an stays within it) and each axis within
/// its own limit (plane_axis_tangential_room's least value over the shares the sweep gives it).
inline double arc_plane_tangential_accel(const ArcPlane& p, double an) {
  const double a_plane = std::min(p.a1, p.a2);
  const double uniform = an < a_plane ? std::sqrt(a_plane * a_plane - an * an) : 0.0;
  const double by_axis = std::min(plane_axis_tangential_room(p.a1, an, 1.0, 0.0, p.n1_lo, p.n1_hi),
                                  plane_axis_tangential_room(p.a2, an, 1.0, 0.0, p.n2_lo, p.n2_hi));
  return std::max(uniform, by_axis);
}

/// The machine's caps on an arc or helix, as path rates.
struct ArcCaps {
  double speed = std::numeric_limits<double>::infinity();  // what the axes allow, mm/s
  double accel = std::numeric_limits<double>::infinity();  // path acceleration, mm/s²
};

/// What the arc's shape and the axes give: `r_mm` the (smallest) in-plane radius, `q` and
/// `h` the in-plane and normal shares of the path speed (r/ρ and |pitch|/ρ on a helix),
/// `v_plane` the path speed the in-plane axes' velocities allow (the caller's bound along
/// its sweep), `plane` the plane axes' accelerations along the sweep, `v_normal` and `a_normal`
/// the normal axis's limits, `speed` the block's programmed path speed. The speed cap adds
/// the centripetal share of arc_centripetal_limit and the normal axis; the tangential
/// acceleration is what the plane has left at the top speed the block can run at (feed override
/// included; arc_plane_tangential_accel), the normal axis taking its projected share.
inline ArcCaps arc_caps(double r_mm, double q, double h, double v_plane, const ArcPlane& plane, double v_normal,
                        double a_normal, double speed) {
  ArcCaps c;
  if (q > 1e-12) {
    c.speed = std::min(c.speed, v_plane);
    c.speed = std::min(c.speed, std::sqrt(kArcCentripetalShare * arc_centripetal_limit(plane) * r_mm) / q);
  }
  if (h > 1e-12) c.speed = std::min(c.speed, v_normal / h);
  if (q > 1e-12) {
    const double v_top = std::min(c.speed, kArcMaxFeedOverride * std::min(speed, c.speed));
    const double vp = v_top * q;
    c.accel = r_mm > 0.0 ? arc_plane_tangential_accel(plane, vp * vp / r_mm) / q : std::min(plane.a1, plane.a2) / q;
  }
  if (h > 1e-12) c.accel = std::min(c.accel, a_normal / h);
  return c;
}

}  // namespace pcnc
