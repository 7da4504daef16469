// probe_compensation.cpp — ball centre to contact point along the measured normal (see
// probe_compensation.hpp).
#include "geometry/probe_compensation.hpp"

#include <algorithm>

#include "geometry/bspline_surface.hpp"
#include "geometry/sphere_fit.hpp"

namespace pcnc {

Vec3 contact_point(const Vec3& centre, const Vec3& normal, double r_eff) { return centre - r_eff * normalized(normal); }

Vec3 contact_point(const Vec3& centre, const Vec3& normal, const Vec3& approach, const ProbeCalibration& cal) {
  return contact_point(centre, normal, effective_radius(cal, approach));
}

GridCompensation compensate_grid(const PointGrid& centres, const std::vector<Vec3>& approaches,
                                 const ProbeCalibration& cal) {
  GridCompensation out;
  const std::size_t count = centres.points.size();
  if (centres.cols < 2 || centres.rows < 2 || count != static_cast<std::size_t>(centres.cols * centres.rows)) {
    out.error = "a grid of at least 2 x 2 points is needed";
    return out;
  }
  if (approaches.size() != 1 && approaches.size() != count) {
    out.error = std::to_string(approaches.size()) + " approach directions for " + std::to_string(count) + " points";
    return out;
  }
  out.degree = std::min({3, centres.cols - 1, centres.rows - 1});
  const SurfaceFit fit = interpolate_grid(centres, out.degree, 1.0);
  if (!fit.ok()) {
    out.error = "surface through the centres: " + fit.error;
    return out;
  }
  out.contacts = centres;
  out.normals.resize(count);
  for (int r = 0; r < centres.rows; ++r) {
    for (int c = 0; c < centres.cols; ++c) {
      const std::size_t i = static_cast<std::size_t>(r * centres.cols + c);
      const Vec3& d = approaches.size() == 1 ? approaches[0] : approaches[i];
      Vec3 n = surface_normal(surface_eval(fit.surface, fit.params_u[static_cast<std::size_t>(c)],
                                           fit.params_v[static_cast<std::size_t>(r)]));
      if (dot(n, d) > 0.0) n = -1.0 * n;
      out.normals[i] = n;
      out.contacts.points[i] = contact_point(centres.points[i], n, d, cal);
    }
  }
  return out;
}

Vec3 local_normal(const std::vector<Vec3>& centres, std::size_t index, int neighbours, const Vec3& approach) {
  if (index >= centres.size() || neighbours < 2) return {0.0, 0.0, 0.0};
  std::vector<std::pair<double, std::size_t>> by_distance;
  for (std::size_t i = 0; i < centres.size(); ++i)
    if (i != index) by_distance.emplace_back(norm(centres[i] - centres[index]), i);
  const std::size_t k = std::min(by_distance.size(), static_cast<std::size_t>(neighbours));
  std::partial_sort(by_distance.begin(), by_distance.begin() + static_cast<std::ptrdiff_t>(k), by_distance.end());
  std::vector<Vec3> pts{centres[index]};
  for (std::size_t i = 0; i < k; ++i) pts.push_back(centres[by_distance[i].second]);
  const PlaneFit plane = fit_plane(pts);
  if (!plane.ok()) return {0.0, 0.0, 0.0};
  Vec3 n = plane.normal;
  if (dot(n, approach) > 0.0) n = -1.0 * n;
  return n;
}

PointsCompensation compensate_points(const std::vector<Vec3>& centres, const std::vector<Vec3>& approaches,
                                     const ProbeCalibration& cal, int neighbours) {
  PointsCompensation out;
  if (centres.size() < 3) {
    out.error = "at least 3 points are needed for normals";
    return out;
  }
  if (approaches.size() != 1 && approaches.size() != centres.size()) {
    out.error = std::to_string(approaches.size()) + " approach directions for " + std::to_string(centres.size()) + " points";
    return out;
  }
  for (std::size_t i = 0; i < centres.size(); ++i) {
    const Vec3& d = approaches.size() == 1 ? approaches[0] : approaches[i];
    const Vec3 n = local_normal(centres, i, neighbours, d);
    if (!(norm(n) > 0.0)) {
      out.error = "point " + std::to_string(i) + ": its neighbours lie on one line, no normal";
      out.contacts.clear();
      out.normals.clear();
      return out;
    }
    out.normals.push_back(n);
    out.contacts.push_back(contact_point(centres[i], n, d, cal));
  }
  return out;
}

}  // namespace pcnc
