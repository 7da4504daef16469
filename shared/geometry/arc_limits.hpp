// arc_limits.hpp — how an arc shares its plane axes' acceleration between the centripetal
// part v²/r and the tangential part. The host's preprocessor plans every arc block with it
// and the rt's executor re-derives the same caps from its own config (it trusts no block).
//
// The in-plane acceleration vector is a_t·T + (v²/r)·N; keeping its magnitude within the
// smaller plane axis's limit a keeps every in-plane axis within it. The speed cap keeps the
// centripetal part within kArcCentripetalShare·a; the tangential part gets what is left at
// the fastest speed the block can ever run (feed override included):
//   a_t = sqrt(a² − (v_top²/r)²) >= sqrt(1 − share²)·a   (0.71·a for share 0.7).
// The share was 0.5 until 2026-11-26; 0.7 was chosen by tools/bench_surfacing.sh (LHchips4 /
// blur_torus: 0.5 83.0 / 85.0 s, 0.7 82.1 / 83.0 s, 0.8 82.7 / 82.8 s; docs/smoothing.md).
// A slow arc on a large radius thus brakes and accelerates almost at the axis limit, where
// a fixed split would leave half of it unused.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

namespace pcnc {

/// Share of the smaller in-plane axis acceleration an arc may use for centripetal acceleration.
constexpr double kArcCentripetalShare = 0.7;
/// The largest feed override (FeedOverride::kMax): the top speed an arc block can be run at
/// is min(what the axes allow, this times its programmed speed).
constexpr double kArcMaxFeedOverride = 2.0;

/// Tangential acceleration in the plane (mm/s²) on an arc of radius `r_mm` whose in-plane
/// speed never exceeds `v_top_plane_mm_s`, for a plane axis limit `a_plane`.
inline double arc_tangential_accel(double a_plane, double r_mm, double v_top_plane_mm_s) {
  if (!(r_mm > 0.0)) return a_plane;
  const double a_n = std::min(v_top_plane_mm_s * v_top_plane_mm_s / r_mm, kArcCentripetalShare * a_plane);
  return std::sqrt(a_plane * a_plane - a_n * a_n);
}

/// The machine's caps on an arc or helix, as path rates.
struct ArcCaps {
  double speed = std::numeric_limits<double>::infinity();  // what the axes allow, mm/s
  double accel = std::numeric_limits<double>::infinity();  // path acceleration, mm/s²
};

/// What the arc's shape and the axes give: `r_mm` the (smallest) in-plane radius, `q` and
/// `h` the in-plane and normal shares of the path speed (r/ρ and |pitch|/ρ on a helix),
/// `v_plane` the path speed the in-plane axes' velocities allow (the caller's bound along
/// its sweep), `a_plane` the smaller in-plane axis acceleration, `v_normal` and `a_normal`
/// the normal axis's limits, `speed` the block's programmed path speed. The speed cap adds
/// the centripetal share and the normal axis; the tangential acceleration is what the plane
/// has left at the top speed the block can run at (feed override included), the normal axis
/// taking its projected share.
inline ArcCaps arc_caps(double r_mm, double q, double h, double v_plane, double a_plane, double v_normal,
                        double a_normal, double speed) {
  ArcCaps c;
  if (q > 1e-12) {
    c.speed = std::min(c.speed, v_plane);
    c.speed = std::min(c.speed, std::sqrt(kArcCentripetalShare * a_plane * r_mm) / q);
  }
  if (h > 1e-12) c.speed = std::min(c.speed, v_normal / h);
  if (q > 1e-12) {
    const double v_top = std::min(c.speed, kArcMaxFeedOverride * std::min(speed, c.speed));
    c.accel = arc_tangential_accel(a_plane, r_mm, v_top * q) / q;
  }
  if (h > 1e-12) c.accel = std::min(c.accel, a_normal / h);
  return c;
}

}  // namespace pcnc
