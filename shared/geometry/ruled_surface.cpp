// ruled_surface.cpp — the curvature functions of a ruled surface at one parameter. See
// ruled_surface.hpp for the formulas; here they are evaluated from u-derivatives through
// the chain rule to the spherical arc length s (no integral of eq. 19 is ever needed).
#include "geometry/ruled_surface.hpp"

#include <cmath>

#include "geometry/spherical_curve.hpp"

namespace pcnc {
namespace {

// d/ds, d2/ds2, d3/ds3 of a curve from its u-jet, with s1..s3 the u-derivatives of s:
// f_u = f_s s1, f_uu = f_ss s1^2 + f_s s2, f_uuu = f_sss s1^3 + 3 f_ss s1 s2 + f_s s3.
CurveJet to_arc_length(const CurveJet& f, double s1, double s2, double s3) {
  CurveJet r;
  r.p = f.p;
  r.d1 = (1.0 / s1) * f.d1;
  r.d2 = (1.0 / (s1 * s1)) * (f.d2 - s2 * r.d1);
  r.d3 = (1.0 / (s1 * s1 * s1)) * (f.d3 - 3.0 * s1 * s2 * r.d2 - s3 * r.d1);
  return r;
}

}  // namespace

RuledJet ruled_jet(const RuledCurves& curves, double u) {
  RuledJet j;
  j.c = curve_jet(curves.directrix, u);
  const CurveJet r = curve_jet(curves.ruling, u);
  j.e = curves.form == RulingForm::kAngles ? sphere_point_jet(r) : unit_vector_jet(r);
  return j;
}

Vec3 ruled_point(const RuledJet& j, double v) { return j.c.p + v * j.e.p; }

RuledInvariants ruled_invariants(const RuledJet& j) {
  RuledInvariants k;
  k.e = j.e.p;
  k.striction = j.c.p;
  const double s1 = norm(j.e.d1);
  k.ds_du = s1;
  if (!(s1 > kMinSphericalRate)) return k;
  const double s2 = dot(j.e.d1, j.e.d2) / s1;
  const double s3 = (dot(j.e.d2, j.e.d2) + dot(j.e.d1, j.e.d3) - s2 * s2) / s1;
  k.regular = true;
  k.d2s_du2 = s2;
  k.d3s_du3 = s3;

  const CurveJet c = to_arc_length(j.c, s1, s2, s3);
  const CurveJet e = to_arc_length(j.e, s1, s2, s3);
  k.t = e.d1;
  k.g = cross(e.p, e.d1);

  k.gamma = det3(e.p, e.d1, e.d2);
  k.dgamma = det3(e.p, e.d1, e.d3);
  k.mu = dot(c.d1, e.d1);
  k.dmu = dot(c.d2, e.d1) + dot(c.d1, e.d2);
  k.ddmu = dot(c.d3, e.d1) + 2.0 * dot(c.d2, e.d2) + dot(c.d1, e.d3);
  k.Gamma = dot(c.d1, e.p) - k.dmu;
  k.dGamma = dot(c.d2, e.p) + k.mu - k.ddmu;
  const Vec3 ee1 = cross(e.p, e.d1), ee2 = cross(e.p, e.d2);
  k.Delta = dot(c.d1, ee1);
  k.dDelta = dot(c.d2, ee1) + dot(c.d1, ee2);
  k.ddDelta = dot(c.d3, ee1) + 2.0 * dot(c.d2, ee2) + dot(c.d1, cross(e.d1, e.d2) + cross(e.p, e.d3));

  // sigma = atan(Delta / mu): sigma' = N / D, sigma'' = (N' D - N D') / D^2.
  const double num = k.dDelta * k.mu - k.Delta * k.dmu;
  const double dnum = k.ddDelta * k.mu - k.Delta * k.ddmu;
  const double den = k.Delta * k.Delta + k.mu * k.mu;
  const double dden = 2.0 * (k.Delta * k.dDelta + k.mu * k.dmu);
  if (den > 0.0) {
    k.dsigma = num / den;
    k.ddsigma = (dnum * den - num * dden) / (den * den);
  }

  k.striction = c.p - k.mu * e.p;
  k.dc_ds = c.d1;
  k.d2c_ds2 = c.d2;
  return k;
}

double distribution_parameter(const RuledJet& j) {
  const double q = dot(j.e.d1, j.e.d1);
  return q > kMinSphericalRate * kMinSphericalRate ? det3(j.c.d1, j.e.p, j.e.d1) / q : 0.0;
}

Vec3 striction_point(const RuledJet& j) {
  const double q = dot(j.e.d1, j.e.d1);
  if (!(q > kMinSphericalRate * kMinSphericalRate)) return j.c.p;
  return j.c.p - (dot(j.c.d1, j.e.d1) / q) * j.e.p;
}

}  // namespace pcnc
