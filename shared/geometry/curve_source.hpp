// curve_source.hpp — one curve of a ruled-surface piece, of either kind the model accepts:
// a chain of Ferguson segments (hermite_curve.hpp) or a NURBS curve (nurbs.hpp), evaluated
// to third order through the same call. A directrix is a curve of points (mm); a ruling is
// a curve of angles (theta, phi, 0) or of tool vectors (spherical_curve.hpp); a spin angle is
// the x component of a curve. A plain view: it points at arrays that must outlive it.
#pragma once

#include "geometry/curve_jet.hpp"
#include "geometry/hermite_curve.hpp"
#include "geometry/nurbs.hpp"
#include "geometry/nurbs_jet.hpp"

namespace pcnc {

struct CurveSource {
  enum class Kind : int { kNone = 0, kHermite = 1, kNurbs = 2 };
  Kind kind = Kind::kNone;
  HermiteView hermite{};
  NurbsView nurbs{};

  static CurveSource of(const HermiteView& h) { return {Kind::kHermite, h, {}}; }
  static CurveSource of(const NurbsView& n) { return {Kind::kNurbs, {}, n}; }

  double u_min() const { return kind == Kind::kNurbs ? nurbs.u_min() : 0.0; }
  double u_max() const {
    return kind == Kind::kNurbs ? nurbs.u_max() : kind == Kind::kHermite ? hermite.u_max() : 0.0;
  }
};

/// The curve's jet at u (clamped to its domain); zero for kNone.
inline CurveJet curve_jet(const CurveSource& c, double u) {
  switch (c.kind) {
    case CurveSource::Kind::kHermite: return hermite_jet(c.hermite, u);
    case CurveSource::Kind::kNurbs: return nurbs_jet(c.nurbs, u);
    case CurveSource::Kind::kNone: break;
  }
  return {};
}

}  // namespace pcnc
