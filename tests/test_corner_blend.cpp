// test_corner_blend.cpp — the rt's corner blend as pure geometry (shared/geometry/corner_blend):
// the weight, the offset's continuity at the window's ends, the deviation bound against the two
// blocks' paths (brute force), the per-axis acceleration bound, the plan's corner speed, and the
// degenerate cases (tiny turn, 179° turn, short blocks, zero-length windows).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "geometry/corner_blend.hpp"
#include "test_constants.hpp"

namespace pcnc {
namespace {


Vec3 unit_dir(double azimuth, double elevation) {
  return {std::cos(elevation) * std::cos(azimuth), std::cos(elevation) * std::sin(azimuth), std::sin(elevation)};
}

// Two straight blocks meeting at P: A along t_in ending at P, B along t_out from P.
CornerBlend line_corner(const Vec3& t_in, const Vec3& t_out, double h) {
  CornerBlend b;
  b.on = true;
  b.h = h;
  b.corner = {1.0, 2.0, 3.0};
  b.t_in = t_in;
  b.t_out = t_out;
  b.at = 10.0;
  return b;
}

// The blended point at path position s of the line corner (own path + offset).
PathJet blended_lines(const CornerBlend& b, double s) {
  const double tau = s - b.at;
  const Vec3& t = tau <= 0.0 ? b.t_in : b.t_out;
  return corner_blend_at(b, s, PathJet{b.corner + tau * t, t, {}});
}

double distance_to_ray(const Vec3& p, const Vec3& origin, const Vec3& dir, double sign) {
  double x = dot(p - origin, dir);
  if (sign * x < 0.0) x = 0.0;
  return norm(p - (origin + x * dir));
}

TEST(CornerBlend, WeightIsASmoothRampWithVanishingSlopeAtItsEnds) {
  EXPECT_EQ(blend_weight(-0.1).w, 0.0);
  EXPECT_EQ(blend_weight(1.2).w, 1.0);
  EXPECT_NEAR(blend_weight(0.5).w, 0.5, 1e-15);
  EXPECT_NEAR(blend_weight(0.5).w1, kBlendCurvature, 1e-15);
  EXPECT_NEAR(blend_weight(1e-9).w1, 0.0, 1e-7);
  EXPECT_NEAR(blend_weight(1.0 - 1e-9).w1, 0.0, 1e-7);
  double prev = 0.0;
  for (int k = 1; k <= 100; ++k) {
    const double w = blend_weight(k / 100.0).w;
    EXPECT_GE(w, prev);
    prev = w;
  }
}

TEST(CornerBlend, OffsetVanishesWithItsSlopeAndCurvatureAtTheWindowEnds) {
  // position, velocity and acceleration join the blocks' own continuously: just inside the window
  // the offset and its first two derivatives tend to 0 (the acceleration as fast as the slope of w′)
  for (double phi : {0.05, 0.4, kPi / 2, 2.5, 3.1}) {
    const CornerBlend b = line_corner({1, 0, 0}, {std::cos(phi), std::sin(phi), 0}, 0.05);
    for (double s : {b.at - b.h + 1e-7, b.at + b.h - 1e-7}) {
      const PathJet o = corner_blend_offset(b, s);
      EXPECT_LT(norm(o.p), 1e-12) << phi;
      EXPECT_LT(norm(o.d1), 1e-9) << phi;
      EXPECT_LT(norm(o.d2), 1e-3) << phi;  // w′ ~ 6σ: 6·(1e-7/0.1)/0.1 = 6e-5 per unit turn
    }
    for (double s : {b.at - b.h - 1e-3, b.at + b.h + 1e-3, b.at - b.h, b.at + b.h}) {
      const PathJet o = corner_blend_offset(b, s);
      EXPECT_EQ(norm(o.p) + norm(o.d1) + norm(o.d2), 0.0);
    }
    // continuous across the corner itself (the own block changes from A to B there)
    const PathJet l = blended_lines(b, b.at - 1e-9), r = blended_lines(b, b.at + 1e-9);
    EXPECT_LT(norm(l.p - r.p), 1e-8);
    EXPECT_LT(norm(l.d1 - r.d1), 1e-6);
    EXPECT_LT(norm(l.d2 - r.d2), 1e-4);
  }
}

TEST(CornerBlend, DerivativesAreThoseOfThePoint) {
  // the stated d1 and d2 are the derivatives of the blended point (finite differences)
  const CornerBlend b = line_corner(unit_dir(0.3, 0.1), unit_dir(1.2, -0.4), 0.08);
  const double e = 1e-5;
  for (double x = -0.95; x <= 0.95; x += 0.1) {
    const double s = b.at + x * b.h;
    const PathJet m = blended_lines(b, s - e), c = blended_lines(b, s), p = blended_lines(b, s + e);
    for (int i = 0; i < kAxes; ++i) {
      EXPECT_NEAR((p.p[i] - m.p[i]) / (2 * e), c.d1[i], 1e-6) << x;
      EXPECT_NEAR((p.p[i] - 2 * c.p[i] + m.p[i]) / (e * e), c.d2[i], 2e-3) << x;
    }
  }
}

TEST(CornerBlend, DeviationFromTwoLinesIsWithinTheBoundAndReachesIt) {
  // brute force: every point of the window against the two blocks (rays from the corner)
  for (double phi_deg : {0.5, 5.0, 24.0, 45.0, 90.0, 135.0, 179.0}) {
    const double phi = phi_deg * kPi / 180.0;
    const Vec3 t_in = unit_dir(0.7, 0.2);
    Vec3 n = normalized(cross(t_in, {0, 0, 1}));
    const Vec3 t_out = std::cos(phi) * t_in + std::sin(phi) * n;
    const CornerBlend b = line_corner(t_in, t_out, 0.1);
    double worst = 0.0;
    for (int k = 0; k <= 20000; ++k) {
      const double s = b.at - b.h + 2.0 * b.h * k / 20000.0;
      const Vec3 p = blended_lines(b, s).p;
      const double d = std::min(distance_to_ray(p, b.corner, t_in, -1.0), distance_to_ray(p, b.corner, t_out, 1.0));
      worst = std::max(worst, d);
    }
    const double bound = kBlendDeviation * b.h * std::sin(phi);
    EXPECT_LE(worst, bound * (1.0 + 1e-9) + 1e-15) << phi_deg;
    EXPECT_GE(worst, 0.5 * bound) << phi_deg;  // the bound is not loose (exact below 90°)
    if (phi_deg <= 90.0) {
      EXPECT_NEAR(worst, bound, 1e-3 * bound) << phi_deg;
    }
  }
}

TEST(CornerBlend, SpeedInSpaceNeverExceedsThePathSpeedAndNeverOvershootsTheCorner) {
  // dp/ds is a convex combination of the two tangents; the points stay in the corner's cone
  for (double phi : {0.1, 1.0, kPi / 2, 3.0, 3.13}) {
    const Vec3 t_in{1, 0, 0}, t_out{std::cos(phi), std::sin(phi), 0};
    const CornerBlend b = line_corner(t_in, t_out, 0.02);
    for (int k = 0; k <= 1000; ++k) {
      const double s = b.at - b.h + 2.0 * b.h * k / 1000.0;
      const PathJet j = blended_lines(b, s);
      EXPECT_LE(norm(j.d1), 1.0 + 1e-12);
      EXPECT_GE(norm(j.d1), std::cos(phi / 2) - 1e-9);
      // p − P = α·t_in + β·t_out with α <= 0 <= β: never past the corner along the incoming block
      EXPECT_LE(dot(j.p - b.corner, t_in), std::max(0.0, std::cos(phi)) * 2.0 * b.h + 1e-12);
    }
  }
}

TEST(CornerBlend, AccelerationOfEachAxisIsWithinTheStatedBound) {
  // |d²p_i/ds²| <= 1.5·|t_out,i − t_in,i|/L, reached at the window's middle
  const Vec3 t_in = unit_dir(0.0, -0.21), t_out = unit_dir(0.0, 0.21);  // a 24° turn in XZ
  const CornerBlend b = line_corner(t_in, t_out, 0.06);
  const double L = 2.0 * b.h;
  std::array<double, kAxes> worst{};
  for (int k = 0; k <= 4000; ++k) {
    const double s = b.at - b.h + 2.0 * b.h * k / 4000.0;
    const PathJet j = blended_lines(b, s);
    for (int i = 0; i < kAxes; ++i) worst[static_cast<std::size_t>(i)] = std::max(worst[static_cast<std::size_t>(i)], std::abs(j.d2[i]));
  }
  for (int i = 0; i < kAxes; ++i) {
    const double bound = kBlendCurvature * std::abs(t_out[i] - t_in[i]) / L;
    EXPECT_LE(worst[static_cast<std::size_t>(i)], bound * (1.0 + 1e-9) + 1e-12) << i;
    EXPECT_GE(worst[static_cast<std::size_t>(i)], bound * (1.0 - 1e-3)) << i;
  }
}

TEST(CornerBlend, ArcIntoLineStaysWithinTheBoundOfTheirPaths) {
  // block A: an arc of radius r in XY ending at P with tangent +Y; block B: a line turning 40° up
  const double r = 1.09, h = 0.03;
  const Vec3 P{r, 0, 0};
  const Vec3 t_in{0, 1, 0};
  const Vec3 t_out = unit_dir(kPi / 2, 40.0 * kPi / 180.0);
  CornerBlend b = line_corner(t_in, t_out, h);
  b.corner = P;
  b.k_in = {-1.0 / r, 0, 0};  // towards the centre
  auto arc = [&](double tau) {  // A at arc length τ <= 0 from its end (counter-clockwise to P)
    const double th = tau / r;
    return PathJet{{r * std::cos(th), r * std::sin(th), 0}, {-std::sin(th), std::cos(th), 0}, {-std::cos(th) / r, -std::sin(th) / r, 0}};
  };
  double worst = 0.0;
  for (int k = 0; k <= 4000; ++k) {
    const double s = b.at - b.h + 2.0 * b.h * k / 4000.0;
    const double tau = s - b.at;
    const PathJet own = tau <= 0.0 ? arc(tau) : PathJet{P + tau * t_out, t_out, {}};
    const Vec3 p = corner_blend_at(b, s, own).p;
    double d = distance_to_ray(p, P, t_out, 1.0);
    for (int m = 0; m <= 2000; ++m) d = std::min(d, norm(p - arc(-0.2 * m / 2000.0).p));
    worst = std::max(worst, d);
  }
  const double sin_phi = norm(cross(t_in, t_out));
  const double bound = kBlendDeviation * h * sin_phi + 0.5 * (1.0 / r) * h * h;
  EXPECT_LE(worst, bound + 1e-7);  // + the brute force's sampling of the arc (0.1 µm)
  EXPECT_GT(worst, 0.5 * kBlendDeviation * h * sin_phi);
  // and the own block's exact jet joins continuously at the window's start
  const PathJet in = corner_blend_at(b, b.at - b.h + 1e-9, arc(-b.h + 1e-9));
  EXPECT_LT(norm(in.p - arc(-b.h).p), 1e-8);
}

TEST(CornerBlend, HalfLengthMeetsTheBudget) {
  EXPECT_NEAR(kBlendDeviation * corner_blend_half_length(0.4, 0.0, 0.002) * 0.4, 0.002, 1e-15);
  const double h = corner_blend_half_length(0.4, 2.0, 0.002);
  EXPECT_NEAR(kBlendDeviation * h * 0.4 + 0.5 * 2.0 * h * h, 0.002, 1e-15);
  EXPECT_TRUE(std::isinf(corner_blend_half_length(0.0, 0.0, 0.002)));  // straight on: no limit from the budget
  EXPECT_EQ(corner_blend_half_length(0.4, 0.0, 0.0), 0.0);
}

CornerBlendInput mill_input(double phi_deg, double len_in, double len_out) {
  CornerBlendInput in;
  const double phi = phi_deg * kPi / 180.0;
  in.corner = {5, 5, 5};
  in.t_in = unit_dir(0.0, -phi / 2);
  in.t_out = unit_dir(0.0, phi / 2);
  in.len_in = len_in;
  in.len_out = len_out;
  in.deviation = 0.002;
  in.share = 0.5;
  in.accel_in = in.accel_out = 2000.0;
  in.axis_accel = {2000.0, 2000.0, 1000.0};
  in.axis_velocity = {100.0, 100.0, 50.0};
  return in;
}

TEST(CornerBlend, PlanKeepsEveryAxisWithinItsLimitAtItsCornerSpeed) {
  // the plan's corner speed v_c with the speed profile it assumes (v² <= v_c² + 2(1 − share)·a·|τ|,
  // path acceleration (1 − share)·a): every axis's acceleration within its limit, sampled finely
  for (double phi_deg : {2.0, 12.0, 24.0, 45.0, 60.0}) {
    const CornerBlendInput in = mill_input(phi_deg, 2.0, 2.0);
    CornerBlend b = corner_blend_plan(in);
    ASSERT_TRUE(b.on) << phi_deg << " h " << b.h;
    EXPECT_LE(b.deviation, in.deviation * (1.0 + 1e-12));
    b.at = 0.0;
    const double a_t = (1.0 - in.share) * in.accel_in;
    double worst = 0.0;
    for (int k = 0; k <= 2000; ++k) {
      const double s = -b.h + 2.0 * b.h * k / 2000.0;
      const PathJet j = blended_lines(b, s);
      for (double sign : {-1.0, 1.0}) {
        const double v2 = b.v_corner * b.v_corner + 2.0 * a_t * std::abs(s);
        for (int i = 0; i < kAxes; ++i) {
          const double acc = std::abs(sign * a_t * j.d1[i] + v2 * j.d2[i]);
          worst = std::max(worst, acc / in.axis_accel[static_cast<std::size_t>(i)]);
          EXPECT_LE(std::sqrt(v2) * std::abs(j.d1[i]), in.axis_velocity[static_cast<std::size_t>(i)] * (1 + 1e-12));
        }
      }
    }
    EXPECT_LE(worst, 1.0 + 1e-9) << phi_deg;
    EXPECT_GT(worst, 0.8) << phi_deg;  // and the speed is not needlessly low
  }
}

TEST(CornerBlend, DegenerateCases) {
  // no turn: no blend
  CornerBlendInput in = mill_input(0.0, 2.0, 2.0);
  EXPECT_FALSE(corner_blend_plan(in).on);
  // a tiny turn: a long window (clipped to half of each block), a high corner speed
  in = mill_input(0.01, 2.0, 2.0);
  CornerBlend b = corner_blend_plan(in);
  EXPECT_TRUE(b.on);
  EXPECT_NEAR(b.h, 1.0, 1e-12);
  EXPECT_GT(b.v_corner, 40.0);
  // 179°: the deviation budget allows any window (sin φ ≈ 0.017), but no corner speed keeps the
  // bound: the speed may grow at (1 − share)·a from the corner faster than the window's curvature
  // falls (the plan assumes the speed law around the corner); a short window does not help
  in = mill_input(179.0, 2.0, 2.0);
  EXPECT_GT(corner_blend_half_length(std::sin(179.0 * kPi / 180.0), 0.0, 0.002), 0.5);
  EXPECT_FALSE(corner_blend_plan(in).on);
  EXPECT_FALSE(corner_blend_plan(mill_input(179.0, 0.02, 0.02)).on);
  // short blocks: the window is clipped to half of the shorter
  in = mill_input(24.0, 0.01, 3.0);
  b = corner_blend_plan(in);
  EXPECT_TRUE(b.on);
  EXPECT_NEAR(b.h, 0.005, 1e-15);
  // zero-length window: no blend; the offset of a window of h = 0 is 0
  in = mill_input(24.0, 0.0, 3.0);
  EXPECT_FALSE(corner_blend_plan(in).on);
  CornerBlend z = line_corner({1, 0, 0}, {0, 1, 0}, 0.0);
  EXPECT_EQ(norm(corner_blend_offset(z, z.at).p), 0.0);
  // no budget: no blend
  in = mill_input(24.0, 2.0, 2.0);
  in.deviation = 0.0;
  EXPECT_FALSE(corner_blend_plan(in).on);
}

TEST(CornerBlend, OverlappingWindowsOfAShortBlockAddUpToOneSmoothPath) {
  // A → (a 2 µm line) → C, two 20° turns, both windows with the same h much longer than the line:
  // the sum of the offsets runs the short line forward, stays within the sum of the two bounds of
  // the polyline, and its velocity turns smoothly (no step from one cycle's sample to the next)
  const Vec3 ta = unit_dir(0.0, 0.0), tb = unit_dir(0.0, 20.0 * kPi / 180.0), tc = unit_dir(0.0, 40.0 * kPi / 180.0);
  const double ell = 0.002, h = 0.03;
  CornerBlend c1 = line_corner(ta, tb, h), c2 = line_corner(tb, tc, h);
  c1.at = 0.0;
  c2.at = ell;
  c1.corner = {0, 0, 0};
  c2.corner = c1.corner + ell * tb;
  auto own = [&](double s) {  // the programmed polyline by arc length
    if (s <= 0.0) return PathJet{s * ta, ta, {}};
    if (s <= ell) return PathJet{s * tb, tb, {}};
    return PathJet{c2.corner + (s - ell) * tc, tc, {}};
  };
  double worst = 0.0, jump = 0.0;
  Vec3 last_d1 = ta;
  for (int k = 0; k <= 4000; ++k) {
    const double s = -h - 0.001 + (2 * h + ell + 0.002) * k / 4000.0;
    const PathJet o1 = corner_blend_offset(c1, s), o2 = corner_blend_offset(c2, s);
    const PathJet x = own(s);
    const Vec3 p = x.p + o1.p + o2.p, d1 = x.d1 + o1.d1 + o2.d1;
    const double d = std::min({distance_to_ray(p, c1.corner, ta, -1.0), distance_to_ray(p, c2.corner, tc, 1.0),
                               norm(p - c1.corner), norm(p - c2.corner)});
    worst = std::max(worst, d);
    jump = std::max(jump, norm(d1 - last_d1));
    last_d1 = d1;
    EXPECT_LE(norm(d1), 1.0 + 1e-12);
  }
  const double bound = kBlendDeviation * h * (std::sin(20.0 * kPi / 180.0) * 2.0);
  EXPECT_LE(worst, bound + ell);
  EXPECT_LT(jump, 0.01);  // 4000 samples over a 0.7 rad turn of the tangent: smooth
}

}  // namespace
}  // namespace pcnc
