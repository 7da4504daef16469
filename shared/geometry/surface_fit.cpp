// surface_fit.cpp — the seed's grid interpolation and fairing (see surface_fit.hpp), solved
// with Eigen.
#include "geometry/surface_fit.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>

namespace pcnc {
namespace {

// Eq. 10 along one line of points `n` long: pt(k) gives its k-th point.
bool line_params(int n, const std::function<const Vec3&(int)>& pt, double e, std::vector<double>& out) {
  out.assign(static_cast<std::size_t>(n), 0.0);
  double total = 0.0;
  for (int k = 1; k < n; ++k) {
    const double d = norm(pt(k) - pt(k - 1));
    const double w = d > 0.0 ? std::pow(d, e) : 0.0;
    total += w;
    out[static_cast<std::size_t>(k)] = total;
  }
  if (!(total > 0.0)) return false;
  for (double& x : out) x /= total;
  out.back() = 1.0;
  return true;
}

std::vector<double> averaged(int n, int lines, const std::function<const Vec3&(int, int)>& pt, double e) {
  std::vector<double> sum(static_cast<std::size_t>(n), 0.0), one;
  int used = 0;
  for (int l = 0; l < lines; ++l) {
    if (!line_params(n, [&](int k) -> const Vec3& { return pt(l, k); }, e, one)) continue;
    for (int k = 0; k < n; ++k) sum[static_cast<std::size_t>(k)] += one[static_cast<std::size_t>(k)];
    ++used;
  }
  if (used == 0) return {};
  for (double& x : sum) x /= used;
  sum.front() = 0.0;
  sum.back() = 1.0;
  return sum;
}

// The collocation matrix N(r, c) = N_c(params[r]).
Eigen::MatrixXd collocation(const std::vector<double>& params, const std::vector<double>& knots, int degree) {
  const int n = static_cast<int>(params.size());
  Eigen::MatrixXd m = Eigen::MatrixXd::Zero(n, n);
  double b[3][kMaxSurfaceDegree + 1];
  for (int r = 0; r < n; ++r) {
    const int span = bspline_basis(knots, degree, n, params[static_cast<std::size_t>(r)], 0, b);
    for (int k = 0; k <= degree; ++k) m(r, span - degree + k) = b[0][k];
  }
  return m;
}

// Solves N X = B; false when N is (numerically) singular.
bool solve(const Eigen::MatrixXd& n, const Eigen::MatrixXd& b, Eigen::MatrixXd& x) {
  Eigen::PartialPivLU<Eigen::MatrixXd> lu(n);
  x = lu.solve(b);
  if (!x.allFinite()) return false;
  const double scale = std::max(1.0, b.cwiseAbs().maxCoeff());
  return (n * x - b).cwiseAbs().maxCoeff() <= 1e-9 * scale;
}

bool strictly_increasing(const std::vector<double>& v) {
  for (std::size_t i = 1; i < v.size(); ++i)
    if (!(v[i] > v[i - 1] + 1e-12)) return false;
  return true;
}

}  // namespace

std::vector<double> grid_params_u(const PointGrid& g, double e) {
  return averaged(g.cols, g.rows, [&](int row, int c) -> const Vec3& { return g.at(c, row); }, e);
}

std::vector<double> grid_params_v(const PointGrid& g, double e) {
  return averaged(g.rows, g.cols, [&](int col, int r) -> const Vec3& { return g.at(col, r); }, e);
}

std::vector<double> averaging_knots(const std::vector<double>& params, int degree) {
  const int n = static_cast<int>(params.size()) - 1;  // n + 1 points
  std::vector<double> k(static_cast<std::size_t>(n + degree + 2), 0.0);
  for (int i = 0; i <= degree; ++i) k[static_cast<std::size_t>(n + 1 + i)] = 1.0;
  for (int j = 1; j <= n - degree; ++j) {
    double s = 0.0;
    for (int i = j; i < j + degree; ++i) s += params[static_cast<std::size_t>(i)];
    k[static_cast<std::size_t>(j + degree)] = s / degree;
  }
  return k;
}

SurfaceFit interpolate_grid(const PointGrid& g, int degree, double e) {
  SurfaceFit f;
  if (degree < 1 || degree > kMaxSurfaceDegree) {
    f.error = "degree " + std::to_string(degree) + " is outside 1.." + std::to_string(kMaxSurfaceDegree);
    return f;
  }
  if (!(e >= 0.0 && e <= 1.0)) {
    f.error = "the parameter exponent e must lie in [0, 1]";
    return f;
  }
  if (g.cols < degree + 1 || g.rows < degree + 1 ||
      g.points.size() != static_cast<std::size_t>(g.cols) * static_cast<std::size_t>(g.rows)) {
    f.error = "a " + std::to_string(g.cols) + " x " + std::to_string(g.rows) + " grid is too small for degree " +
              std::to_string(degree) + ": at least " + std::to_string(degree + 1) + " x " + std::to_string(degree + 1) +
              " points are needed";
    return f;
  }
  for (const Vec3& p : g.points) {
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) {
      f.error = "a point is not finite";
      return f;
    }
  }
  f.params_u = grid_params_u(g, e);
  f.params_v = grid_params_v(g, e);
  if (!strictly_increasing(f.params_u) || !strictly_increasing(f.params_v)) {
    f.error = "the grid's points coincide: two columns or two rows get the same parameter";
    return f;
  }
  BSplineSurface& s = f.surface;
  s.degree = degree;
  s.count_u = g.cols;
  s.count_v = g.rows;
  s.e = e;
  s.knots_u = averaging_knots(f.params_u, degree);
  s.knots_v = averaging_knots(f.params_v, degree);
  // Through the rows: Nu R = Q, one right-hand side per row and coordinate.
  const int nu = g.cols, nv = g.rows;
  Eigen::MatrixXd q(nu, 3 * nv), r, pv;
  for (int row = 0; row < nv; ++row)
    for (int c = 0; c < nu; ++c)
      for (int k = 0; k < 3; ++k) q(c, 3 * row + k) = g.at(c, row)[static_cast<std::size_t>(k)];
  if (!solve(collocation(f.params_u, s.knots_u, degree), q, r)) {
    f.error = "the interpolation along u is singular";
    return f;
  }
  // ... then through the columns: Nv P = R.
  Eigen::MatrixXd rt(nv, 3 * nu);
  for (int row = 0; row < nv; ++row)
    for (int c = 0; c < nu; ++c)
      for (int k = 0; k < 3; ++k) rt(row, 3 * c + k) = r(c, 3 * row + k);
  if (!solve(collocation(f.params_v, s.knots_v, degree), rt, pv)) {
    f.error = "the interpolation along v is singular";
    return f;
  }
  s.points.resize(static_cast<std::size_t>(nu) * static_cast<std::size_t>(nv));
  for (int row = 0; row < nv; ++row)
    for (int c = 0; c < nu; ++c)
      s.points[static_cast<std::size_t>(row * nu + c)] = {pv(row, 3 * c), pv(row, 3 * c + 1), pv(row, 3 * c + 2)};
  return f;
}

double fairness(const SurfaceFit& fit) {
  double sum = 0.0;
  for (double v : fit.params_v) {
    for (double u : fit.params_u) {
      const NormalCurvatures k = normal_curvatures(surface_eval(fit.surface, u, v));
      sum += k.ku * k.ku + k.kv * k.kv;
    }
  }
  return sum;
}

FairFit fair_fit(const PointGrid& g, int degree) {
  FairFit best;
  best.fairness = std::numeric_limits<double>::infinity();
  int fits = 0;
  auto f_of = [&](double e) {
    SurfaceFit f = interpolate_grid(g, degree, e);
    ++fits;
    const double F = f.ok() ? fairness(f) : std::numeric_limits<double>::infinity();
    if (f.ok() && F < best.fairness) {
      best.fit = std::move(f);
      best.e = e;
      best.fairness = F;
    } else if (!f.ok() && best.fit.error.empty() && best.fit.surface.points.empty()) {
      best.fit.error = f.error;
    }
    return F;
  };
  constexpr double kStep = 0.05;
  double e_scan = 0.0, f_scan = std::numeric_limits<double>::infinity();
  for (int i = 0; i <= 20; ++i) {
    const double e = i * kStep;
    const double F = f_of(e);
    if (F < f_scan) f_scan = F, e_scan = e;
  }
  if (std::isfinite(f_scan)) {
    // golden section on [e_scan - step, e_scan + step] within [0, 1]
    const double g_ratio = 0.5 * (std::sqrt(5.0) - 1.0);
    double a = std::max(0.0, e_scan - kStep), b = std::min(1.0, e_scan + kStep);
    double c = b - g_ratio * (b - a), d = a + g_ratio * (b - a);
    double fc = f_of(c), fd = f_of(d);
    while (b - a > 1e-4) {
      if (fc < fd) {
        b = d, d = c, fd = fc;
        c = b - g_ratio * (b - a);
        fc = f_of(c);
      } else {
        a = c, c = d, fc = fd;
        d = a + g_ratio * (b - a);
        fd = f_of(d);
      }
    }
  }
  best.fits = fits;
  return best;
}

}  // namespace pcnc
