// corner_blend.hpp — the rt's corner blend (issue 14), pure geometry: at a flowing junction that
// turns by φ > 0, the commanded path is blended over an arc-length window [−h, h] centred on
// the corner (τ = s − s_corner, σ = (τ + h)/(2h), L = 2h), as the superposition of the two
// blocks run at complementary rates:
//
//   p(τ) = A(α(τ)) + B(β(τ)) − P,   β(τ) = ∫ w from −h to τ,   α(τ) = τ − β(τ),
//   w(σ) = 3σ² − 2σ³ (smoothstep),
//
// A(α) block A's path at arc length α from its end (α from −h to 0: its last h), B(β) block B's
// at β from its start (β from 0 to h), P the corner. So dp/ds = (1 − w)·A′ + w·B′, a convex
// combination of the two tangents: the path's speed in space never exceeds the path speed, and
// with straight blocks the blend stays inside the corner's cone (it never overshoots the corner
// along either block, so it cannot leave a travel the blocks keep). w′ vanishes at both window
// ends: position, velocity and acceleration join the blocks' own continuously.
// d²p/ds² = (1 − w)²·A″ + w²·B″ + (w′/L)·(B′ − A′).
//
// The executor adds the blend as an offset to the exact path of the block it is on:
// Δ(τ) = A(α) + B(β) − P − X(τ), X the path through the corner (A for τ ≤ 0, B after), every
// point from the blocks' jets at the corner (point, tangent, curvature vector): exact for lines,
// second order for curves, zero at and beyond the window's ends. Offsets of overlapping windows
// add up: for straight blocks the sum is exactly the superposition of all of them (the blended
// path is the programmed path, by arc length, convolved with the kernel w′/L), which is how a
// block shorter than the windows around it is passed: both corners' windows span it.
//
// Bounds (two straight blocks; `corner_blend_plan` adds the blocks' curvature κ):
//   distance from the two blocks' paths ≤ kBlendDeviation·h·sin φ (= β(0)·sin φ; + ½·κ·h²)
//   |d²p_i/ds²| ≤ 1.5·|t_b,i − t_a,i|/L (at σ = ½)
// The plan chooses h and the largest corner speed v_c such that, with the path speed changing
// by at most (1 − share)·a_t inside the window (a_t the path acceleration of the block on that
// side, so v(τ)² ≤ v_c² + 2(1 − share)·a_t·|τ|), every axis's acceleration
// (1 − share)·a_t·|p′_i| + v²·|p″_i| and velocity v·|p′_i| stay within its limits, and the
// deviation within the budget. Tests: tests/test_corner_blend.cpp.
#pragma once

#include <array>

#include "geometry/vec3.hpp"

namespace pcnc {

/// Deviation constant: β(0)/h = 2·∫₀^½ w = 0.1875 (the distance of the blend of two lines from
/// them is β·sin φ, largest at the corner).
constexpr double kBlendDeviation = 0.1875;
/// max w′ (at σ = ½: d²p/ds² = (t_b − t_a)·1.5/L there, for two lines).
constexpr double kBlendCurvature = 1.5;

/// The blend weight and its derivatives with respect to σ (0 below 0, 1 above 1).
struct BlendWeight {
  double w = 0.0, w1 = 0.0, w2 = 0.0;
};
BlendWeight blend_weight(double sigma);

/// A point of a path with its first and second derivatives with respect to arc length.
struct PathJet {
  Vec3 p{}, d1{}, d2{};
};

/// One corner's window: the corner point, the tangents in and out, the half-length h (0: no
/// blend) and the corner speed the bounds allow.
struct CornerBlend {
  bool on = false;
  double h = 0.0;       // half the window, mm (the window is [−h, h] around the corner)
  Vec3 corner{};
  Vec3 t_in{}, t_out{};  // unit: block A's end tangent, block B's start tangent
  Vec3 k_in{}, k_out{};  // curvature vectors (d²p/ds²) of block A at its end, block B at its start
  double at = 0.0;       // the corner's position along the path (arc length; the executor's)
  // from corner_blend_plan only (the executor keeps the planned junction speed and leaves them 0):
  double v_corner = 0.0;  // the largest speed at the corner for which the bounds hold, mm/s
  double deviation = 0.0;  // the bound on the distance from the blocks' paths, mm
  // the executor's bookkeeping: how far before the corner the window may reach (the block before
  // it, less the window at that block's start), and whether it shares its h with the corner before
  double reach = 0.0;
  bool grouped = false;
  double v_window = 0.0;  // the executor's: κ·h, the tangents' turn within the window (its speed cap's margin)
};

/// What a corner's plan needs: the geometry, the blocks' lengths (the window is clipped to half
/// of each, so the windows of consecutive corners never overlap), a bound on the curvature of the
/// two blocks near the corner (1/mm, 0 for lines), the deviation allowed, the share of
/// each axis's acceleration the blend's normal part may take (the path acceleration in the window
/// is limited to 1 − share of the blocks'), each block's largest path acceleration, and the axes'
/// limits.
struct CornerBlendInput {
  Vec3 corner{};
  Vec3 t_in{}, t_out{};
  Vec3 k_in{}, k_out{};
  double len_in = 0.0, len_out = 0.0;
  double curvature = 0.0;  // bound on |d²p/ds²| of either block within the window, 1/mm
  double deviation = 0.0;
  double share = 0.5;
  double accel_in = 0.0, accel_out = 0.0;  // the blocks' largest path accelerations, mm/s²
  std::array<double, kAxes> axis_accel{};
  std::array<double, kAxes> axis_velocity{};
};

/// A corner's geometry (the blend off, no window yet): the corner point, the tangents and the
/// curvature vectors of the two blocks there.
CornerBlend corner_of(const Vec3& corner, const Vec3& t_in, const Vec3& t_out, const Vec3& k_in, const Vec3& k_out);

/// The window and corner speed for a junction (on = false when the turn is 0, or no window of
/// positive length keeps every bound at a positive corner speed). Pure, no allocation.
CornerBlend corner_blend_plan(const CornerBlendInput& in);

/// The window's half-length for a deviation budget: the h with kBlendDeviation·h·sin_phi + ½·κ·h²
/// = deviation (sin_phi the turn's sine, or the sum of the sines of a group's turns; +infinity
/// when both are 0, 0 for no budget).
double corner_blend_half_length(double sin_phi, double curvature, double deviation);

/// The blend's offset Δ (and its first and second derivatives in arc length) at path position s
/// (τ = s − b.at): zero outside the window. The blended path is the block's own path plus Δ.
PathJet corner_blend_offset(const CornerBlend& b, double s);

/// The blended path at τ = s − b.at from the exact jet of the block the executor is on there
/// (block A for τ ≤ 0, block B after): own + corner_blend_offset.
PathJet corner_blend_at(const CornerBlend& b, double s, const PathJet& own);

}  // namespace pcnc
