// hermite_curve.cpp — Ferguson segments: coefficients, jet, piecewise evaluation. See
// hermite_curve.hpp.
#include "geometry/hermite_curve.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace pcnc {

HermiteCoefficients hermite_coefficients(const HermiteSegment& s) {
  // Rows of M (eq. 12) read bottom up: constant, linear, quadratic, cubic.
  HermiteCoefficients c;
  c.a0 = s.p0;
  c.a1 = s.t0;
  c.a2 = -3.0 * s.p0 + 3.0 * s.p1 - 2.0 * s.t0 - s.t1;
  c.a3 = 2.0 * s.p0 - 2.0 * s.p1 + s.t0 + s.t1;
  return c;
}

CurveJet hermite_jet(const HermiteSegment& s, double u) {
  const HermiteCoefficients c = hermite_coefficients(s);
  CurveJet j;
  j.p = c.a0 + u * (c.a1 + u * (c.a2 + u * c.a3));
  j.d1 = c.a1 + u * (2.0 * c.a2 + 3.0 * u * c.a3);
  j.d2 = 2.0 * c.a2 + 6.0 * u * c.a3;
  j.d3 = 6.0 * c.a3;
  return j;
}

CurveJet hermite_jet(const HermiteView& c, double u) {
  if (c.count <= 0) return {};
  u = std::clamp(u, 0.0, c.u_max());
  const int i = std::min(static_cast<int>(std::floor(u)), c.count - 1);
  return hermite_jet(c.segments[i], u - i);
}

std::vector<HermiteSegment> hermite_through(const std::vector<Vec3>& points, const std::vector<Vec3>& tangents) {
  if (points.size() < 2 || points.size() != tangents.size())
    throw std::invalid_argument("hermite_through: need >= 2 points and one tangent per point");
  std::vector<HermiteSegment> out;
  for (std::size_t i = 0; i + 1 < points.size(); ++i)
    out.push_back({points[i], points[i + 1], tangents[i], tangents[i + 1]});
  return out;
}

std::vector<Vec3> catmull_rom_tangents(const std::vector<Vec3>& points) {
  const std::size_t n = points.size();
  if (n < 2) throw std::invalid_argument("catmull_rom_tangents: need >= 2 points");
  std::vector<Vec3> t(n);
  t[0] = points[1] - points[0];
  t[n - 1] = points[n - 1] - points[n - 2];
  for (std::size_t i = 1; i + 1 < n; ++i) t[i] = 0.5 * (points[i + 1] - points[i - 1]);
  return t;
}

}  // namespace pcnc
