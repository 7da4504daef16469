// block_nurbs.cpp — a NURBS curve into and out of a block's arrays (see block_nurbs.hpp).
#include "ipc/block_nurbs.hpp"

#include <algorithm>
#include <cstdio>

namespace pcnc {

NurbsView view_of(const NurbsGeometry& g) {
  return {g.points, g.weights, g.knots, static_cast<int>(g.point_count), static_cast<int>(g.degree)};
}

std::string to_geometry(const NurbsCurve& curve, NurbsGeometry& g) {
  if (curve.points.size() > static_cast<std::size_t>(kMaxNurbsPoints)) {
    char buf[120];
    std::snprintf(buf, sizeof buf, "NURBS piece has %zu control points; a block holds at most %d (split it first)",
                  curve.points.size(), kMaxNurbsPoints);
    return buf;
  }
  if (std::string err = validate(curve); !err.empty()) return err;
  g.degree = static_cast<std::uint8_t>(curve.degree);
  g.point_count = static_cast<std::uint16_t>(curve.points.size());
  g.knot_count = static_cast<std::uint16_t>(curve.knots.size());
  std::copy(curve.points.begin(), curve.points.end(), g.points);
  std::copy(curve.weights.begin(), curve.weights.end(), g.weights);
  std::copy(curve.knots.begin(), curve.knots.end(), g.knots);
  return {};
}

NurbsCurve from_geometry(const NurbsGeometry& g) {
  NurbsCurve c;
  c.degree = g.degree;
  c.points.assign(g.points, g.points + g.point_count);
  c.weights.assign(g.weights, g.weights + g.point_count);
  c.knots.assign(g.knots, g.knots + g.knot_count);
  return c;
}

}  // namespace pcnc
