// sphere_fit.hpp — least-squares primitives through probed points (issue 15 item 3): the
// sphere a probe calibration touches (centre and radius: an algebraic fit, then Gauss–Newton
// on the geometric distances) and the plane through a handful of neighbours (a local surface
// normal). Each fit reports its residuals. Pure mathematics: std, Eigen in the .cpp only.
#pragma once

#include <string>
#include <vector>

#include "geometry/vec3.hpp"

namespace pcnc {

struct SphereFit {
  Vec3 centre{};
  double radius = 0.0;
  std::vector<double> residuals;  // |p_i - centre| - radius, mm, in the points' order
  double rms = 0.0;               // of the residuals, mm
  double max_abs = 0.0;           // largest |residual|, mm
  int iterations = 0;             // Gauss–Newton steps taken
  std::string error;              // why there is no sphere (too few or coplanar points)
  bool ok() const { return error.empty(); }
};

/// The sphere minimising the sum of squared geometric distances Σ(|p_i − c| − r)².
/// Start: the algebraic fit |p|² = 2 c·p + k (linear least squares, r² = k + |c|²); then
/// Gauss–Newton on (c, r) until the step is below 1e-12 mm (at most 50 steps). Needs at least
/// 4 points that do not lie on one plane or line.
SphereFit fit_sphere(const std::vector<Vec3>& points);

struct PlaneFit {
  Vec3 point{};                   // the points' centroid, on the plane
  Vec3 normal{0.0, 0.0, 1.0};     // unit; oriented with normal[2] >= 0 (up, for a table)
  std::vector<double> residuals;  // signed distance (p_i - point)·normal, mm
  double rms = 0.0;
  double max_abs = 0.0;
  std::string error;              // fewer than 3 points, or all on one line
  bool ok() const { return error.empty(); }
};

/// The total-least-squares plane: through the centroid, normal along the eigenvector of the
/// points' scatter matrix with the smallest eigenvalue.
PlaneFit fit_plane(const std::vector<Vec3>& points);

}  // namespace pcnc
