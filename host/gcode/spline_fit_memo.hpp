// spline_fit_memo.hpp — fit_polyline remembered across the front end's passes in one process,
// like the NURBS plans (gcode/nurbs_plan_memo.hpp, which explains why: pcnc-host checks the
// whole program, then streams it through the same pipeline again, and the smoothing stage
// fitted every run twice). A fit is kept with its exact input (every point and the tolerance,
// compared in full) and handed out once to the next pass that asks for the same; fit_polyline
// is a pure function of them, so a hit returns what fitting would. Bounded (kSplineFitMemoBytes;
// an insertion past it drops every entry first) and thread-safe.
#pragma once

#include <cstddef>
#include <vector>

#include "gcode/hand_over_memo.hpp"
#include "geometry/spline_fit.hpp"

namespace pcnc {

constexpr std::size_t kSplineFitMemoBytes = 16u << 20;

/// fit_polyline(points, tolerance), from the memo when a pass fitted the same before.
SplineFit fit_polyline_memo(const std::vector<Vec3>& points, double tolerance);

using SplineFitMemoStats = MemoStats;
SplineFitMemoStats spline_fit_memo_stats();
void spline_fit_memo_clear();

}  // namespace pcnc
