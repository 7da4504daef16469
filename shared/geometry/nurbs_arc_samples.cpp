// nurbs_arc_samples.cpp — arc lengths at many parameters (see nurbs_arc_samples.hpp).
#include "geometry/nurbs_arc_samples.hpp"

#include <cmath>

namespace pcnc {
namespace {

// 4-point Gauss–Legendre on [a, b] of the parametric speed |C'(u)|.
// [a, b] lies in the knot span `span` (tried first for each point).
double gauss4_speed(const NurbsView& c, double a, double b, int span) {
  static constexpr double kX[2] = {0.33998104358485626, 0.86113631159405258};
  static constexpr double kW[2] = {0.65214515486254614, 0.34785484513745386};
  const double mid = 0.5 * (a + b);
  const double half = 0.5 * (b - a);
  double sum = 0.0;
  for (int g = 0; g < 2; ++g) {
    Vec3 lo, hi;
    nurbs_derivative_pair(c, mid - half * kX[g], mid + half * kX[g], span, lo, hi);
    sum += kW[g] * (norm(lo) + norm(hi));
  }
  return half * sum;
}

}  // namespace

std::vector<double> nurbs_arc_lengths_at(const NurbsView& c, const std::vector<double>& us) {
  const std::size_t n = us.size();
  std::vector<double> s(n, 0.0);
  std::vector<double> piece;
  std::size_t j = 1;
  while (j < n) {
    // the stretch of intervals [us[k-1], us[k]], k = j .. e-1, inside the knot span of us[j-1]
    const int span = find_span(c, us[j - 1]);
    const double span_end = c.knots[span + 1];
    std::size_t e = j;
    while (e < n && us[e] <= span_end && us[e] >= us[e - 1]) ++e;
    if (e == j) {  // crosses a knot (or goes backwards): adaptively, on its own
      s[j] = s[j - 1] + nurbs_arc_length(c, us[j - 1], us[j]);
      ++j;
      continue;
    }
    piece.assign(e - j, 0.0);
    double sum = 0.0;
    for (std::size_t k = j; k < e; ++k) {
      piece[k - j] = us[k] > us[k - 1] ? gauss4_speed(c, us[k - 1], us[k], span) : 0.0;
      sum += piece[k - j];
    }
    const double whole = nurbs_arc_length(c, us[j - 1], us[e - 1]);
    if (sum > 0.0 && std::fabs(sum - whole) <= kArcSamplesAgreement * whole) {
      const double scale = whole / sum;
      double acc = 0.0;
      for (std::size_t k = j; k < e; ++k) {
        acc += piece[k - j] * scale;
        s[k] = s[j - 1] + acc;
      }
      s[e - 1] = s[j - 1] + whole;
    } else {
      for (std::size_t k = j; k < e; ++k) s[k] = s[k - 1] + nurbs_arc_length(c, us[k - 1], us[k]);
    }
    j = e;
  }
  return s;
}

}  // namespace pcnc
