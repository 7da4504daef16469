// corner_blend.cpp — the rt's corner blend: weight, blended jet, and the window's plan (see
// corner_blend.hpp for the bounds).
#include "geometry/corner_blend.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace pcnc {

BlendWeight blend_weight(double sigma) {
  BlendWeight b;
  if (sigma <= 0.0) return b;
  if (sigma >= 1.0) {
    b.w = 1.0;
    return b;
  }
  b.w = sigma * sigma * (3.0 - 2.0 * sigma);
  b.w1 = 6.0 * sigma * (1.0 - sigma);
  b.w2 = 6.0 - 12.0 * sigma;
  return b;
}

namespace {

// β(τ)/L = ∫₀^σ w = σ³ − σ⁴/2
double beta_of(double sigma) { return sigma * sigma * sigma * (1.0 - 0.5 * sigma); }

// a path's point and derivatives at arc length x from where its jet `j` is taken (second order)
PathJet shift(const PathJet& j, double x) {
  return PathJet{j.p + x * j.d1 + (0.5 * x * x) * j.d2, j.d1 + x * j.d2, j.d2};
}

}  // namespace

double corner_blend_half_length(double sin_phi, double curvature, double deviation) {
  if (!(deviation > 0.0)) return 0.0;
  const double c = kBlendDeviation * std::abs(sin_phi);
  const double kappa = std::max(0.0, curvature);
  const double den = c + std::sqrt(c * c + 2.0 * kappa * deviation);
  return den > 0.0 ? 2.0 * deviation / den : std::numeric_limits<double>::infinity();
}

PathJet corner_blend_offset(const CornerBlend& b, double s) {
  const double tau = s - b.at;
  if (!b.on || !(b.h > 0.0) || tau <= -b.h || tau >= b.h) return PathJet{};
  const double L = 2.0 * b.h;
  const double sigma = (tau + b.h) / L;
  const BlendWeight bw = blend_weight(sigma);
  const double beta = L * beta_of(sigma);
  const double alpha = tau - beta;
  const PathJet a0{b.corner, b.t_in, b.k_in}, b0{b.corner, b.t_out, b.k_out};
  const PathJet A = shift(a0, alpha), B = shift(b0, beta);
  const PathJet X = shift(tau <= 0.0 ? a0 : b0, tau);  // the path through the corner
  const double u = 1.0 - bw.w;
  PathJet out;
  out.p = A.p + B.p - b.corner - X.p;
  out.d1 = u * A.d1 + bw.w * B.d1 - X.d1;
  out.d2 = (u * u) * A.d2 + (bw.w * bw.w) * B.d2 + (bw.w1 / L) * (B.d1 - A.d1) - X.d2;
  return out;
}

PathJet corner_blend_at(const CornerBlend& b, double s, const PathJet& own) {
  const PathJet d = corner_blend_offset(b, s);
  return PathJet{own.p + d.p, own.d1 + d.d1, own.d2 + d.d2};
}

CornerBlend corner_of(const Vec3& corner, const Vec3& t_in, const Vec3& t_out, const Vec3& k_in, const Vec3& k_out) {
  CornerBlend b;
  b.corner = corner;
  b.t_in = t_in;
  b.t_out = t_out;
  b.k_in = k_in;
  b.k_out = k_out;
  return b;
}

CornerBlend corner_blend_plan(const CornerBlendInput& in) {
  CornerBlend out = corner_of(in.corner, in.t_in, in.t_out, in.k_in, in.k_out);
  const double sin_phi = norm(cross(in.t_in, in.t_out));
  const Vec3 d = in.t_out - in.t_in;
  const double kappa = std::max(0.0, in.curvature);
  if (!(norm(d) > 1e-9) || !(in.deviation > 0.0) || !(in.share > 0.0)) return out;
  // the window: the deviation budget c·sin φ·h + ½·κ·h² = δ, clipped to half of each block
  const double c = kBlendDeviation * sin_phi;
  const double h_dev = corner_blend_half_length(sin_phi, kappa, in.deviation);
  const double h = std::min({h_dev, 0.5 * in.len_in, 0.5 * in.len_out});
  if (!(h > 0.0) || !std::isfinite(h)) return out;
  const double L = 2.0 * h;
  // the corner speed: every sample of the window, every axis (the speed there at most
  // v_c² + 2(1 − share)·a_t·|τ|, the path acceleration there (1 − share)·a_t)
  constexpr int kSamples = 256;
  double v2 = std::numeric_limits<double>::infinity();
  for (int k = 0; k <= kSamples; ++k) {
    const double sigma = static_cast<double>(k) / kSamples;
    const double x = sigma - 0.5;  // τ/L
    const BlendWeight bw = blend_weight(sigma);
    const double a_t = (1.0 - in.share) * (sigma <= 0.5 ? in.accel_in : in.accel_out);
    const double extra = 2.0 * a_t * h * std::abs(2.0 * x);  // v² − v_c² at most there
    for (int i = 0; i < kAxes; ++i) {
      // |dp_i/ds|: the tangents turn by at most κ·h within the window
      const double p1 = std::abs((1.0 - bw.w) * in.t_in[i] + bw.w * in.t_out[i]) + kappa * h;
      // |d²p_i/ds²| ≤ κ·((1 − w)² + w²) + (w′/L)·(|d_i| + 2κh)
      const double p2 = kappa * ((1.0 - bw.w) * (1.0 - bw.w) + bw.w * bw.w) + bw.w1 / L * (std::abs(d[i]) + 2.0 * kappa * h);
      const double room = in.axis_accel[i] - a_t * p1;
      if (!(room > 0.0)) return out;
      if (p2 > 0.0) v2 = std::min(v2, room / p2 - extra);
      if (p1 > 0.0 && in.axis_velocity[i] > 0.0) v2 = std::min(v2, (in.axis_velocity[i] / p1) * (in.axis_velocity[i] / p1) - extra);
    }
  }
  v2 *= 0.995;  // the bounds between the samples
  if (!(v2 > 0.0)) return out;
  out.on = true;
  out.h = h;
  out.v_corner = std::sqrt(v2);
  out.deviation = c * h + 0.5 * kappa * h * h;
  return out;
}

}  // namespace pcnc
