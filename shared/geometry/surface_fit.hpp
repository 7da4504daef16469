// surface_fit.hpp — the seed paper's surface from measured points: global interpolation of
// an m x n grid by a non-uniform B-spline surface (eq. 6-10) and its fairing by the choice of
// the parameter exponent e (eq. 15).
//
//   parameters (eq. 10): within each row the chord lengths to the power e (0 <= e <= 1:
//     0 uniform, 0.5 centripetal, 1 chord length), cumulated and normalised to [0, 1], then
//     averaged over the rows (u) and over the columns (v);
//   knots (eq. 9): averaging, clamped at 0 and 1;
//   control points (eq. 7-8): [Q] = [Nu][P][Nv]^T, solved with Eigen (LU with partial
//     pivoting) through the rows, then through the columns;
//   fairness (eq. 15): F = sum over the data points of k_nu^2 + k_nv^2 (normal curvatures,
//     bspline_surface.hpp);
//   fair fit: e in [0, 1] minimising F: a scan at steps of 0.05, then golden-section search
//     on the best scan point's bracket (+-0.05) down to 1e-4.
// Pure mathematics: std, Eigen (in the .cpp only) and geometry/.
#pragma once

#include <string>
#include <vector>

#include "geometry/bspline_surface.hpp"
#include "geometry/vec3.hpp"

namespace pcnc {

/// A measured grid: `rows` rows of `cols` points, row by row (rows of constant y, y increasing;
/// x increasing within a row). Q(c, r) is column c of row r.
struct PointGrid {
  int cols = 0;
  int rows = 0;
  std::vector<Vec3> points;
  const Vec3& at(int c, int r) const { return points[static_cast<std::size_t>(r * cols + c)]; }
};

/// Eq. 10 averaged: the u parameters (one per column, 0 .. 1) from the rows, with exponent e.
/// Rows whose points all coincide are left out of the average. Empty when no row has length.
std::vector<double> grid_params_u(const PointGrid& g, double e);
/// ... the v parameters (one per row) from the columns.
std::vector<double> grid_params_v(const PointGrid& g, double e);
/// Eq. 9: clamped averaging knots for `params` (ascending, 0 .. 1) and `degree`.
std::vector<double> averaging_knots(const std::vector<double>& params, int degree);

struct SurfaceFit {
  BSplineSurface surface;
  std::vector<double> params_u;  // the data points' parameters
  std::vector<double> params_v;
  std::string error;             // why there is no surface (then surface is empty)
  bool ok() const { return error.empty(); }
};

/// The interpolating surface of degree `degree` through every point of `g`, parameters with
/// exponent `e`. Refuses grids smaller than (degree + 1) in either direction, non-finite
/// points, e outside [0, 1], and grids whose parameters coincide (singular systems).
SurfaceFit interpolate_grid(const PointGrid& g, int degree, double e);

/// Eq. 15 over the fit's data parameters.
double fairness(const SurfaceFit& fit);

struct FairFit {
  SurfaceFit fit;          // at the chosen e
  double e = 1.0;
  double fairness = 0.0;   // F at the chosen e
  int fits = 0;            // interpolations made
};
/// The fit at the e in [0, 1] that minimises F (see the file comment). On a refused grid,
/// fit.error says why.
FairFit fair_fit(const PointGrid& g, int degree);

}  // namespace pcnc
