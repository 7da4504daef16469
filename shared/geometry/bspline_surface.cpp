// bspline_surface.cpp — evaluation, normal, normal curvatures and the height query of the
// B-spline surface (see bspline_surface.hpp). The basis is Cox–de Boor with derivatives
// (The NURBS Book, A2.2/A2.3), on fixed arrays.
#include "geometry/bspline_surface.hpp"

#include <algorithm>
#include <cmath>

namespace pcnc {
namespace {

constexpr int kM = kMaxSurfaceDegree + 1;

int find_span(const std::vector<double>& knots, int degree, int count, double t) {
  const int n = count - 1;
  if (t >= knots[static_cast<std::size_t>(n + 1)]) {
    // the last non-empty span
    int s = n;
    while (s > degree && knots[static_cast<std::size_t>(s)] >= knots[static_cast<std::size_t>(n + 1)]) --s;
    return s;
  }
  if (t <= knots[static_cast<std::size_t>(degree)]) {
    int s = degree;
    while (s < n && knots[static_cast<std::size_t>(s + 1)] <= knots[static_cast<std::size_t>(degree)]) ++s;
    return s;
  }
  int low = degree, high = n + 1;
  int mid = (low + high) / 2;
  while (t < knots[static_cast<std::size_t>(mid)] || t >= knots[static_cast<std::size_t>(mid + 1)]) {
    if (t < knots[static_cast<std::size_t>(mid)]) {
      high = mid;
    } else {
      low = mid;
    }
    mid = (low + high) / 2;
  }
  return mid;
}

// The surface and its derivatives up to order `nd` (1 or 2).
void eval_to(const BSplineSurface& s, double u, double v, int nd, SurfaceEval& out) {
  double bu[3][kM], bv[3][kM];
  const int p = s.degree;
  const int su = bspline_basis(s.knots_u, p, s.count_u, u, nd, bu);
  const int sv = bspline_basis(s.knots_v, p, s.count_v, v, nd, bv);
  // temp[k][l]: the k-th u-derivative of row (sv - p + l), combined over u
  Vec3 temp[3][kM];
  for (int l = 0; l <= p; ++l) {
    const int j = sv - p + l;
    Vec3 t0{}, t1{}, t2{};
    for (int r = 0; r <= p; ++r) {
      const Vec3& q = s.point(su - p + r, j);
      t0 = t0 + bu[0][r] * q;
      t1 = t1 + bu[1][r] * q;
      if (nd >= 2) t2 = t2 + bu[2][r] * q;
    }
    temp[0][l] = t0;
    temp[1][l] = t1;
    temp[2][l] = t2;
  }
  out = SurfaceEval{};
  for (int l = 0; l <= p; ++l) {
    out.p = out.p + bv[0][l] * temp[0][l];
    out.su = out.su + bv[0][l] * temp[1][l];
    out.sv = out.sv + bv[1][l] * temp[0][l];
    if (nd >= 2) {
      out.suu = out.suu + bv[0][l] * temp[2][l];
      out.suv = out.suv + bv[1][l] * temp[1][l];
      out.svv = out.svv + bv[2][l] * temp[0][l];
    }
  }
}

bool finite(const Vec3& p) { return std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]); }

std::string check_knots(const std::vector<double>& k, int degree, int count, const char* name) {
  const std::string n(name);
  if (count < degree + 1)
    return n + ": " + std::to_string(count) + " control points, a degree-" + std::to_string(degree) +
           " surface needs at least " + std::to_string(degree + 1);
  if (k.size() != static_cast<std::size_t>(count + degree + 1))
    return n + ": " + std::to_string(k.size()) + " knots, expected " + std::to_string(count + degree + 1) +
           " (control points + degree + 1)";
  for (std::size_t i = 0; i < k.size(); ++i) {
    if (!std::isfinite(k[i])) return n + ": knot " + std::to_string(i) + " is not a finite number";
    if (i > 0 && k[i] < k[i - 1]) return n + ": knot " + std::to_string(i) + " decreases";
  }
  const auto p = static_cast<std::size_t>(degree);
  for (std::size_t i = 1; i <= p; ++i) {
    if (k[i] != k[0]) return n + ": not clamped: the first " + std::to_string(p + 1) + " knots must be equal";
    if (k[k.size() - 1 - i] != k.back())
      return n + ": not clamped: the last " + std::to_string(p + 1) + " knots must be equal";
  }
  if (!(k[p] < k[static_cast<std::size_t>(count)])) return n + ": the parameter domain is empty";
  return {};
}

}  // namespace

std::string validate(const BSplineSurface& s) {
  if (s.degree < 1 || s.degree > kMaxSurfaceDegree)
    return "degree: " + std::to_string(s.degree) + " is outside 1.." + std::to_string(kMaxSurfaceDegree);
  if (auto w = check_knots(s.knots_u, s.degree, s.count_u, "knots_u"); !w.empty()) return w;
  if (auto w = check_knots(s.knots_v, s.degree, s.count_v, "knots_v"); !w.empty()) return w;
  if (s.points.size() != static_cast<std::size_t>(s.count_u) * static_cast<std::size_t>(s.count_v))
    return "control_points: " + std::to_string(s.points.size()) + " points, expected " + std::to_string(s.count_u) + " x " +
           std::to_string(s.count_v);
  for (std::size_t i = 0; i < s.points.size(); ++i)
    if (!finite(s.points[i])) return "control_points: point " + std::to_string(i) + " is not finite";
  if (!std::isfinite(s.e)) return "e: not a finite number";
  return {};
}

int bspline_basis(const std::vector<double>& U, int p, int count, double t, int max_deriv,
                  double ders[3][kMaxSurfaceDegree + 1]) {
  t = std::clamp(t, U[static_cast<std::size_t>(p)], U[static_cast<std::size_t>(count)]);
  const int span = find_span(U, p, count, t);
  double ndu[kM][kM], left[kM], right[kM], a[2][kM];
  ndu[0][0] = 1.0;
  for (int j = 1; j <= p; ++j) {
    left[j] = t - U[static_cast<std::size_t>(span + 1 - j)];
    right[j] = U[static_cast<std::size_t>(span + j)] - t;
    double saved = 0.0;
    for (int r = 0; r < j; ++r) {
      ndu[j][r] = right[r + 1] + left[j - r];
      const double temp = ndu[r][j - 1] / ndu[j][r];
      ndu[r][j] = saved + right[r + 1] * temp;
      saved = left[j - r] * temp;
    }
    ndu[j][j] = saved;
  }
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j <= p; ++j) ders[k][j] = 0.0;
  for (int j = 0; j <= p; ++j) ders[0][j] = ndu[j][p];
  const int n = std::min(std::clamp(max_deriv, 0, 2), p);
  for (int r = 0; r <= p; ++r) {
    int s1 = 0, s2 = 1;
    a[0][0] = 1.0;
    for (int k = 1; k <= n; ++k) {
      double d = 0.0;
      const int rk = r - k, pk = p - k;
      if (r >= k) {
        a[s2][0] = a[s1][0] / ndu[pk + 1][rk];
        d = a[s2][0] * ndu[rk][pk];
      }
      const int j1 = rk >= -1 ? 1 : -rk;
      const int j2 = (r - 1 <= pk) ? k - 1 : p - r;
      for (int j = j1; j <= j2; ++j) {
        a[s2][j] = (a[s1][j] - a[s1][j - 1]) / ndu[pk + 1][rk + j];
        d += a[s2][j] * ndu[rk + j][pk];
      }
      if (r <= pk) {
        a[s2][k] = -a[s1][k - 1] / ndu[pk + 1][r];
        d += a[s2][k] * ndu[r][pk];
      }
      ders[k][r] = d;
      std::swap(s1, s2);
    }
  }
  double f = p;
  for (int k = 1; k <= n; ++k) {
    for (int j = 0; j <= p; ++j) ders[k][j] *= f;
    f *= (p - k);
  }
  return span;
}

SurfaceEval surface_eval(const BSplineSurface& s, double u, double v) {
  SurfaceEval e;
  eval_to(s, u, v, 2, e);
  return e;
}

Vec3 surface_point(const BSplineSurface& s, double u, double v) {
  double bu[3][kM], bv[3][kM];
  const int p = s.degree;
  const int su = bspline_basis(s.knots_u, p, s.count_u, u, 0, bu);
  const int sv = bspline_basis(s.knots_v, p, s.count_v, v, 0, bv);
  Vec3 out{};
  for (int l = 0; l <= p; ++l) {
    Vec3 row{};
    for (int r = 0; r <= p; ++r) row = row + bu[0][r] * s.point(su - p + r, sv - p + l);
    out = out + bv[0][l] * row;
  }
  return out;
}

Vec3 surface_normal(const SurfaceEval& e) { return normalized(cross(e.su, e.sv)); }

NormalCurvatures normal_curvatures(const SurfaceEval& e) {
  const Vec3 n = surface_normal(e);
  const double eu = dot(e.su, e.su), ev = dot(e.sv, e.sv);
  NormalCurvatures k;
  if (eu > 0.0) k.ku = dot(e.suu, n) / eu;
  if (ev > 0.0) k.kv = dot(e.svv, n) / ev;
  return k;
}

SurfaceHeight surface_height(const BSplineSurface& s, double x, double y) {
  const double u0 = s.u_min(), u1 = s.u_max(), v0 = s.v_min(), v1 = s.v_max();
  // First guess: the parallelogram of three corners (a measured grid is nearly one).
  const Vec3& c00 = s.point(0, 0);
  const Vec3 a = s.point(s.count_u - 1, 0) - c00, b = s.point(0, s.count_v - 1) - c00;
  const double det0 = a[0] * b[1] - a[1] * b[0];
  double fu = 0.5, fv = 0.5;
  if (std::fabs(det0) > 1e-12) {
    fu = ((x - c00[0]) * b[1] - (y - c00[1]) * b[0]) / det0;
    fv = (a[0] * (y - c00[1]) - a[1] * (x - c00[0])) / det0;
  }
  double u = std::clamp(u0 + fu * (u1 - u0), u0, u1), v = std::clamp(v0 + fv * (v1 - v0), v0, v1);
  SurfaceEval e;
  double residual = 0.0;
  for (int it = 0; it < 50; ++it) {
    eval_to(s, u, v, 1, e);
    const double rx = x - e.p[0], ry = y - e.p[1];
    residual = std::hypot(rx, ry);
    if (residual < 1e-10) break;
    const double det = e.su[0] * e.sv[1] - e.sv[0] * e.su[1];
    double du = 0.0, dv = 0.0;
    if (std::fabs(det) > 1e-300) {
      du = (rx * e.sv[1] - e.sv[0] * ry) / det;
      dv = (e.su[0] * ry - rx * e.su[1]) / det;
    }
    const bool u_out = (u <= u0 && du < 0.0) || (u >= u1 && du > 0.0);
    const bool v_out = (v <= v0 && dv < 0.0) || (v >= v1 && dv > 0.0);
    if (u_out && v_out) break;  // a corner holds both
    if (u_out) {                // held on a u edge: the best v along it
      const double g = e.sv[0] * e.sv[0] + e.sv[1] * e.sv[1];
      du = 0.0;
      dv = g > 0.0 ? (e.sv[0] * rx + e.sv[1] * ry) / g : 0.0;
    } else if (v_out) {
      const double g = e.su[0] * e.su[0] + e.su[1] * e.su[1];
      dv = 0.0;
      du = g > 0.0 ? (e.su[0] * rx + e.su[1] * ry) / g : 0.0;
    }
    const double nu = std::clamp(u + du, u0, u1), nv = std::clamp(v + dv, v0, v1);
    const bool still = std::fabs(nu - u) < 1e-15 && std::fabs(nv - v) < 1e-15;
    u = nu;
    v = nv;
    if (still) break;
  }
  eval_to(s, u, v, 1, e);
  residual = std::hypot(x - e.p[0], y - e.p[1]);
  return SurfaceHeight{e.p[2], u, v, residual < 1e-6};
}

}  // namespace pcnc
