// minmax_lp.cpp — min over x of max_j (a_j·x − b_j) by the simplex method. See minmax_lp.hpp.
//
// Primal: minimise t over (x, t) with a_j·x − t <= b_j. Its dual, in standard form:
// minimise Σ b_j·y_j subject to Σ y_j·a_j = 0, Σ y_j = 1, y >= 0 (4 equality rows, one column
// per row j). Phase 1 starts from four artificial columns (the identity), phase 2 keeps them
// out of the basis; the primal solution is the dual's simplex multipliers π, read from the
// artificial columns' reduced costs (−π_i): x = π_0..2, t = −π_3.
#include "geometry/minmax_lp.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>

namespace pcnc {
namespace {

constexpr int kRows = 4;
constexpr double kEps = 1e-11;

struct Tableau {
  std::size_t m = 0;                // real columns
  std::size_t cols = 0;             // m + 4 artificial
  std::vector<double> t;            // kRows x (cols + 1), the last column the right-hand side
  std::vector<double> d;            // reduced costs, cols
  std::array<std::size_t, kRows> basis{};

  double& at(int r, std::size_t c) { return t[static_cast<std::size_t>(r) * (cols + 1) + c]; }
  double rhs(int r) const { return t[static_cast<std::size_t>(r) * (cols + 1) + cols]; }

  void pivot(int r, std::size_t c) {
    const std::size_t w = cols + 1;
    double* pr = &t[static_cast<std::size_t>(r) * w];
    const double p = pr[c];
    for (std::size_t k = 0; k < w; ++k) pr[k] /= p;
    for (int i = 0; i < kRows; ++i) {
      if (i == r) continue;
      double* pi = &t[static_cast<std::size_t>(i) * w];
      const double f = pi[c];
      if (f == 0.0) continue;
      for (std::size_t k = 0; k < w; ++k) pi[k] -= f * pr[k];
    }
    const double f = d[c];
    if (f != 0.0)
      for (std::size_t k = 0; k < cols; ++k) d[k] -= f * pr[k];
    basis[static_cast<std::size_t>(r)] = c;
  }

  void price(const std::vector<double>& cost) {
    d = cost;
    for (int r = 0; r < kRows; ++r) {
      const double cb = cost[basis[static_cast<std::size_t>(r)]];
      if (cb == 0.0) continue;
      for (std::size_t k = 0; k < cols; ++k) d[k] -= cb * at(r, k);
    }
  }

  // Minimises the priced cost over columns below `enter_limit`. false: unbounded or too many steps.
  bool run(std::size_t enter_limit) {
    const std::size_t max_steps = 20000;  // 4 rows: a few hundred pivots at most in practice
    std::size_t stalled = 0;
    for (std::size_t step = 0; step < max_steps; ++step) {
      const bool bland = stalled > 50;
      std::size_t enter = cols;
      double best = -kEps;
      for (std::size_t k = 0; k < enter_limit; ++k) {
        if (d[k] < best) {
          enter = k;
          if (bland) break;
          best = d[k];
        }
      }
      if (enter == cols) return true;  // optimal
      int leave = -1;
      double ratio = 0.0;
      for (int r = 0; r < kRows; ++r) {
        const double e = at(r, enter);
        if (e <= kEps) continue;
        const double q = rhs(r) / e;
        if (leave < 0 || q < ratio - 1e-15 ||
            (q <= ratio + 1e-15 && basis[static_cast<std::size_t>(r)] < basis[static_cast<std::size_t>(leave)])) {
          leave = r;
          ratio = q;
        }
      }
      if (leave < 0) return false;  // unbounded
      stalled = ratio <= 1e-15 ? stalled + 1 : 0;
      pivot(leave, enter);
    }
    return false;
  }
};

}  // namespace

MinMaxResult minimize_max_affine(const std::vector<MinMaxRow>& rows) {
  MinMaxResult out;
  if (rows.empty()) return out;
  Tableau tb;
  tb.m = rows.size();
  tb.cols = tb.m + kRows;
  tb.t.assign(static_cast<std::size_t>(kRows) * (tb.cols + 1), 0.0);
  for (std::size_t j = 0; j < tb.m; ++j) {
    for (int i = 0; i < 3; ++i) tb.at(i, j) = rows[j].a[static_cast<std::size_t>(i)];
    tb.at(3, j) = 1.0;
  }
  for (int i = 0; i < kRows; ++i) {
    tb.at(i, tb.m + static_cast<std::size_t>(i)) = 1.0;
    tb.basis[static_cast<std::size_t>(i)] = tb.m + static_cast<std::size_t>(i);
  }
  tb.at(3, tb.cols) = 1.0;  // right-hand side (0, 0, 0, 1)

  // phase 1: drive the artificial columns to zero
  std::vector<double> cost(tb.cols, 0.0);
  for (int i = 0; i < kRows; ++i) cost[tb.m + static_cast<std::size_t>(i)] = 1.0;
  tb.price(cost);
  if (!tb.run(tb.cols)) return out;
  double infeasibility = 0.0;
  for (int r = 0; r < kRows; ++r)
    if (tb.basis[static_cast<std::size_t>(r)] >= tb.m) infeasibility += tb.rhs(r);
  if (infeasibility > 1e-9) return out;  // the primal is unbounded below
  // artificial columns left in the basis (at zero): pivot them out where a real column allows
  for (int r = 0; r < kRows; ++r) {
    if (tb.basis[static_cast<std::size_t>(r)] < tb.m) continue;
    for (std::size_t k = 0; k < tb.m; ++k) {
      if (std::abs(tb.at(r, k)) > 1e-9) {
        tb.pivot(r, k);
        break;
      }
    }
  }
  // phase 2: the dual's cost b, artificial columns never enter
  cost.assign(tb.cols, 0.0);
  for (std::size_t j = 0; j < tb.m; ++j) cost[j] = rows[j].b;
  tb.price(cost);
  if (!tb.run(tb.m)) return out;
  for (int i = 0; i < 3; ++i) out.x[static_cast<std::size_t>(i)] = -tb.d[tb.m + static_cast<std::size_t>(i)];
  double value = -1e300;
  for (const MinMaxRow& r : rows) value = std::max(value, dot(r.a, out.x) - r.b);
  out.value = value;
  out.ok = true;
  return out;
}

}  // namespace pcnc
