// nurbs_circles.hpp — the exact circles of the NURBS tests: rational quadratic curves with
// weights 1 and 1/sqrt(2) (the seed paper's construction), centred anywhere in the XY plane.
#pragma once

#include <cmath>

#include "geometry/nurbs.hpp"

namespace pcnc::test {

inline const double kCircleWeight = 1.0 / std::sqrt(2.0);

/// Quarter circle of radius r around c, from +X to +Y (counter-clockwise).
inline NurbsCurve quarter_circle(double r, Vec3 c = {0, 0, 0}) {
  NurbsCurve q;
  q.degree = 2;
  q.points = {c + Vec3{r, 0, 0}, c + Vec3{r, r, 0}, c + Vec3{0, r, 0}};
  q.weights = {1, kCircleWeight, 1};
  q.knots = {0, 0, 0, 1, 1, 1};
  return q;
}

/// Full circle of radius r around c, counter-clockwise from +X: four quarters, 9 points.
inline NurbsCurve full_circle(double r, Vec3 c = {0, 0, 0}) {
  NurbsCurve q;
  q.degree = 2;
  const double xy[9][2] = {{1, 0}, {1, 1}, {0, 1}, {-1, 1}, {-1, 0}, {-1, -1}, {0, -1}, {1, -1}, {1, 0}};
  for (int i = 0; i < 9; ++i) {
    q.points.push_back(c + Vec3{r * xy[i][0], r * xy[i][1], 0.0});
    q.weights.push_back(i % 2 == 1 ? kCircleWeight : 1.0);
  }
  q.knots = {0, 0, 0, 1, 1, 2, 2, 3, 3, 4, 4, 4};
  return q;
}

}  // namespace pcnc::test
