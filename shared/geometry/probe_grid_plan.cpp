// probe_grid_plan.cpp — the probing plan over a rectangle (see probe_grid_plan.hpp).
#include "geometry/probe_grid_plan.hpp"

#include <cmath>

namespace pcnc {

void estimate_at(const SurfaceEstimate& s, double x, double y, double& z, Vec3& normal) {
  if (s.surface) {
    const SurfaceHeight h = surface_height(*s.surface, x, y);
    z = h.z;
    normal = surface_normal(surface_eval(*s.surface, h.u, h.v));
    if (normal[2] < 0.0) normal = -1.0 * normal;
    return;
  }
  z = s.z0_mm + s.slope_x * x + s.slope_y * y;
  normal = normalized(Vec3{-s.slope_x, -s.slope_y, 1.0});
}

ProbePoint plan_probe_point(double x, double y, const ProbeGridSpec& spec, const SurfaceEstimate& estimate) {
  ProbePoint p;
  double z = 0.0;
  estimate_at(estimate, x, y, z, p.normal);
  p.expected_contact = {x, y, z};
  p.approach = -1.0 * p.normal;
  p.start = p.expected_contact + (spec.ball_radius_mm + spec.clearance_mm) * p.normal;
  p.end = p.expected_contact + (spec.ball_radius_mm - spec.probe_distance_mm) * p.normal;
  return p;
}

ProbeGridPlan plan_probe_grid(const ProbeGridSpec& spec, const SurfaceEstimate& estimate) {
  ProbeGridPlan out;
  if (spec.nx < 1 || spec.ny < 1) {
    out.error = "nx and ny must be >= 1";
    return out;
  }
  if (!(spec.x1_mm > spec.x0_mm || (spec.nx == 1 && spec.x1_mm == spec.x0_mm)) ||
      !(spec.y1_mm > spec.y0_mm || (spec.ny == 1 && spec.y1_mm == spec.y0_mm))) {
    out.error = "the rectangle needs x0 < x1 and y0 < y1 (equal only for a single column or row)";
    return out;
  }
  if (!(spec.ball_radius_mm > 0.0) || !(spec.clearance_mm > 0.0) || !(spec.probe_distance_mm > 0.0)) {
    out.error = "ball radius, clearance and probing distance must be > 0";
    return out;
  }
  out.points.reserve(static_cast<std::size_t>(spec.nx * spec.ny));
  for (int r = 0; r < spec.ny; ++r) {
    const double y = spec.ny == 1 ? spec.y0_mm : spec.y0_mm + (spec.y1_mm - spec.y0_mm) * r / (spec.ny - 1);
    for (int c = 0; c < spec.nx; ++c) {
      const double x = spec.nx == 1 ? spec.x0_mm : spec.x0_mm + (spec.x1_mm - spec.x0_mm) * c / (spec.nx - 1);
      ProbePoint p = plan_probe_point(x, y, spec, estimate);
      p.col = c;
      p.row = r;
      out.points.push_back(p);
    }
  }
  return out;
}

}  // namespace pcnc
