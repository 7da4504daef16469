// test_kinematics.cpp — forward and inverse kinematics (issue 16, item 2) of the table-table
// XYZAC and head-table XYZBC machines against independent computations: poses worked out by
// hand, forward∘inverse = identity over thousands of seeded random poses, inverse∘forward on
// joints away from the singularity (both solutions, C unwrapped to the previous turn), the
// rotary directions stated in docs/kinematics.md, and the singularity (C kept, no jump).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "geometry/kinematics.hpp"
#include "test_constants.hpp"

namespace pcnc {
namespace {


void expect_near_vec(const Vec3& a, const Vec3& b, double tol) {
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(a[i], b[i], tol) << "component " << i;
}

Kinematics table_table(const Vec3& a_pivot, const Vec3& c_pivot, double tool) {
  return {KinematicsKind::kTableTable, a_pivot, c_pivot, tool};
}
Kinematics head_table(const Vec3& b_pivot, const Vec3& c_pivot, double tool) {
  return {KinematicsKind::kHeadTable, b_pivot, c_pivot, tool};
}

Vec3 random_unit_vec(std::mt19937_64& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  for (;;) {
    const Vec3 v{n(rng), n(rng), n(rng)};
    if (norm(v) > 1e-3) return normalized(v);
  }
}

Kinematics random_machine(KinematicsKind kind, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> p(-80.0, 80.0), len(0.0, 60.0);
  return {kind, {p(rng), p(rng), p(rng)}, {p(rng), p(rng), p(rng)}, len(rng)};
}

// --- poses by hand ---------------------------------------------------------------------------

TEST(Kinematics, ZeroJointsAreTheMachineFrameWithTheToolAlongZ) {
  for (const Kinematics& k : {table_table({1, 2, 30}, {4, -5, 0}, 25), head_table({0, 0, 90}, {3, 3, 0}, 25)}) {
    const ToolPose p = forward(k, {10, 20, 30, 0, 0});
    expect_near_vec(p.tip, {10, 20, 5}, 1e-12);  // gauge point minus the tool length
    expect_near_vec(p.axis, {0, 0, 1}, 1e-12);
  }
}

TEST(Kinematics, TableTableKnownPoseByHand) {
  // A axis through (0, 0, 50), C axis through (5, 3, ·), tool 20 mm; x y z = (5, 3, 90),
  // A = C = 90°. The tip in machine coordinates is (5, 3, 70); from the A pivot (5, 3, 20);
  // turned +90° about X: (5, −20, 3), back from the pivot: (5, −20, 53); from the C axis
  // (0, −23, 53), turned +90° about Z: (23, 0, 53), back: (28, 3, 53). The axis: ez turned
  // +90° about X is −ey, then +90° about Z is +ex.
  const Kinematics k = table_table({0, 0, 50}, {5, 3, 0}, 20);
  const ToolPose p = forward(k, {5, 3, 90, 90 * kDeg, 90 * kDeg});
  expect_near_vec(p.tip, {28, 3, 53}, 1e-12);
  expect_near_vec(p.axis, {1, 0, 0}, 1e-12);
  // and the inverse finds the same joints from near them
  const Joints q = inverse(k, p, {0, 0, 0, 80 * kDeg, 80 * kDeg});
  const Joints want{5, 3, 90, 90 * kDeg, 90 * kDeg};
  for (int j = 0; j < kJoints; ++j) EXPECT_NEAR(q[j], want[j], 1e-12) << j;
}

TEST(Kinematics, HeadTableKnownPoseByHand) {
  // B pivot 100 mm above the gauge point, tool 30 mm: at B = 0 the tip is 130 mm below the
  // pivot; B = +90° (right-handed about Y) swings it to 130 mm along −X, level with the pivot:
  // tip (−130, 0, 100), axis +ex. C = +90° then turns both +90° about Z (C axis on Z).
  const Kinematics k = head_table({0, 0, 100}, {0, 0, 0}, 30);
  ToolPose p = forward(k, {0, 0, 0, 90 * kDeg, 0});
  expect_near_vec(p.tip, {-130, 0, 100}, 1e-12);
  expect_near_vec(p.axis, {1, 0, 0}, 1e-12);
  p = forward(k, {0, 0, 0, 90 * kDeg, 90 * kDeg});
  expect_near_vec(p.tip, {0, -130, 100}, 1e-12);
  expect_near_vec(p.axis, {0, 1, 0}, 1e-12);
}

TEST(Kinematics, RotaryDirectionsAsDocumented) {
  // docs/kinematics.md: +A turns the tool about +X right-handed relative to the workpiece,
  // +C about +Z; the axis is (sinA·sinC, −sinA·cosC, cosA) and for XYZBC (sinB·cosC, sinB·sinC, cosB).
  const Kinematics ac = table_table({0, 0, 0}, {0, 0, 0}, 0);
  const Kinematics bc = head_table({0, 0, 0}, {0, 0, 0}, 0);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> ang(-kPi, kPi);
  for (int i = 0; i < 100; ++i) {
    const double t = ang(rng), c = ang(rng);
    expect_near_vec(forward(ac, {0, 0, 0, t, c}).axis, {std::sin(t) * std::sin(c), -std::sin(t) * std::cos(c), std::cos(t)}, 1e-14);
    expect_near_vec(forward(bc, {0, 0, 0, t, c}).axis, {std::sin(t) * std::cos(c), std::sin(t) * std::sin(c), std::cos(t)}, 1e-14);
  }
  // A small +A tilts the tool towards −Y of the part; a point of the part on +X seen at +C
  // lies (relative to the tool) turned the other way: the table carries it to −C.
  EXPECT_LT(forward(ac, {0, 0, 0, 0.1, 0}).axis[1], 0.0);
  EXPECT_GT(forward(bc, {0, 0, 0, 0.1, 0}).axis[0], 0.0);
  // With the tool at machine (10, 0, 0) and C = +90°, the tip sits at the part's (0, 10, 0):
  // the table has turned −90° (clockwise seen from above) to bring that point under the tool.
  expect_near_vec(forward(ac, {10, 0, 0, 0, 90 * kDeg}).tip, {0, 10, 0}, 1e-12);
}

TEST(Kinematics, TheSeedsSphericalRulingIsTheHeadTablesBC) {
  // The seed's ruling R = (cosθ·sinφ, sinθ·sinφ, cosφ) (eq. 10) is the XYZBC axis at B = φ,
  // C = θ, and the XYZAC axis at A = φ, C = θ + 90° (docs/kinematics.md).
  const Kinematics ac = table_table({1, 2, 3}, {4, 5, 6}, 7);
  const Kinematics bc = head_table({1, 2, 3}, {4, 5, 6}, 7);
  std::mt19937_64 rng(8);
  std::uniform_real_distribution<double> theta(-kPi, kPi), phi(0, kPi);
  for (int i = 0; i < 100; ++i) {
    const double th = theta(rng), ph = phi(rng);
    const Vec3 r{std::cos(th) * std::sin(ph), std::sin(th) * std::sin(ph), std::cos(ph)};
    expect_near_vec(forward(bc, {9, 8, 7, ph, th}).axis, r, 1e-14);
    expect_near_vec(forward(ac, {9, 8, 7, ph, th + kPi / 2}).axis, r, 1e-14);
  }
}

TEST(Kinematics, TrivialMachineIsXyzMinusToolLength) {
  const Kinematics k{KinematicsKind::kTrivial, {1, 2, 3}, {4, 5, 6}, 12};
  const ToolPose p = forward(k, {1, 2, 3, 0.5, 0.7});
  expect_near_vec(p.tip, {1, 2, -9}, 0);
  expect_near_vec(p.axis, {0, 0, 1}, 0);
  const Joints q = inverse(k, {{4, 5, 6}, {1, 0, 0}}, {0, 0, 0, 1, 1});
  EXPECT_EQ(q, (Joints{4, 5, 18, 0, 0}));
}

// --- identities over random poses -------------------------------------------------------------

void forward_of_inverse_is_identity(KinematicsKind kind, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> pos(-150.0, 150.0), ang(-4.0 * kPi, 4.0 * kPi);
  double worst_tip = 0, worst_axis = 0;
  for (int i = 0; i < 5000; ++i) {
    const Kinematics k = random_machine(kind, rng);
    const ToolPose pose{{pos(rng), pos(rng), pos(rng)}, random_unit_vec(rng)};
    const Joints prev{pos(rng), pos(rng), pos(rng), ang(rng) / 4, ang(rng)};
    const Joints q = inverse(k, pose, prev);
    const ToolPose back = forward(k, q);
    worst_tip = std::fmax(worst_tip, norm(back.tip - pose.tip));
    worst_axis = std::fmax(worst_axis, norm(back.axis - pose.axis));
    // C is within half a turn of the previous C (unwrapped to its turn)
    ASSERT_LE(std::abs(q[kRotary] - prev[kRotary]), kPi + 1e-12);
  }
  EXPECT_LT(worst_tip, 1e-9);
  EXPECT_LT(worst_axis, 1e-12);
}

TEST(Kinematics, ForwardOfInverseIsIdentityTableTable) { forward_of_inverse_is_identity(KinematicsKind::kTableTable, 1); }
TEST(Kinematics, ForwardOfInverseIsIdentityHeadTable) { forward_of_inverse_is_identity(KinematicsKind::kHeadTable, 2); }

void inverse_of_forward_is_identity(KinematicsKind kind, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> pos(-150.0, 150.0), tilt(-kPi, kPi), rot(-6.0 * kPi, 6.0 * kPi),
      nudge(-0.05, 0.05);
  int tested = 0;
  while (tested < 5000) {
    const Kinematics k = random_machine(kind, rng);
    const Joints q{pos(rng), pos(rng), pos(rng), tilt(rng), rot(rng)};
    if (std::abs(std::sin(q[kTilt])) < 0.1) continue;  // away from the singularity
    ++tested;
    const ToolPose p = forward(k, q);
    // from joints near q: q itself, on the same turn of C
    Joints near = q;
    near[kTilt] += nudge(rng);
    near[kRotary] += nudge(rng);
    const Joints back = inverse(k, p, near);
    for (int j = 0; j < kJoints; ++j) ASSERT_NEAR(back[j], q[j], 1e-9) << "joint " << j << " pose " << tested;
    // from joints near the other solution (−tilt, C + π): that one, which reaches the same pose
    Joints other = q;
    other[kTilt] = -q[kTilt] + nudge(rng);
    other[kRotary] = q[kRotary] + kPi + nudge(rng);
    const Joints alt = inverse(k, p, other);
    ASSERT_NEAR(alt[kTilt], -q[kTilt], 1e-9);
    ASSERT_NEAR(alt[kRotary], q[kRotary] + kPi, 1e-9);
    const ToolPose pa = forward(k, alt);
    ASSERT_LT(norm(pa.tip - p.tip), 1e-9);
    ASSERT_LT(norm(pa.axis - p.axis), 1e-12);
  }
}

TEST(Kinematics, InverseOfForwardIsIdentityTableTable) { inverse_of_forward_is_identity(KinematicsKind::kTableTable, 3); }
TEST(Kinematics, InverseOfForwardIsIdentityHeadTable) { inverse_of_forward_is_identity(KinematicsKind::kHeadTable, 4); }

TEST(Kinematics, TravelPrefersTheReachableTilt) {
  // B from −30° to +110°: an axis tilted 60° is reached at B = +60° (C + 180°), even from
  // joints near the other solution (B = −60°), which the plain rule would take.
  const Kinematics k = head_table({0, 0, 90}, {0, 0, 0}, 20);
  const RotaryTravel travel{-30 * kDeg, 110 * kDeg};
  const ToolPose p = forward(k, {5, 6, 7, -60 * kDeg, 10 * kDeg});
  const Joints near_other{0, 0, 0, -55 * kDeg, 12 * kDeg};
  const Joints plain = inverse(k, p, near_other);
  EXPECT_NEAR(plain[kTilt], -60 * kDeg, 1e-12);
  const Joints q = inverse(k, p, near_other, travel);
  EXPECT_NEAR(q[kTilt], 60 * kDeg, 1e-12);
  EXPECT_NEAR(q[kRotary], 190 * kDeg, 1e-12);  // unwrapped nearest 12°: 190°, not −170°
  const ToolPose back = forward(k, q);
  EXPECT_LT(norm(back.tip - p.tip), 1e-9);
  EXPECT_LT(norm(back.axis - p.axis), 1e-12);
  // both inside: the nearer, as without a travel
  const Joints both = inverse(k, forward(k, {5, 6, 7, -20 * kDeg, 0}), {0, 0, 0, -0.3, 0}, travel);
  EXPECT_NEAR(both[kTilt], -20 * kDeg, 1e-12);
  // both outside (tilt 120°): the nearer one still, for the caller to refuse
  const Joints out = inverse(k, forward(k, {5, 6, 7, 120 * kDeg, 0}), {0, 0, 0, 2.0, 0}, travel);
  EXPECT_NEAR(out[kTilt], 120 * kDeg, 1e-12);
}

TEST(Kinematics, TravelPrefersTheReachableTurnOfC) {
  // A from −10° to +90°, C from −200° to +200°, now at 190°: an axis at A = 40°, C = 210°
  // (mod 360°) is reached at C = −150° (210° is beyond the travel; the other solution needs
  // A = −40°, beyond A's travel)
  const Kinematics k = table_table({0, 0, 30}, {1, 1, 0}, 10);
  const RotaryTravel travel{-10 * kDeg, 90 * kDeg, -200 * kDeg, 200 * kDeg};
  const ToolPose p = forward(k, {3, 4, 5, 40 * kDeg, 210 * kDeg});
  const Joints previous{0, 0, 0, 35 * kDeg, 190 * kDeg};
  EXPECT_NEAR(inverse(k, p, previous)[kRotary], 210 * kDeg, 1e-12);  // unbounded: the nearest
  const Joints q = inverse(k, p, previous, travel);
  EXPECT_NEAR(q[kTilt], 40 * kDeg, 1e-12);
  EXPECT_NEAR(q[kRotary], -150 * kDeg, 1e-12);
  EXPECT_LT(norm(forward(k, q).tip - p.tip), 1e-9);
  // with A allowed to −90°, of the two inside the travel the nearer: A = −40°, C = 30°
  // (75° + 160° from the previous joints, against 5° + 340°)
  const Joints q2 = inverse(k, p, previous, {-90 * kDeg, 90 * kDeg, -200 * kDeg, 200 * kDeg});
  EXPECT_NEAR(q2[kTilt], -40 * kDeg, 1e-12);
  EXPECT_NEAR(q2[kRotary], 30 * kDeg, 1e-12);
  // a continuous C (no travel) unwraps to the turn nearest the previous C: 570° from 500°
  const Joints q3 = inverse(k, p, {0, 0, 0, 35 * kDeg, 500 * kDeg}, {-10 * kDeg, 90 * kDeg});
  EXPECT_NEAR(q3[kRotary], 570 * kDeg, 1e-12);
}

TEST(Kinematics, UnwrapNear) {
  EXPECT_NEAR(unwrap_near(0.1, 4 * kPi), 4 * kPi + 0.1, 1e-12);
  EXPECT_NEAR(unwrap_near(-3.0, 3.0), 2 * kPi - 3.0, 1e-12);
  EXPECT_NEAR(unwrap_near(1.0, -20 * kPi + 1.2), -20 * kPi + 1.0, 1e-12);
}

// --- the singularity ---------------------------------------------------------------------------

TEST(Kinematics, AtTheSingularityCStaysWhereItWas) {
  for (KinematicsKind kind : {KinematicsKind::kTableTable, KinematicsKind::kHeadTable}) {
    const Kinematics k{kind, {3, -4, 40}, {7, 2, 0}, 15};
    for (double keep : {0.0, 1.3, -7.7, 40.0}) {
      const ToolPose p{{12, -3, 8}, {0, 0, 1}};
      const Joints q = inverse(k, p, {0, 0, 0, 0.2, keep});
      EXPECT_EQ(q[kRotary], keep);
      EXPECT_NEAR(q[kTilt], 0.0, 1e-15);
      const ToolPose back = forward(k, q);
      EXPECT_LT(norm(back.tip - p.tip), 1e-9);
    }
  }
}

TEST(Kinematics, APathThroughTheSingularityKeepsC) {
  // The tool axis swings on a great circle through +Z (the C axis): from tilted one way to
  // tilted the other. The tilt changes sign, C does not move at all.
  for (KinematicsKind kind : {KinematicsKind::kTableTable, KinematicsKind::kHeadTable}) {
    const Kinematics k{kind, {3, -4, 40}, {7, 2, 0}, 15};
    const Vec3 across = normalized(Vec3{0.6, -0.8, 0.0});
    const double c0 = kind == KinematicsKind::kTableTable ? std::atan2(across[0], -across[1]) : std::atan2(across[1], across[0]);
    Joints prev{0, 0, 0, 0.5, c0 + 6 * kPi};  // on its third turn
    double tilt_before = 0, max_dtilt = 0;
    const int n = 2001;  // odd: the middle sample is exactly on the pole
    for (int i = 0; i < n; ++i) {
      const double phi = 0.5 - 1.0 * i / (n - 1);  // +0.5 rad .. −0.5 rad through 0
      const ToolPose p{{10 + 0.01 * i, 5, -2}, std::cos(phi) * Vec3{0, 0, 1} + std::sin(phi) * across};
      const Joints q = inverse(k, p, prev);
      ASSERT_NEAR(q[kRotary], c0 + 6 * kPi, 1e-9) << "sample " << i;
      const ToolPose back = forward(k, q);
      ASSERT_LT(norm(back.tip - p.tip), 1e-9);
      ASSERT_LT(norm(back.axis - p.axis), 1e-12);
      if (i > 0) max_dtilt = std::fmax(max_dtilt, std::abs(q[kTilt] - tilt_before));
      tilt_before = q[kTilt];
      prev = q;
    }
    EXPECT_NEAR(tilt_before, -0.5, 1e-9);
    EXPECT_LT(max_dtilt, 1.0 / (n - 1) + 1e-9);  // the tilt moves evenly, no jump either
  }
}

}  // namespace
}  // namespace pcnc
