// ruled_motion.cpp — tool pose, velocities and accelerations on a ruled surface, and the
// constant-feed parameter step. See ruled_motion.hpp for the formulas.
#include "geometry/ruled_motion.hpp"

#include <algorithm>
#include <cmath>

namespace pcnc {

ToolMotion tool_motion(const RuledJet& j, double u, double feed, double dfeed, const SpinJet& spin) {
  const CurveJet& c = j.c;
  const CurveJet& e = j.e;
  ToolMotion m;
  m.u = u;
  m.position = c.p;
  m.A = e.p;

  // Time law from the constant-feed condition |c_u| du/dt = F.
  const double speed = norm(c.d1);
  if (speed > 0.0) {
    m.du_dt = feed / speed;
    m.d2u_dt2 = (dfeed - (dot(c.d1, c.d2) / speed) * m.du_dt * m.du_dt) / speed;
  }

  // p = c_u - (c_u . e) e, the motion direction perpendicular to the axis, and its
  // derivatives (product rule on each term).
  const double k0 = dot(c.d1, e.p);
  const double k1 = dot(c.d2, e.p) + dot(c.d1, e.d1);
  const double k2 = dot(c.d3, e.p) + 2.0 * dot(c.d2, e.d1) + dot(c.d1, e.d2);
  const Vec3 p = c.d1 - k0 * e.p;
  const Vec3 p1 = c.d2 - k1 * e.p - k0 * e.d1;
  const Vec3 p2 = c.d3 - k2 * e.p - 2.0 * k1 * e.d1 - k0 * e.d2;
  const double pp = dot(p, p);

  // w = det(e, p, p_u) / |p|^2: the turning rate of P about e, per unit u.
  double w = 0.0, w_u = 0.0;
  if (pp > 0.0 && std::sqrt(pp) > 1e-12 * (speed + 1.0)) {
    m.frame_defined = true;
    const Vec3 P = (1.0 / std::sqrt(pp)) * p;
    const Vec3 Q = cross(e.p, P);
    const double ce = std::cos(spin.eta), se = std::sin(spin.eta);
    m.O = ce * P + se * Q;
    m.N = cross(m.A, m.O);
    const double det = det3(e.p, p, p1);
    const double ddet = det3(e.d1, p, p1) + det3(e.p, p, p2);
    w = det / pp;
    w_u = ddet / pp - det * 2.0 * dot(p, p1) / (pp * pp);
  }
  const double spin_rate = w + spin.d1;
  m.omega_u = spin_rate * e.p + cross(e.p, e.d1);
  m.omega_uu = (w_u + spin.d2) * e.p + spin_rate * e.d1 + cross(e.p, e.d2);

  const double ud = m.du_dt, udd = m.d2u_dt2;
  m.velocity = ud * c.d1;
  m.acceleration = (ud * ud) * c.d2 + udd * c.d1;
  m.omega = ud * m.omega_u;
  m.alpha = (ud * ud) * m.omega_uu + udd * m.omega_u;
  m.axis_velocity = ud * e.d1;
  m.axis_acceleration = (ud * ud) * e.d2 + udd * e.d1;
  return m;
}

SeedMotionTerms seed_motion_terms(const RuledInvariants& k, const SpinJet& spin) {
  SeedMotionTerms s;
  if (!k.regular) return s;
  // eta as a function of s: eta_s = eta_u / s_u, eta_ss = (eta_uu - eta_s s_uu) / s_u^2.
  const double eta_s = spin.d1 / k.ds_du;
  const double eta_ss = (spin.d2 - eta_s * k.d2s_du2) / (k.ds_du * k.ds_du);
  s.dc_ds = (k.Gamma + k.dmu) * k.e + k.mu * k.t + k.Delta * k.g;
  s.d2c_ds2 = (k.dGamma + k.ddmu - k.mu) * k.e + (k.Gamma + 2.0 * k.dmu - k.Delta * k.gamma) * k.t +
              (k.dDelta + k.mu * k.gamma) * k.g;
  s.Omega = eta_s + k.dsigma + k.gamma;
  s.dOmega = eta_ss + k.ddsigma + k.dgamma;
  s.U0 = s.Omega * k.e + k.g;
  s.dU0 = s.dOmega * k.e + (eta_s + k.dsigma) * k.t;
  return s;
}

ParameterStep advance_parameter(const CurveSource& directrix, double u, double feed, double dfeed, double period,
                                bool correct) {
  ParameterStep s;
  const double lo = directrix.u_min(), hi = directrix.u_max();
  const CurveJet c0 = curve_jet(directrix, u);
  const double speed = norm(c0.d1);
  s.target = feed * period + 0.5 * dfeed * period * period;
  if (!(speed > 0.0) || !(s.target > 0.0)) {
    s.u_next = u;
    return s;
  }
  const double ud = feed / speed;
  const double udd = (dfeed - (dot(c0.d1, c0.d2) / speed) * ud * ud) / speed;
  s.u_next = std::clamp(u + ud * period + 0.5 * udd * period * period, lo, hi);
  CurveJet c1 = curve_jet(directrix, s.u_next);
  Vec3 chord = c1.p - c0.p;
  s.chord = norm(chord);
  // Newton on f(u) = |c(u) - c(u0)| - target, f' = (c(u) - c(u0)) . c_u(u) / |c(u) - c(u0)|,
  // while the chord is off by more than kChordTolerance (relative), at most kMaxCorrections
  // times: one step is enough on a smooth curve; a curve whose parametric speed changes
  // sharply within the period may need another.
  for (int i = 0; correct && i < kMaxCorrections && s.chord > 0.0 && s.u_next < hi &&
                  std::abs(s.chord - s.target) > kChordTolerance * s.target;
       ++i) {
    const double slope = dot(chord, c1.d1) / s.chord;
    if (!(slope > 0.0)) break;
    s.u_next = std::clamp(s.u_next + (s.target - s.chord) / slope, u, hi);
    c1 = curve_jet(directrix, s.u_next);
    chord = c1.p - c0.p;
    s.chord = norm(chord);
  }
  return s;
}

}  // namespace pcnc
