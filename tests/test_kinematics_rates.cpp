// test_kinematics_rates.cpp — the analytic Jacobian and joint rates (issue 16, items 2 and 4)
// against central finite differences: the Jacobian against differences of the forward
// kinematics; dq/du against J (J·dq/du reproduces the pose's rate) and against differences of
// the inverse kinematics along a moving pose; d²q/du² against second differences of the inverse;
// the rotary rate at the singularity and its 1/sin(tilt) growth beside it.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "geometry/axis_slerp.hpp"
#include "geometry/kinematics.hpp"
#include "geometry/kinematics_rates.hpp"
#include "test_constants.hpp"

namespace pcnc {
namespace {


Kinematics random_rates_machine(KinematicsKind kind, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> p(-80.0, 80.0), len(0.0, 60.0);
  return {kind, {p(rng), p(rng), p(rng)}, {p(rng), p(rng), p(rng)}, len(rng)};
}

Joints random_joints(std::mt19937_64& rng, double min_sin_tilt) {
  std::uniform_real_distribution<double> pos(-100.0, 100.0), tilt(-kPi, kPi), rot(-3 * kPi, 3 * kPi);
  for (;;) {
    const Joints q{pos(rng), pos(rng), pos(rng), tilt(rng), rot(rng)};
    if (std::abs(std::sin(q[kTilt])) >= min_sin_tilt) return q;
  }
}

std::array<double, 6> pose_vector(const ToolPose& p) {
  return {p.tip[0], p.tip[1], p.tip[2], p.axis[0], p.axis[1], p.axis[2]};
}

const KinematicsKind kKinds[] = {KinematicsKind::kTableTable, KinematicsKind::kHeadTable, KinematicsKind::kTrivial};

TEST(KinematicsRates, JacobianMatchesCentralDifferences) {
  std::mt19937_64 rng(11);
  const double h = 1e-6;
  for (KinematicsKind kind : kKinds)
    for (int i = 0; i < 500; ++i) {
      const Kinematics k = random_rates_machine(kind, rng);
      const Joints q = random_joints(rng, 0.0);
      const Jacobian j = jacobian(k, q);
      for (int col = 0; col < kJoints; ++col) {
        Joints qp = q, qm = q;
        qp[col] += h;
        qm[col] -= h;
        const auto fp = pose_vector(forward(k, qp)), fm = pose_vector(forward(k, qm));
        for (int row = 0; row < 6; ++row)
          ASSERT_NEAR(j[row][col], (fp[row] - fm[row]) / (2 * h), 2e-6) << "row " << row << " col " << col;
      }
    }
}

TEST(KinematicsRates, JointRatesInvertTheJacobian) {
  std::mt19937_64 rng(12);
  std::uniform_real_distribution<double> r(-2.0, 2.0);
  for (KinematicsKind kind : {KinematicsKind::kTableTable, KinematicsKind::kHeadTable})
    for (int i = 0; i < 2000; ++i) {
      const Kinematics k = random_rates_machine(kind, rng);
      const Joints q = random_joints(rng, 0.05);
      const Joints dq{r(rng), r(rng), r(rng), r(rng), r(rng)};
      const Jacobian j = jacobian(k, q);
      PoseRate d1;
      for (int row = 0; row < 3; ++row)
        for (int col = 0; col < kJoints; ++col) {
          d1.tip[row] += j[row][col] * dq[col];
          d1.axis[row] += j[3 + row][col] * dq[col];
        }
      const Joints back = joint_rates(k, q, d1);
      for (int col = 0; col < kJoints; ++col) ASSERT_NEAR(back[col], dq[col], 1e-9) << col;
    }
}

// A pose moving along u: tip on a helix-like curve, axis on a great circle (both smooth).
struct MovingPose {
  Vec3 tip0, tip1;
  AxisSlerp axes;
  ToolPose at(double u) const {
    return {tip0 + u * tip1 + Vec3{3 * std::sin(u), 2 * std::cos(2 * u), u * u}, slerp_axis(axes, u)};
  }
  PoseRate d1(double u) const {
    return {tip1 + Vec3{3 * std::cos(u), -4 * std::sin(2 * u), 2 * u}, slerp_axis_d1(axes, u)};
  }
  PoseRate d2(double u) const { return {Vec3{-3 * std::sin(u), -8 * std::cos(2 * u), 2}, slerp_axis_d2(axes, u)}; }
};

TEST(KinematicsRates, RatesAndAccelsMatchDifferencesOfTheInverse) {
  std::mt19937_64 rng(13);
  std::uniform_real_distribution<double> pos(-50.0, 50.0), u01(0.2, 0.8);
  std::normal_distribution<double> n(0.0, 1.0);
  const double h = 1e-3;  // five-point stencils: truncation O(h⁴)
  int tested = 0;
  for (KinematicsKind kind : kKinds)
    for (int i = 0; i < 400; ++i) {
      const Kinematics k = random_rates_machine(kind, rng);
      const Vec3 a = normalized(Vec3{n(rng), n(rng), 1.5 + std::abs(n(rng))});
      const Vec3 b = normalized(Vec3{n(rng), n(rng), 1.5 + std::abs(n(rng))});
      const MovingPose m{{pos(rng), pos(rng), pos(rng)}, {pos(rng), pos(rng), pos(rng)}, make_axis_slerp(a, b)};
      const double u = u01(rng);
      const Joints q = inverse(k, m.at(u), {0, 0, 0, 0.3, 0});
      if (kind != KinematicsKind::kTrivial && std::abs(std::sin(q[kTilt])) < 0.1) continue;
      ++tested;
      const Joints qp = inverse(k, m.at(u + h), q), qm = inverse(k, m.at(u - h), q);
      const Joints qpp = inverse(k, m.at(u + 2 * h), qp), qmm = inverse(k, m.at(u - 2 * h), qm);
      const Joints dq = joint_rates(k, q, m.d1(u));
      const Joints ddq = joint_accels(k, q, dq, m.d2(u));
      for (int j = 0; j < kJoints; ++j) {
        const double fd1 = (qmm[j] - 8 * qm[j] + 8 * qp[j] - qpp[j]) / (12 * h);
        const double fd2 = (-qmm[j] + 16 * qm[j] - 30 * q[j] + 16 * qp[j] - qpp[j]) / (12 * h * h);
        ASSERT_NEAR(dq[j], fd1, 1e-6 * (1 + std::abs(fd1))) << "joint " << j << " kind " << static_cast<int>(kind);
        ASSERT_NEAR(ddq[j], fd2, 1e-5 * (1 + std::abs(fd2))) << "joint " << j << " kind " << static_cast<int>(kind);
      }
    }
  EXPECT_GT(tested, 1000);
}

TEST(KinematicsRates, RotaryRateIsZeroAtTheSingularityAndGrowsAsOneOverSinBeside) {
  for (KinematicsKind kind : {KinematicsKind::kTableTable, KinematicsKind::kHeadTable}) {
    const Kinematics k{kind, {3, -4, 40}, {7, 2, 0}, 15};
    // at the pole, any axis rate gives C no speed; the tilt takes the rate along its direction
    const Joints pole{10, 10, 10, 0.0, 0.4};
    const Vec3 n_t = jacobian(k, pole)[3][kTilt] * Vec3{1, 0, 0} + jacobian(k, pole)[4][kTilt] * Vec3{0, 1, 0};
    const Joints at = joint_rates(k, pole, {{0, 0, 0}, Vec3{0.3, -0.7, 0}});
    EXPECT_EQ(at[kRotary], 0.0);
    EXPECT_NEAR(at[kTilt], dot(Vec3{0.3, -0.7, 0}, n_t), 1e-15);
    // beside it, an axis rate of 1 rad/u across the tilt direction needs C' = 1/sin(tilt)
    for (double tilt : {0.1, 1e-3, 1e-6}) {
      const Joints q{10, 10, 10, tilt, 0.4};
      const Jacobian j = jacobian(k, q);
      const Vec3 across = normalized(Vec3{j[3][kRotary], j[4][kRotary], j[5][kRotary]});
      const Joints r = joint_rates(k, q, {{0, 0, 0}, across});
      EXPECT_NEAR(r[kRotary] * std::sin(tilt), 1.0, 1e-9) << tilt;
      EXPECT_NEAR(r[kTilt], 0.0, 1e-9);
    }
  }
}

}  // namespace
}  // namespace pcnc
