// nurbs_step.hpp — a step of given chord length along a NURBS curve: how the rt's
// interpolator advances a NURBS block each cycle and how the host's rough interpolation
// samples a curve.
//
// nurbs_parameter_step() advances the curve parameter so that the chord to the next
// setpoint has a given length ds: a second-order Taylor step
//   u+ = u + ds/|C'| - ds^2 (C'.C'') / (2 |C'|^4)
// followed by Newton iterations on the chord length |C(u+) - C(u)| = ds (usually one, which
// brings the relative error far below 1e-9). Pure and allocation-free.
#pragma once

#include "geometry/nurbs.hpp"
#include "geometry/vec3.hpp"

namespace pcnc {

struct NurbsStep {
  double u = 0.0;       // new parameter
  NurbsEval eval{};     // curve at u (point = the new setpoint)
  double chord = 0.0;   // |C(u) - C(u_old)|, mm
  bool at_end = false;  // the end of the curve was reached (chord may be shorter than ds)
};

/// Advances from parameter u (where the curve is `at`) by a chord of length ds > 0. If the
/// end of the curve is closer than ds, returns the end with at_end set.
NurbsStep nurbs_parameter_step(const NurbsView& c, double u, const NurbsEval& at, double ds);
/// The same with a knot-span hint the caller keeps between steps (nurbs_eval's hinted form: the
/// same span, so the same step bit for bit, without a search while u stays in one span).
NurbsStep nurbs_parameter_step(const NurbsView& c, double u, const NurbsEval& at, double ds, int& span_hint);

}  // namespace pcnc
