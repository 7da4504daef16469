// bspline_surface.hpp — the non-uniform B-spline surface as a value type (the seed paper's
// eq. 4-5, 12-13): evaluation of the point and its first and second partial derivatives, the
// unit normal, the normal curvatures along u and v, and the height z at a machine X/Y (the
// surface correction's question). Evaluation allocates nothing.
//
// Conventions: one degree p for both directions (1..kMaxSurfaceDegree), count_u control
// points along u (x, within a row of the measured grid) and count_v along v (y, the rows),
// stored row by row: points[j * count_u + i]. Clamped knot vectors with count + p + 1 knots,
// non-decreasing; the parameter domain is [knots[p], knots[count]] ([0, 1] for a fit).
// Pure mathematics: the standard library and geometry/ only.
#pragma once

#include <string>
#include <vector>

#include "geometry/vec3.hpp"

namespace pcnc {

constexpr int kMaxSurfaceDegree = 5;

struct BSplineSurface {
  int degree = 3;
  int count_u = 0;                 // control points along u (columns)
  int count_v = 0;                 // control points along v (rows)
  std::vector<double> knots_u;     // count_u + degree + 1
  std::vector<double> knots_v;     // count_v + degree + 1
  std::vector<Vec3> points;        // count_v rows of count_u, mm
  double e = 1.0;                  // the parameter exponent of the fit (eq. 10), for the record

  const Vec3& point(int i, int j) const { return points[static_cast<std::size_t>(j * count_u + i)]; }
  double u_min() const { return knots_u[static_cast<std::size_t>(degree)]; }
  double u_max() const { return knots_u[static_cast<std::size_t>(count_u)]; }
  double v_min() const { return knots_v[static_cast<std::size_t>(degree)]; }
  double v_max() const { return knots_v[static_cast<std::size_t>(count_v)]; }
};

/// One bicubic Bezier patch over [0, 1]^2 as a B-spline surface: control point (i, j) is
/// point(i, j), i along u and j along v, each 0..3.
template <class PointOf>
BSplineSurface bicubic_patch(PointOf point) {
  BSplineSurface s;
  s.degree = 3;
  s.count_u = 4;
  s.count_v = 4;
  s.knots_u = {0, 0, 0, 0, 1, 1, 1, 1};
  s.knots_v = s.knots_u;
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i) s.points.push_back(point(i, j));
  return s;
}

/// Why `s` is not a usable surface (degree, sizes, knots clamped and non-decreasing with a
/// non-empty domain, finite numbers) as "<key>: <why>" (degree, knots_u, knots_v,
/// control_points, e), or an empty string.
std::string validate(const BSplineSurface& s);

/// The B-spline basis of `degree` over `knots` (count + degree + 1 of them) at t, clamped
/// into the domain: returns the span s (knots[s] <= t < knots[s+1], the last span at the
/// end) and fills ders[k][r] = k-th derivative of N_{s-degree+r}, k = 0..max_deriv (<= 2).
int bspline_basis(const std::vector<double>& knots, int degree, int count, double t, int max_deriv,
                  double ders[3][kMaxSurfaceDegree + 1]);

/// A point of the surface and its partial derivatives.
struct SurfaceEval {
  Vec3 p{};
  Vec3 su{}, sv{};
  Vec3 suu{}, suv{}, svv{};
};

SurfaceEval surface_eval(const BSplineSurface& s, double u, double v);
Vec3 surface_point(const BSplineSurface& s, double u, double v);

/// Eq. 13: N = Su x Sv / |Su x Sv| (zero where the surface is degenerate).
Vec3 surface_normal(const SurfaceEval& e);

/// Eq. 12, the normal curvatures of the u and v parameter lines, 1/mm: k_nu = Suu.N / |Su|^2,
/// k_nv = Svv.N / |Sv|^2 (L/E and N/G of the second fundamental form). The seed prints |Pu|^3
/// in the denominator; that is not a curvature (it changes with the parameter's speed and
/// has units of 1/mm^2), so the differential-geometry definition is used (docs/surface.md).
struct NormalCurvatures {
  double ku = 0.0;
  double kv = 0.0;
};
NormalCurvatures normal_curvatures(const SurfaceEval& e);

/// The surface above a machine X/Y: the parameters (u, v) whose point has that X and Y
/// (Newton on the 2x2 Jacobian of x, y), its z, and whether X/Y lies on the surface's
/// footprint. Outside it, (u, v) are held at the domain's edge: z is the edge's height.
struct SurfaceHeight {
  double z = 0.0;
  double u = 0.0;
  double v = 0.0;
  bool inside = false;
};
SurfaceHeight surface_height(const BSplineSurface& s, double x, double y);

}  // namespace pcnc
