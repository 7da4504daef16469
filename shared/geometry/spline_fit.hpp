// spline_fit.hpp — a cubic B-spline within a tolerance of a polyline: the mathematics of the
// host's smoothing stage (host/gcode/smoothing.hpp, docs/smoothing.md).
//
// fit_polyline() takes the points of a run of straight moves and returns a clamped cubic
// B-spline (a NURBS curve with unit weights, simple interior knots: C2 everywhere) that
//   * starts exactly at the first point and ends exactly at the last;
//   * keeps every curve point within `tolerance` of the polyline, and every programmed point
//     and segment within `tolerance` of the curve — measured on the result (dense samples of
//     the curve against the segments, the points and segment samples against the sampled
//     curve), not assumed from the construction.
// The parameter is the polyline's chord length (mm), so that |C'| stays near 1.
//
// Method: least squares on the programmed points and segment samples (at least two per knot
// span) with the end control
// points fixed, a small second-difference penalty on the control polygon (it keeps spans
// without data well posed), solved as a banded system; the knots start a few millimetres
// apart and every span whose measured deviation exceeds 90 % of the tolerance is halved,
// then the fit is solved again, until every span fits or a span cannot be halved further.
// Pure: standard library and geometry/ only.
#pragma once

#include <vector>

#include "geometry/nurbs.hpp"
#include "geometry/vec3.hpp"

namespace pcnc {

struct SplineFit {
  NurbsCurve curve;        // degree 3, weights 1, domain [0, chord length]
  double deviation = 0.0;  // measured two-sided distance between curve and polyline, mm
  bool ok = false;         // deviation <= tolerance
  int worst_point = -1;    // the programmed point nearest the largest deviation (a place to split)
};

/// Fits `points` (at least 2, consecutive points distinct) within `tolerance` (> 0, mm).
/// When !ok the curve is still valid but too far somewhere: the caller keeps a corner there.
SplineFit fit_polyline(const std::vector<Vec3>& points, double tolerance);

/// The two-sided distance between `curve` and the polyline through `points`, measured: the
/// curve sampled densely (`samples_per_span` per knot span) against the polyline, and each
/// programmed point and segment sample against the sampled curve. Near-parameter windows
/// (the curve's parameter is the polyline's chord length) keep it linear in the run.
/// `per_point` (when given) receives for each point index the largest deviation found near it.
double polyline_deviation(const NurbsCurve& curve, const std::vector<Vec3>& points, int samples_per_span = 16,
                          std::vector<double>* per_point = nullptr);

/// The distance from p to the segment a-b.
double point_segment_distance(const Vec3& p, const Vec3& a, const Vec3& b);

}  // namespace pcnc
