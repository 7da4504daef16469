// nurbs_arc_samples.hpp — the arc length of a NURBS curve at many sorted parameters at once:
// the feed schedule's dense samples (32-128 a knot span, host/gcode/nurbs_schedule.cpp), where
// one adaptive nurbs_arc_length per interval cost three 8-point quadratures each (24
// evaluations of C') and was 77 % of the front end's time on a smoothed surfacing program.
//
// Each interval between two consecutive parameters inside one knot span is integrated with
// 4-point Gauss–Legendre on |C'(u)| (smooth inside a span; the intervals are small). The
// intervals of one span are then checked together against the adaptive length of the whole
// stretch (nurbs_arc_length): when their sum agrees with it to kArcSamplesAgreement (relative),
// they are scaled to it, so the stretch's end carries the adaptive value; otherwise (a kink
// of |C'| where C' nearly vanishes, say) each interval is integrated adaptively, as before.
// An interval that crosses a knot is always integrated adaptively. Pure; no state.
#pragma once

#include <vector>

#include "geometry/nurbs.hpp"

namespace pcnc {

/// Largest relative difference between the 4-point sum of a span's intervals and the span's
/// adaptive length for the sum to be used.
constexpr double kArcSamplesAgreement = 1e-11;

/// s[j] = arc length from us[0] to us[j] (s[0] = 0); `us` non-decreasing, inside the domain.
std::vector<double> nurbs_arc_lengths_at(const NurbsView& c, const std::vector<double>& us);

}  // namespace pcnc
