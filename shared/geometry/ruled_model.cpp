// ruled_model.cpp — Ferguson directrix and ruling through set points. See ruled_model.hpp.
#include "geometry/ruled_model.hpp"

#include <cmath>

#include "geometry/spherical_curve.hpp"

namespace pcnc {

RuledCurves RuledModel::curves() const {
  RuledCurves r;
  r.directrix = CurveSource::of(HermiteView{directrix.data(), static_cast<int>(directrix.size())});
  r.ruling = CurveSource::of(HermiteView{ruling.data(), static_cast<int>(ruling.size())});
  r.form = form;
  return r;
}

std::vector<Vec3> chord_derivatives(const std::vector<double>& l, const std::vector<Vec3>& f) {
  const std::size_t n = f.size();
  std::vector<Vec3> d(n);
  if (n == 2) {
    d[0] = d[1] = (1.0 / (l[1] - l[0])) * (f[1] - f[0]);
    return d;
  }
  // Derivative of the parabola through three samples, at the first, middle or last of them.
  auto three = [](double h0, double h1, const Vec3& a, const Vec3& b, const Vec3& c, int at) {
    const double s = h0 + h1;
    if (at == 0) return (-(2 * h0 + h1) / (h0 * s)) * a + (s / (h0 * h1)) * b + (-h0 / (h1 * s)) * c;
    if (at == 1) return (-h1 / (h0 * s)) * a + ((h1 - h0) / (h0 * h1)) * b + (h0 / (h1 * s)) * c;
    return (h1 / (h0 * s)) * a + (-s / (h0 * h1)) * b + ((2 * h1 + h0) / (h1 * s)) * c;
  };
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t m = i == 0 ? 1 : i == n - 1 ? n - 2 : i;  // middle of the three samples
    const int at = i == 0 ? 0 : i == n - 1 ? 2 : 1;
    d[i] = three(l[m] - l[m - 1], l[m + 1] - l[m], f[m - 1], f[m], f[m + 1], at);
  }
  return d;
}

RuledModelResult ruled_model_through(const std::vector<Vec3>& points, const std::vector<Vec3>& tool_vectors,
                                     RulingForm form) {
  RuledModelResult r;
  const std::size_t n = points.size();
  if (n < 2 || tool_vectors.size() != n) {
    r.error = "a ruled piece needs at least 2 set points and one tool vector per point";
    return r;
  }
  std::vector<double> l(n, 0.0);
  std::vector<Vec3> axes(n);
  for (std::size_t i = 0; i < n; ++i) {
    if (!(norm(tool_vectors[i]) > 0.0)) {
      r.error = "tool vector " + std::to_string(i + 1) + " is zero";
      return r;
    }
    axes[i] = normalized(tool_vectors[i]);
    if (i > 0) {
      const double chord = norm(points[i] - points[i - 1]);
      if (!(chord > 0.0)) {
        r.error = "set points " + std::to_string(i) + " and " + std::to_string(i + 1) + " coincide";
        return r;
      }
      l[i] = l[i - 1] + chord;
    }
  }
  const std::vector<Vec3> ruling = form == RulingForm::kAngles ? sphere_angles_unwrapped(axes) : axes;
  const std::vector<Vec3> dc = chord_derivatives(l, points);
  const std::vector<Vec3> dr = chord_derivatives(l, ruling);
  r.model.form = form;
  for (std::size_t i = 0; i + 1 < n; ++i) {
    const double L = l[i + 1] - l[i];
    r.model.directrix.push_back({points[i], points[i + 1], L * dc[i], L * dc[i + 1]});
    r.model.ruling.push_back({ruling[i], ruling[i + 1], L * dr[i], L * dr[i + 1]});
  }
  return r;
}

}  // namespace pcnc
