// ruled_motion.hpp — the tool's motion on a ruled surface at one parameter u, the seed
// paper's section 5 (eqs. 21-26), all analytic, plus the parameter step per sampling period
// (its eq. 5 taken to second order, with a correction).
//
// The tool frame (the seed's O, A, N): A = e(u), the tool axis (the ruling); O the unit
// direction of the tool's motion perpendicular to A, P = unit(c_u - (c_u . e) e), turned
// about A by the spin angle eta(u) (eq. 8; eta = 0 when the program gives none); N = A x O.
// For a regular surface P = cos(sigma) t + sin(sigma) g, so (A, O, N) is the generator
// trihedron (e, t, g) turned by sigma + eta, and the angular velocity per unit s is
// U0 = Omega e + g, Omega = eta' + sigma' + gamma, its derivative U0' = Omega' e +
// (eta' + sigma') t (eqs. 23-24). Here the same quantities are computed per unit u, which
// also holds where ds/du = 0 (a cylinder):
//   omega_u  = (w + eta_u) e + e x e_u,     w = P_u . (e x P) = det(e, p, p_u) / |p|^2
//   omega_uu = (w_u + eta_uu) e + (w + eta_u) e_u + e x e_uu.
// Time enters through the feed F = |dc/dt| (mm/s) and its rate dF/dt:
//   du/dt = F / |c_u|,  d2u/dt2 = (dF/dt - (c_u . c_uu / |c_u|) (du/dt)^2) / |c_u|,
//   v = c_u u',  a = c_uu u'^2 + c_u u'',  omega = omega_u u',  alpha = omega_uu u'^2 + omega_u u''.
// The frame is undefined where the tool moves along its own axis (p = 0): `frame_defined`;
// near such a point the frame's spin about A (w) grows without bound, while the axis's own
// rates (axis_velocity, axis_acceleration), which are all a 5-axis machine follows, do not.
#pragma once

#include "geometry/curve_jet.hpp"
#include "geometry/curve_source.hpp"
#include "geometry/ruled_surface.hpp"
#include "geometry/vec3.hpp"

namespace pcnc {

/// Position, frame and first- and second-order motion of the tool at one u.
struct ToolMotion {
  double u = 0.0;
  double du_dt = 0.0, d2u_dt2 = 0.0;  // 1/s, 1/s^2
  Vec3 position{};                    // c(u), mm
  Vec3 A{}, O{}, N{};                 // tool frame: axis, motion direction, A x O
  bool frame_defined = false;
  Vec3 velocity{};      // mm/s
  Vec3 acceleration{};  // mm/s^2
  Vec3 omega{};         // rad/s, angular velocity of the frame
  Vec3 alpha{};         // rad/s^2, angular acceleration
  Vec3 omega_u{};       // rad per unit u (what omega is before the time chain rule)
  Vec3 omega_uu{};
  // The tool axis's own rates, dA/dt = e_u u' = omega x A and d2A/dt2 = e_uu u'^2 + e_u u'':
  // what a 5-axis machine's joints follow (they cannot turn the tool about its own axis, so
  // omega's component along A, the frame's spin, does not reach them).
  Vec3 axis_velocity{};      // 1/s
  Vec3 axis_acceleration{};  // 1/s^2
};

/// The spin angle eta(u) (radians) and its first two u-derivatives; zero when not given.
struct SpinJet {
  double eta = 0.0, d1 = 0.0, d2 = 0.0;
};

/// The tool's motion at the jet's u for feed F (mm/s, > 0) changing at dF/dt (mm/s^2).
ToolMotion tool_motion(const RuledJet& j, double u, double feed, double dfeed, const SpinJet& spin = {});

/// The seed's route through the trihedron (eqs. 21-24) for a regular surface: c', c'' per
/// unit s from the invariants (eq. 21), U0 and U0' (eq. 23) for the spin's s-derivatives.
struct SeedMotionTerms {
  Vec3 dc_ds{}, d2c_ds2{};
  Vec3 U0{}, dU0{};
  double Omega = 0.0, dOmega = 0.0;
};
SeedMotionTerms seed_motion_terms(const RuledInvariants& k, const SpinJet& spin);

/// One sampling period's advance of the parameter at constant feed (the seed's eq. 5 taken
/// to second order): u + u' T + u'' T^2 / 2 from the directrix's jet at u. With `correct`,
/// Newton steps on the chord |c(u_next) - c(u)| = F T + dF/dt T^2 / 2 follow while it is off
/// by more than kChordTolerance, at most kMaxCorrections (one directrix evaluation each;
/// usually one, none when the Taylor step is already that close). The result is clamped to
/// the directrix's domain.
constexpr double kChordTolerance = 1e-9;
constexpr int kMaxCorrections = 3;
struct ParameterStep {
  double u_next = 0.0;
  double target = 0.0;  // the length to travel, mm
  double chord = 0.0;   // |c(u_next) - c(u)|, mm
  /// (chord - target) / target: the relative feed error of this period.
  double feed_error() const { return target > 0.0 ? (chord - target) / target : 0.0; }
};
ParameterStep advance_parameter(const CurveSource& directrix, double u, double feed, double dfeed, double period,
                                bool correct = true);

}  // namespace pcnc
