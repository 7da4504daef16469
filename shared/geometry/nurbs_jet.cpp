// nurbs_jet.cpp — third-order NURBS evaluation. See nurbs_jet.hpp.
//
// The non-zero basis functions of every degree 0..p are built by the Cox–de Boor recurrence;
// the k-th derivative of the degree-p functions follows from the (k-1)-th derivative of the
// degree-(p-1) functions by N'_{i,d} = d (N_{i,d-1}/(t_{i+d}-t_i) - N_{i+1,d-1}/(t_{i+d+1}-t_{i+1})).
#include "geometry/nurbs_jet.hpp"

#include <algorithm>
#include <array>

namespace pcnc {
namespace {

constexpr int kJetOrder = kMaxNurbsDegree + 1;
using Row = std::array<double, kJetOrder>;

inline double ratio(double a, double b) { return b != 0.0 ? a / b : 0.0; }

// d/du of the degree-d functions N_{span-d+j,d}, j = 0..d, from `lower`, the degree-(d-1)
// values (or derivatives) N_{span-d+1+j,d-1}, j = 0..d-1.
Row raise(const double* t, int span, int d, const Row& lower) {
  Row out{};
  for (int j = 0; j <= d; ++j) {
    const int i = span - d + j;
    double v = 0.0;
    if (j >= 1) v += ratio(lower[j - 1], t[i + d] - t[i]);
    if (j <= d - 1) v -= ratio(lower[j], t[i + d + 1] - t[i + 1]);
    out[j] = d * v;
  }
  return out;
}

}  // namespace

CurveJet nurbs_jet(const NurbsView& c, double u) {
  u = std::clamp(u, c.u_min(), c.u_max());
  const int p = c.degree;
  const int span = find_span(c, u);
  const double* t = c.knots;

  // table[d][j] = N_{span-d+j, d}(u).
  std::array<Row, kJetOrder> table{};
  table[0][0] = 1.0;
  for (int d = 1; d <= p; ++d) {
    for (int j = 0; j <= d; ++j) {
      const int i = span - d + j;
      double v = 0.0;
      if (j >= 1) v += ratio(u - t[i], t[i + d] - t[i]) * table[d - 1][j - 1];
      if (j <= d - 1) v += ratio(t[i + d + 1] - u, t[i + d + 1] - t[i + 1]) * table[d - 1][j];
      table[d][j] = v;
    }
  }
  // deriv[k] = k-th derivative of the degree-p functions, k = 0..3 (zero above p).
  std::array<Row, 4> deriv{};
  deriv[0] = table[p];
  for (int k = 1; k <= std::min(3, p); ++k) {
    Row r = table[p - k];  // degree p-k values
    for (int d = p - k + 1; d <= p; ++d) r = raise(t, span, d, r);
    deriv[k] = r;
  }
  // Homogeneous curve A = sum N w P and weight W = sum N w with their derivatives.
  std::array<Vec3, 4> a{};
  std::array<double, 4> w{};
  for (int j = 0; j <= p; ++j) {
    const int i = span - p + j;
    const Vec3 wp = c.weights[i] * c.points[i];
    for (int k = 0; k < 4; ++k) {
      a[k] = a[k] + deriv[k][j] * wp;
      w[k] += deriv[k][j] * c.weights[i];
    }
  }
  // C = A / W: A^(k) = sum_i binom(k,i) W^(i) C^(k-i).
  CurveJet e;
  const double inv = 1.0 / w[0];
  e.p = inv * a[0];
  e.d1 = inv * (a[1] - w[1] * e.p);
  e.d2 = inv * (a[2] - 2.0 * w[1] * e.d1 - w[2] * e.p);
  e.d3 = inv * (a[3] - 3.0 * w[1] * e.d2 - 3.0 * w[2] * e.d1 - w[3] * e.p);
  return e;
}

}  // namespace pcnc
