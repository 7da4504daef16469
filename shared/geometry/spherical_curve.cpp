// spherical_curve.cpp — rulings on the unit sphere. See spherical_curve.hpp.
#include "geometry/spherical_curve.hpp"

#include <algorithm>
#include <cmath>

namespace pcnc {

CurveJet sphere_point_jet(const CurveJet& angles) {
  // Each component is a product f(theta) g(phi); write the jets of cos/sin of each angle
  // (chain rule to third order) and multiply them with Leibniz' rule.
  const double th = angles.p[0], t1 = angles.d1[0], t2 = angles.d2[0], t3 = angles.d3[0];
  const double ph = angles.p[1], f1 = angles.d1[1], f2 = angles.d2[1], f3 = angles.d3[1];
  // Jet of g(x(u)) for g = cos or sin: g' = g1 x', g'' = g2 x'^2 + g1 x'', g''' = g3 x'^3 +
  // 3 g2 x' x'' + g1 x''' with g1, g2, g3 the derivatives of g.
  auto jet = [](double g0, double g1, double g2, double g3, double x1, double x2, double x3) {
    return ScalarJet{g0, g1 * x1, g2 * x1 * x1 + g1 * x2, g3 * x1 * x1 * x1 + 3.0 * g2 * x1 * x2 + g1 * x3};
  };
  const double ct = std::cos(th), st = std::sin(th), cp = std::cos(ph), sp = std::sin(ph);
  const ScalarJet cos_t = jet(ct, -st, -ct, st, t1, t2, t3);
  const ScalarJet sin_t = jet(st, ct, -st, -ct, t1, t2, t3);
  const ScalarJet cos_p = jet(cp, -sp, -cp, sp, f1, f2, f3);
  const ScalarJet sin_p = jet(sp, cp, -sp, -cp, f1, f2, f3);
  auto mul = [](const ScalarJet& a, const ScalarJet& b) {
    return ScalarJet{a.f * b.f, a.d1 * b.f + a.f * b.d1, a.d2 * b.f + 2.0 * a.d1 * b.d1 + a.f * b.d2,
                     a.d3 * b.f + 3.0 * a.d2 * b.d1 + 3.0 * a.d1 * b.d2 + a.f * b.d3};
  };
  const ScalarJet x = mul(cos_t, sin_p), y = mul(sin_t, sin_p), z = cos_p;
  return {{x.f, y.f, z.f}, {x.d1, y.d1, z.d1}, {x.d2, y.d2, z.d2}, {x.d3, y.d3, z.d3}};
}

CurveJet unit_vector_jet(const CurveJet& r) {
  // e = r / n with n = |r|: r = n e, so r' = n' e + n e', r'' = n'' e + 2 n' e' + n e'',
  // r''' = n''' e + 3 n'' e' + 3 n' e'' + n e'''. The n^(k) from n^2 = r.r.
  const double n = norm(r.p);
  const double q1 = dot(r.p, r.d1);                               // (n^2)'/2
  const double q2 = dot(r.d1, r.d1) + dot(r.p, r.d2);             // (n^2)''/2
  const double q3 = 3.0 * dot(r.d1, r.d2) + dot(r.p, r.d3);       // (n^2)'''/2
  const double n1 = q1 / n;
  const double n2 = (q2 - n1 * n1) / n;
  const double n3 = (q3 - 3.0 * n1 * n2) / n;
  CurveJet e;
  e.p = (1.0 / n) * r.p;
  e.d1 = (1.0 / n) * (r.d1 - n1 * e.p);
  e.d2 = (1.0 / n) * (r.d2 - n2 * e.p - 2.0 * n1 * e.d1);
  e.d3 = (1.0 / n) * (r.d3 - n3 * e.p - 3.0 * n2 * e.d1 - 3.0 * n1 * e.d2);
  return e;
}

Vec3 sphere_angles(const Vec3& e) {
  const double planar = std::hypot(e[0], e[1]);
  const double theta = planar > 0.0 ? std::atan2(e[1], e[0]) : 0.0;
  return {theta, std::atan2(planar, e[2]), 0.0};
}

std::vector<Vec3> sphere_angles_unwrapped(const std::vector<Vec3>& unit_vectors) {
  std::vector<Vec3> out;
  for (const Vec3& e : unit_vectors) {
    Vec3 a = sphere_angles(e);
    if (!out.empty()) {
      const double prev = out.back()[0];
      a[0] += 2.0 * M_PI * std::round((prev - a[0]) / (2.0 * M_PI));
    }
    out.push_back(a);
  }
  return out;
}

}  // namespace pcnc
