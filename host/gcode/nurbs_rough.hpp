// nurbs_rough.hpp — the seed paper's rough interpolation of a NURBS curve, as an offline
// comparison (`pcnc nurbs FILE --tolerance d`): step along the curve by the feed per sample,
// and bisect a step wherever its chord deviates more than delta from the curve. The result
// is the polyline a CAM system would have sent as G01 blocks; the direct NURBS block
// replaces all of them.
#pragma once

#include <cstddef>
#include <vector>

#include "geometry/nurbs.hpp"
#include "geometry/vec3.hpp"

namespace pcnc {

struct RoughPolyline {
  std::vector<double> params;  // curve parameter of each vertex, first u_min, last u_max
  std::vector<Vec3> points;    // the vertices (on the curve)
  std::size_t segments = 0;    // points.size() - 1: the G01 blocks it stands for
  std::size_t bisections = 0;  // steps that had to be halved (at any depth)
  double max_deviation_mm = 0.0;  // measured against a dense evaluation of the curve
};

/// Rough interpolation of a valid curve: steps whose chord is `step_mm` long (the feed per
/// rough sample, F * T), each accepted when the curve at its middle and quarter parameters
/// lies within `tolerance_mm` of the chord, else halved in parameter (recursively, the seed
/// halves once). Vertices are exact curve points.
RoughPolyline rough_interpolate(const NurbsCurve& curve, double step_mm, double tolerance_mm);

/// Largest distance of the curve from the polyline, the curve between two vertices sampled
/// at `samples` parameters and measured against the segment joining them.
double polyline_deviation(const NurbsCurve& curve, const std::vector<double>& params,
                          const std::vector<Vec3>& points, int samples = 64);

/// Distance of q from the segment [a, b].
double distance_to_segment(const Vec3& q, const Vec3& a, const Vec3& b);

}  // namespace pcnc
