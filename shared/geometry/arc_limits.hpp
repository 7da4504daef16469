// arc_limits.hpp — how an arc shares its plane axes' acceleration between the centripetal
// part v²/r and the tangential part. The host's preprocessor plans every arc block with it
// and the rt's executor re-derives the same caps from its own config (it trusts no block).
//
// The in-plane acceleration vector is a_t·T + (v²/r)·N; keeping its magnitude within the
// smaller plane axis's limit a keeps every in-plane axis within it. The speed cap keeps the
// centripetal part within kArcCentripetalShare·a; the tangential part gets what is left at
// the fastest speed the block can ever run (feed override included):
//   a_t = sqrt(a² − (v_top²/r)²) >= sqrt(1 − share²)·a   (0.87·a for share 0.5).
// A slow arc on a large radius thus brakes and accelerates almost at the axis limit, where
// a fixed split would leave half of it unused.
#pragma once

#include <algorithm>
#include <cmath>

namespace pcnc {

/// Share of the smaller in-plane axis acceleration an arc may use for centripetal acceleration.
constexpr double kArcCentripetalShare = 0.5;
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

}  // namespace pcnc
