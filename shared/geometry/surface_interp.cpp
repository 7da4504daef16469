// surface_interp.cpp — bilinear and Catmull–Rom heights over a probe grid (see the header).
#include "geometry/surface_interp.hpp"

#include <algorithm>

namespace pcnc {
namespace {

double catmull(double p0, double p1, double p2, double p3, double t) {
  return 0.5 * (2.0 * p1 + (-p0 + p2) * t + (2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3) * t * t +
                (-p0 + 3.0 * p1 - 3.0 * p2 + p3) * t * t * t);
}

}  // namespace

GridHeights::GridHeights(const PointGrid& g) : cols_(g.cols), rows_(g.rows) {
  xs_.assign(static_cast<std::size_t>(cols_), 0.0);
  ys_.assign(static_cast<std::size_t>(rows_), 0.0);
  z_.resize(g.points.size());
  for (int r = 0; r < rows_; ++r) {
    for (int c = 0; c < cols_; ++c) {
      const Vec3& p = g.at(c, r);
      xs_[static_cast<std::size_t>(c)] += p[0] / rows_;
      ys_[static_cast<std::size_t>(r)] += p[1] / cols_;
      z_[static_cast<std::size_t>(r * cols_ + c)] = p[2];
    }
  }
}

void GridHeights::locate(const std::vector<double>& axis, double t, int& cell, double& f) {
  const int n = static_cast<int>(axis.size());
  if (n < 2) {
    cell = 0;
    f = 0.0;
    return;
  }
  const auto it = std::upper_bound(axis.begin(), axis.end(), t);
  cell = std::clamp(static_cast<int>(it - axis.begin()) - 1, 0, n - 2);
  const double a = axis[static_cast<std::size_t>(cell)], b = axis[static_cast<std::size_t>(cell + 1)];
  f = b > a ? std::clamp((t - a) / (b - a), 0.0, 1.0) : 0.0;
}

double GridHeights::z(int c, int r) const {
  // beyond the border: the mirrored neighbour 2 P0 - P1
  if (c < 0) return 2.0 * z(0, r) - z(1, r);
  if (c >= cols_) return 2.0 * z(cols_ - 1, r) - z(cols_ - 2, r);
  if (r < 0) return 2.0 * z(c, 0) - z(c, 1);
  if (r >= rows_) return 2.0 * z(c, rows_ - 1) - z(c, rows_ - 2);
  return z_[static_cast<std::size_t>(r * cols_ + c)];
}

double GridHeights::bilinear(double x, double y) const {
  int c, r;
  double fx, fy;
  locate(xs_, x, c, fx);
  locate(ys_, y, r, fy);
  return (1 - fx) * (1 - fy) * z(c, r) + fx * (1 - fy) * z(c + 1, r) + (1 - fx) * fy * z(c, r + 1) +
         fx * fy * z(c + 1, r + 1);
}

double GridHeights::catmull_rom(double x, double y) const {
  int c, r;
  double fx, fy;
  locate(xs_, x, c, fx);
  locate(ys_, y, r, fy);
  double col[4];
  for (int k = 0; k < 4; ++k) {
    const int rr = r - 1 + k;
    col[k] = catmull(z(c - 1, rr), z(c, rr), z(c + 1, rr), z(c + 2, rr), fx);
  }
  return catmull(col[0], col[1], col[2], col[3], fy);
}

}  // namespace pcnc
