// ruled_surface.hpp — the curvature theory of a ruled surface x(u, v) = c(u) + v e(u), the
// seed paper's sections 3-5 (eqs. 7, 18-24): directrix c(u) (the tool tip or the
// cutter-contact point), unit ruling e(u) (the tool axis) tracing a curve on the unit sphere.
//
// Everything is computed analytically from the jets of c and e at one u (curve_jet.hpp):
// the spherical arc length rate ds/du = |e'| (eq. 18-19) and its next two derivatives; the
// generator trihedron e, t = e_s, g = e x t (eq. 20); and, as functions of the spherical arc
// length s (the theory's own parameter, primes below are d/ds):
//   gamma  = e . (e' x e'')         geodesic curvature of the spherical indicatrix
//                                   (t' = -e + gamma g, g' = -gamma t)
//   mu     = c' . e'                c = b + mu e: b = c - mu e is the striction curve
//   Gamma  = c' . e - mu'           b' = Gamma e + Delta g
//   Delta  = c' . (e x e')          the distribution parameter (0: developable)
//   sigma' = (Delta' mu - Delta mu') / (Delta^2 + mu^2), the turning rate of the surface
//            tangent perpendicular to the ruling, tan(sigma) = Delta / mu
// with gamma', mu', mu'', Gamma', Delta', Delta'' and sigma''; c' and c'' in the trihedron
// (eq. 21). All of it needs ds/du > 0: where the ruling stands still (a cylinder, e
// constant) `regular` is false and the s-functions are zero; the tool motion
// (ruled_motion.hpp) does not need them.
#pragma once

#include "geometry/curve_jet.hpp"
#include "geometry/curve_source.hpp"
#include "geometry/vec3.hpp"

namespace pcnc {

/// The directrix and the unit ruling of a ruled surface at one parameter u.
struct RuledJet {
  CurveJet c;  // directrix c(u) and derivatives (mm per unit u)
  CurveJet e;  // unit ruling e(u) and derivatives
};

/// How the ruling of a piece is given.
enum class RulingForm : int {
  kAngles = 0,  // the curve holds (theta, phi, 0), radians: the seed's eq. (10), (17)
  kVector = 1,  // the curve holds tool vectors, normalised at evaluation
};

/// A ruled-surface piece: directrix and ruling curves over the same parameter u.
struct RuledCurves {
  CurveSource directrix;
  CurveSource ruling;
  RulingForm form = RulingForm::kAngles;
  double u_min() const { return directrix.u_min(); }
  double u_max() const { return directrix.u_max(); }
};

/// The jets of directrix and unit ruling at u.
RuledJet ruled_jet(const RuledCurves& curves, double u);

/// The surface point x(u, v) = c(u) + v e(u) at one (u, v) (eq. 7).
Vec3 ruled_point(const RuledJet& j, double v);

/// The curvature functions of the surface at one u (see the header comment).
struct RuledInvariants {
  bool regular = false;  // ds/du > 0: the s-functions below are defined
  double ds_du = 0.0, d2s_du2 = 0.0, d3s_du3 = 0.0;
  Vec3 e{}, t{}, g{};  // generator trihedron (t, g zero when not regular)
  double gamma = 0.0, dgamma = 0.0;
  double mu = 0.0, dmu = 0.0, ddmu = 0.0;
  double Gamma = 0.0, dGamma = 0.0;
  double Delta = 0.0, dDelta = 0.0, ddDelta = 0.0;
  double dsigma = 0.0, ddsigma = 0.0;
  Vec3 striction{};    // b = c - mu e, the striction point on this ruling
  Vec3 dc_ds{};        // c' = (Gamma + mu') e + mu t + Delta g           (eq. 21)
  Vec3 d2c_ds2{};      // c'' = (Gamma' + mu'' - mu) e + (Gamma + 2 mu' - Delta gamma) t
                       //       + (Delta' + mu gamma) g
};

/// Below this ds/du (rad per unit u) the surface counts as cylindrical at u.
constexpr double kMinSphericalRate = 1e-12;

RuledInvariants ruled_invariants(const RuledJet& j);

/// The distribution parameter straight from u-derivatives, det(c_u, e, e_u) / |e_u|^2 (mm),
/// without the trihedron; 0 where ds/du = 0.
double distribution_parameter(const RuledJet& j);

/// The striction point straight from u-derivatives, c - (c_u . e_u / |e_u|^2) e; c itself
/// where ds/du = 0.
Vec3 striction_point(const RuledJet& j);

}  // namespace pcnc
