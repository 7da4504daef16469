// contour_error.hpp — how far the machine really is from the programmed path: the distance
// from the measured (encoder) position to the nearest point of a block's curve. Used for the
// run report's contour error, which is measured against the programmed geometry, not against
// the setpoints. Pure and allocation-free so the rt cycle can call it.
#pragma once

#include "motion/path.hpp"

namespace pcnc {

struct PathDistance {
  double distance = 0.0;  // mm
  double s = 0.0;         // path length of the nearest point on the block, mm
};

/// Nearest point of `block` (a motion block) to `p`: in closed form for lines and planar
/// arcs (also the slight spirals of CAM arcs); on helices searched by Newton's method on
/// (c(s) − p)·t(s) = 0 from `s_guess` (the setpoint's path position is a good guess: the
/// machine lags behind it by the following error), clamped to [0, length].
PathDistance distance_to_path(const PreparedBlock& block, const Vec3& p, double s_guess);

class Executor;

/// Distance from the measured position to the programmed path of the feed move in execution
/// (lines and arcs; rapids and NURBS are not measured): the nearest point of the current
/// block, or of the previous one while the axes, lagging the setpoint by up to `lag_mm`, may
/// still be on it (not when a rapid follows: leaving a cut at rapid speed is not a contour
/// error). −1 when there is no feed move to measure against.
double contour_error(const Executor& exec, const Vec3& measured, double lag_mm);

}  // namespace pcnc
