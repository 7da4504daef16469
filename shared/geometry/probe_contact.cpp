// probe_contact.cpp — distances from a probe's ball centre to the table's objects, and the
// pre-travel model (probe_contact.hpp).
#include "geometry/probe_contact.hpp"

#include <algorithm>
#include <cmath>

namespace pcnc {

namespace {

// The B-spline top at (x, y) and its gradient: dz/dx, dz/dy from the parameter Jacobian
// [x_u x_v; y_u y_v]^-1 applied to (z_u, z_v); held flat outside the footprint.
double bspline_height(const BSplineSurface& b, double x, double y, double& gx, double& gy) {
  const SurfaceHeight h = surface_height(b, x, y);
  gx = gy = 0.0;
  if (!h.inside) return h.z;
  const SurfaceEval e = surface_eval(b, h.u, h.v);
  const double det = e.su[0] * e.sv[1] - e.sv[0] * e.su[1];
  if (std::fabs(det) < 1e-300) return h.z;
  // [du dv] per dx: ( sv_y, -su_y)/det; per dy: (-sv_x, su_x)/det
  gx = (e.su[2] * e.sv[1] - e.sv[2] * e.su[1]) / det;
  gy = (e.sv[2] * e.su[0] - e.su[2] * e.sv[0]) / det;
  return h.z;
}

// The Wiener error at (x, y) and its gradient (central differences over 1e-4 of the rectangle).
double error_height(const TableScene& s, double x, double y, double& gx, double& gy) {
  const double wx = s.error_x1_mm - s.error_x0_mm, wy = s.error_y1_mm - s.error_y0_mm;
  const double t1 = (x - s.error_x0_mm) / wx, t2 = (y - s.error_y0_mm) / wy, h = 1e-4;
  const WienerSurface& w = *s.error;
  gx = (w.smooth_value(t1 + h, t2) - w.smooth_value(t1 - h, t2)) / (2.0 * h * wx);
  gy = (w.smooth_value(t1, t2 + h) - w.smooth_value(t1, t2 - h)) / (2.0 * h * wy);
  return w.smooth_value(t1, t2);
}

}  // namespace

double surface_height(const TableScene& s, double x, double y, double* dzdx, double* dzdy) {
  double z = s.z_mm + s.slope_x * x + s.slope_y * y;
  double gx = s.slope_x, gy = s.slope_y;
  if (s.bspline) z = bspline_height(*s.bspline, x, y, gx, gy);
  if (s.error) {
    double ex = 0.0, ey = 0.0;
    z += error_height(s, x, y, ex, ey);
    gx += ex;
    gy += ey;
  }
  if (!s.bspline && s.bump_height_mm != 0.0) {
    const double dx = x - s.bump_x_mm, dy = y - s.bump_y_mm;
    const double inv2s2 = 1.0 / (2.0 * s.bump_sigma_mm * s.bump_sigma_mm);
    const double b = s.bump_height_mm * std::exp(-(dx * dx + dy * dy) * inv2s2);
    z += b;
    gx += -2.0 * dx * inv2s2 * b;
    gy += -2.0 * dy * inv2s2 * b;
  }
  if (dzdx) *dzdx = gx;
  if (dzdy) *dzdy = gy;
  return z;
}

double surface_gap(const TableScene& s, const Vec3& c) {
  if (!s.has_surface) return kNoContact;
  double gx = 0.0, gy = 0.0;
  const double z = surface_height(s, c[0], c[1], &gx, &gy);
  return (c[2] - z) / std::sqrt(1.0 + gx * gx + gy * gy);
}

double sphere_gap(const TableScene& s, const Vec3& c) {
  if (!(s.sphere_radius_mm > 0.0)) return kNoContact;
  return norm(c - s.sphere_center) - s.sphere_radius_mm;
}

double gauge_gap(const TableScene& s, const Vec3& c) {
  if (!s.has_gauge) return kNoContact;
  // signed distance to an axis-aligned box: outside, the distance to the nearest point of it;
  // inside, minus the distance to the nearest face
  Vec3 out{};
  double inside = -kNoContact;
  for (int i = 0; i < kAxes; ++i) {
    const double below = s.gauge_min[i] - c[i], above = c[i] - s.gauge_max[i];
    out[i] = std::max({below, above, 0.0});
    inside = std::max(inside, std::max(below, above));
  }
  const double d = norm(out);
  return d > 0.0 ? d : inside;
}

double artefact_gap(const TableScene& s, const Vec3& c) {
  double g = kNoContact;
  for (int i = 0; i < s.artefact_balls && i < TableScene::kMaxArtefactBalls; ++i)
    g = std::min(g, norm(c - s.artefact_centres[static_cast<std::size_t>(i)]) - s.artefact_ball_radius_mm);
  return g;
}

double scene_gap(const TableScene& s, const Vec3& c) {
  return std::min({surface_gap(s, c), sphere_gap(s, c), gauge_gap(s, c), artefact_gap(s, c)});
}

double pretravel_mm(const ProbeModel& p, const Vec3& d) {
  const Vec3 u = normalized(d);
  if (u[0] == 0.0 && u[1] == 0.0) return p.pretravel_axial_mm;
  const double theta = std::atan2(u[1], u[0]);
  const double lateral = p.pretravel_lateral_mm + p.pretravel_lobe_mm * std::cos(3.0 * theta);
  return p.pretravel_axial_mm * u[2] * u[2] + lateral * (u[0] * u[0] + u[1] * u[1]);
}

double probe_speed_limit(double accel, double dt, double overtravel_mm) {
  // the positive root of v²/(2a) + 2·dt·v − overtravel = 0
  return accel * (-2.0 * dt + std::sqrt(4.0 * dt * dt + 2.0 * overtravel_mm / accel));
}

}  // namespace pcnc
