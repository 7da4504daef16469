// surface_interp.hpp — what other senders do with a probe grid ("autolevel"), the baselines
// the fitted B-spline surface is measured against: bilinear interpolation (bCNC, CNCjs) and
// Catmull–Rom bicubic interpolation (Candle) of the probed heights over a rectilinear grid.
//
// The grid is a PointGrid (surface_fit.hpp) whose columns share an x and rows share a y (each
// taken as the mean over the column or row). Outside the grid the height is held at the edge.
// At the border Catmull–Rom uses a mirrored neighbour (2 P0 - P1), as Candle does.
#pragma once

#include <vector>

#include "geometry/surface_fit.hpp"

namespace pcnc {

class GridHeights {
 public:
  explicit GridHeights(const PointGrid& g);

  double bilinear(double x, double y) const;
  double catmull_rom(double x, double y) const;

 private:
  // the cell holding a coordinate and the fraction across it
  static void locate(const std::vector<double>& axis, double t, int& cell, double& f);
  double z(int c, int r) const;

  int cols_, rows_;
  std::vector<double> xs_, ys_, z_;
};

}  // namespace pcnc
