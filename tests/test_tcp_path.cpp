// test_tcp_path.cpp — joints along a tool-centre-point move and the path caps that keep them
// within their limits (issue 16, item 4): the samples reach the programmed poses; the move is
// then run in time at the caps (accelerate, cruise, decelerate), every joint's speed and
// acceleration measured by finite differences of the inverse kinematics on a 0.1 ms grid, and
// checked against its limits, and the limiting joint is seen to use its limit (the caps are
// not needlessly low). A move that passes near the singularity is slowed by C; one that passes
// through it is not.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "geometry/kinematics.hpp"
#include "geometry/tcp_path.hpp"
#include "test_constants.hpp"

namespace pcnc {
namespace {


JointLimits desk_limits() {
  // x y z: 50 mm/s, 500 mm/s²; A: 90°/s, 600°/s²; C: 180°/s, 1200°/s²
  return {{50, 50, 50, 90 * kDeg, 180 * kDeg}, {500, 500, 500, 600 * kDeg, 1200 * kDeg}};
}

Vec3 tilted(double tilt_deg, double toward_deg) {
  const double t = tilt_deg * kDeg, d = toward_deg * kDeg;
  return {std::sin(t) * std::cos(d), std::sin(t) * std::sin(d), std::cos(t)};
}

// The path position at time t of a move of length `len` run from rest to rest at most at
// speed v with acceleration a (trapezoid, or triangle when too short); total time in *total.
double s_at(double t, double len, double v, double a, double* total) {
  double ta = v / a, sa = 0.5 * a * ta * ta;
  if (2 * sa > len) {
    ta = std::sqrt(len / a);
    sa = 0.5 * len;
    v = a * ta;
  }
  const double tc = (len - 2 * sa) / v;
  *total = 2 * ta + tc;
  if (t <= ta) return 0.5 * a * t * t;
  if (t <= ta + tc) return sa + v * (t - ta);
  const double td = std::fmin(t - ta - tc, ta);
  return sa + v * tc + v * td - 0.5 * a * td * td;
}

struct Measured {
  Joints max_speed{}, max_accel{};
};

// Runs the move in time at the given speed and acceleration and measures the joints.
Measured run(const Kinematics& k, const TcpMove& m, double len, const Joints& start, double v, double a) {
  const AxisSlerp axes = make_axis_slerp(m.start.axis, m.end.axis);
  const double dt = 1e-4;
  double total = 0;
  s_at(0, len, v, a, &total);
  Measured out;
  Joints prev = start;
  auto q_at = [&](double t) {
    double unused = 0;
    const double s = s_at(std::fmin(std::fmax(t, 0.0), total), len, v, a, &unused);
    prev = inverse(k, tcp_pose(m, axes, s / len), prev);
    return prev;
  };
  Joints q0 = q_at(-dt), q1 = q_at(0.0);
  for (double t = dt; t <= total + 2 * dt; t += dt) {
    const Joints q2 = q_at(t);
    for (int j = 0; j < kJoints; ++j) {
      out.max_speed[j] = std::fmax(out.max_speed[j], std::abs(q2[j] - q0[j]) / (2 * dt));
      out.max_accel[j] = std::fmax(out.max_accel[j], std::abs(q2[j] - 2 * q1[j] + q0[j]) / (dt * dt));
    }
    q0 = q1;
    q1 = q2;
  }
  return out;
}

TEST(TcpPath, SamplesReachTheProgrammedPoses) {
  const Kinematics k{KinematicsKind::kTableTable, {0, 0, 40}, {2, -1, 0}, 20};
  const TcpMove m{{{-5, 3, 2}, tilted(30, 10)}, {{8, -4, -1}, tilted(50, 120)}};
  const auto samples = sample_tcp_move(k, m, 15.0, {0, 0, 0, 0.4, 0}, 101);
  ASSERT_GE(samples.size(), 101u);
  ASSERT_LE(samples.size(), 103u);  // at most the nearest points to +Z and −Z added
  const AxisSlerp axes = make_axis_slerp(m.start.axis, m.end.axis);
  for (const JointSample& js : samples) {
    const ToolPose want = tcp_pose(m, axes, js.s / 15.0);
    const ToolPose got = forward(k, js.q);
    ASSERT_LT(norm(got.tip - want.tip), 1e-9);
    ASSERT_LT(norm(got.axis - want.axis), 1e-12);
  }
  EXPECT_EQ(samples.front().s, 0.0);
  EXPECT_EQ(samples.back().s, 15.0);
  // dq/ds agrees with the differences of evenly spaced neighbours (0.15 mm apart)
  for (std::size_t i = 1; i + 1 < samples.size(); ++i) {
    const double h1 = samples[i].s - samples[i - 1].s, h2 = samples[i + 1].s - samples[i].s;
    ASSERT_GT(h1, 0.0);
    if (std::abs(h1 - h2) > 1e-12) continue;
    for (int j = 0; j < kJoints; ++j) {
      const double fd = (samples[i + 1].q[j] - samples[i - 1].q[j]) / (h1 + h2);
      ASSERT_NEAR(samples[i].dq[j], fd, 1e-3 * (1 + std::abs(fd)));
    }
  }
}

void caps_keep_joints_within_limits(const Kinematics& k, const TcpMove& m, double len, double feed, double accel,
                                    int expect_speed_joint /* -2: any */, int n = 2001) {
  const JointLimits lim = desk_limits();
  const Joints start = inverse(k, m.start, {0, 0, 0, 0.3, 0});
  const auto samples = sample_tcp_move(k, m, len, start, n);
  const PathCaps caps = tcp_path_caps(samples, lim, feed, accel);
  ASSERT_GT(caps.speed, 0.0);
  // the move's speed is the lowest of the per-sample profile
  double lowest = feed;
  for (const JointSample& js : samples) lowest = std::fmin(lowest, joint_speed_cap(js, lim, feed, nullptr));
  EXPECT_EQ(caps.speed, lowest);
  ASSERT_GT(caps.accel, 0.0);
  if (expect_speed_joint >= -1) {
    EXPECT_EQ(caps.speed_joint, expect_speed_joint);
  }
  const Measured got = run(k, m, len, start, caps.speed, caps.accel);
  for (int j = 0; j < kJoints; ++j) {
    EXPECT_LE(got.max_speed[j], lim.velocity[j] * 1.01) << "joint " << j;
    EXPECT_LE(got.max_accel[j], lim.acceleration[j] * 1.01) << "joint " << j;
  }
  if (caps.speed_joint >= 0 && caps.speed < feed) {
    // the joint that set the speed really comes close to its limit: the cap is not needlessly low
    const int j = caps.speed_joint;
    EXPECT_TRUE(got.max_speed[j] > 0.95 * lim.velocity[j] || got.max_accel[j] > 0.45 * lim.acceleration[j])
        << "joint " << j << " speed " << got.max_speed[j] << " accel " << got.max_accel[j];
  }
}

TEST(TcpPath, CapsKeepJointsWithinLimitsTableTable) {
  const Kinematics k{KinematicsKind::kTableTable, {0, 0, 40}, {2, -1, 0}, 20};
  // a strong reorientation over 10 mm: A and C need more than the feed allows
  const TcpMove m{{{-5, 3, 2}, tilted(10, 0)}, {{5, 3, 2}, tilted(60, 150)}};
  caps_keep_joints_within_limits(k, m, 10.0, 40.0, 2000.0, -2);
}

TEST(TcpPath, CapsKeepJointsWithinLimitsHeadTable) {
  const Kinematics k{KinematicsKind::kHeadTable, {0, 0, 80}, {0, 0, 0}, 30};
  // the head's long arm: a tilt swings the tip's joints in X and Z far more than the tip moves
  const TcpMove m{{{0, 0, 0}, tilted(-40, 0)}, {{2, 0, 0}, tilted(40, 0)}};
  const JointLimits lim = desk_limits();
  const Joints start = inverse(k, m.start, {0, 0, 0, -0.5, 0});
  const auto samples = sample_tcp_move(k, m, 2.0, start, 2001);
  const PathCaps caps = tcp_path_caps(samples, lim, 40.0, 2000.0);
  EXPECT_LT(caps.speed, 40.0);
  const Measured got = run(k, m, 2.0, start, caps.speed, caps.accel);
  for (int j = 0; j < kJoints; ++j) {
    EXPECT_LE(got.max_speed[j], lim.velocity[j] * 1.01) << "joint " << j;
    EXPECT_LE(got.max_accel[j], lim.acceleration[j] * 1.01) << "joint " << j;
  }
  EXPECT_LT(got.max_speed[kRotary], 1e-9);  // through the pole on a great circle: C stays
}

TEST(TcpPath, NearTheSingularityCSetsTheSpeed) {
  const Kinematics k{KinematicsKind::kTableTable, {0, 0, 40}, {0, 0, 0}, 20};
  // the axis passes 0.5° beside +Z (nearest halfway): C turns by about 180° within a few
  // degrees of the path
  const Vec3 side{std::sin(0.5 * kDeg), 0, std::cos(0.5 * kDeg)};
  const TcpMove m{{{0, -5, 0}, normalized(side + Vec3{0, -0.3, 0})}, {{0, 5, 0}, normalized(side + Vec3{0, 0.3, 0})}};
  caps_keep_joints_within_limits(k, m, 10.0, 40.0, 2000.0, kRotary);
  // independent bound: at the closest point the axis turns at θ/len rad/mm across the tilt
  // direction and C needs (θ/len)/sin(0.5°) rad/mm. With an even number of samples none falls
  // on the closest point but the one added there.
  const double theta = std::acos(dot(m.start.axis, m.end.axis));
  const double c_per_mm = theta / 10.0 / std::sin(0.5 * kDeg);
  for (int n : {2001, 100, 2}) {
    const auto samples = sample_tcp_move(k, m, 10.0, inverse(k, m.start, {0, 0, 0, 0.3, 0}), n);
    const PathCaps caps = tcp_path_caps(samples, desk_limits(), 40.0, 2000.0);
    EXPECT_EQ(caps.speed_joint, kRotary) << n;
    EXPECT_NEAR(caps.speed, 180 * kDeg / c_per_mm, 1e-6 * caps.speed) << n;
  }
}

TEST(TcpPath, ANearMissBetweenSamplesIsStillSeen) {
  // 0.1° beside the pole, 10 evenly spaced samples, none near the closest point: the sample
  // added there sets the cap, which the run in time confirms
  const Kinematics k{KinematicsKind::kHeadTable, {0, 0, 80}, {0, 0, 0}, 20};
  const Vec3 side{0, std::sin(0.1 * kDeg), std::cos(0.1 * kDeg)};
  const TcpMove m{{{-5, 0, 0}, normalized(side + Vec3{-0.2, 0, 0})}, {{5, 0, 0}, normalized(side + Vec3{0.3, 0, 0})}};
  caps_keep_joints_within_limits(k, m, 10.0, 40.0, 2000.0, kRotary, 10);
  // the evenly spaced samples alone would allow C far more than its speed
  auto samples = sample_tcp_move(k, m, 10.0, inverse(k, m.start, {0, 0, 0, -0.3, 0}), 10);
  ASSERT_EQ(samples.size(), 11u);
  const PathCaps with = tcp_path_caps(samples, desk_limits(), 40.0, 2000.0);
  std::erase_if(samples, [](const JointSample& js) {
    const double grid = js.s / (10.0 / 9);
    return std::abs(grid - std::round(grid)) > 1e-9;
  });
  ASSERT_EQ(samples.size(), 10u);
  const PathCaps without = tcp_path_caps(samples, desk_limits(), 40.0, 2000.0);
  EXPECT_GT(without.speed, 10 * with.speed);
}

TEST(TcpPath, LeavingThePoleCStartsWhereTheAxisLeavesIt) {
  // The tool stands vertical (on the C axis) and tilts 30° towards 50° in X-Y: C must be at
  // 50° (or 230° with the tilt negative) from the start, not jump there at the first step.
  const Kinematics k{KinematicsKind::kHeadTable, {0, 0, 80}, {1, 2, 0}, 20};
  const TcpMove m{{{0, 0, 0}, {0, 0, 1}}, {{4, 3, -1}, tilted(30, 50)}};
  struct Case {
    double previous_c_deg, start_c_deg, end_tilt_deg;
  };
  for (const Case& c : {Case{0, 50, 30}, Case{200, 230, -30}, Case{-340, -310, 30}, Case{-100, -130, -30}}) {
    const Joints previous{0, 0, 0, 0, c.previous_c_deg * kDeg};
    // the plain inverse at the start keeps the previous C: the move would start with a jump
    EXPECT_NEAR(inverse(k, m.start, previous)[kRotary], c.previous_c_deg * kDeg, 1e-12);
    const Joints start = tcp_start_joints(k, m, previous);
    EXPECT_NEAR(start[kRotary], c.start_c_deg * kDeg, 1e-9) << c.previous_c_deg;
    EXPECT_LT(norm(forward(k, start).tip - m.start.tip), 1e-9);
    const auto samples = sample_tcp_move(k, m, 5.0, previous, 501);
    EXPECT_EQ(samples.front().q, start);
    for (const JointSample& js : samples) ASSERT_NEAR(js.q[kRotary], start[kRotary], 1e-9) << js.s;
    EXPECT_NEAR(samples.back().q[kTilt], c.end_tilt_deg * kDeg, 1e-9);
  }
  // a head that tilts only −5°..+90° leaves the pole with the positive tilt: C = 50°, not 230°
  const RotaryTravel travel{-5 * kDeg, 90 * kDeg};
  const Joints previous{0, 0, 0, 0, 200 * kDeg};
  EXPECT_NEAR(tcp_start_joints(k, m, previous, travel)[kRotary], 50 * kDeg, 1e-9);
  const auto samples = sample_tcp_move(k, m, 5.0, previous, 101, travel);
  for (const JointSample& js : samples) ASSERT_NEAR(js.q[kRotary], 50 * kDeg, 1e-9);
  EXPECT_NEAR(samples.back().q[kTilt], 30 * kDeg, 1e-9);
}

TEST(TcpPath, SpeedProfileIsLowOnlyWhereAJointNeedsIt) {
  // the near miss of NearTheSingularityCSetsTheSpeed: C needs a low speed around the middle
  // only; at the ends, where the axis is 17° from the pole, the profile is far higher
  const Kinematics k{KinematicsKind::kTableTable, {0, 0, 40}, {0, 0, 0}, 20};
  const Vec3 side{std::sin(0.5 * kDeg), 0, std::cos(0.5 * kDeg)};
  const TcpMove m{{{0, -5, 0}, normalized(side + Vec3{0, -0.3, 0})}, {{0, 5, 0}, normalized(side + Vec3{0, 0.3, 0})}};
  const JointLimits lim = desk_limits();
  const auto samples = sample_tcp_move(k, m, 10.0, inverse(k, m.start, {0, 0, 0, 0.3, 0}), 101);
  int joint = -1;
  const double middle = joint_speed_cap(samples[50], lim, 40.0, &joint);
  EXPECT_EQ(joint, kRotary);
  const double end = joint_speed_cap(samples.front(), lim, 40.0, nullptr);
  EXPECT_GT(end, 20 * middle);
  // each sample's cap is the smallest of the formulas, recomputed here
  for (const JointSample& js : samples) {
    double want = 40.0;
    for (int j = 0; j < kJoints; ++j) {
      if (js.dq[j] != 0) want = std::fmin(want, lim.velocity[j] / std::abs(js.dq[j]));
      if (js.ddq[j] != 0) want = std::fmin(want, std::sqrt(lim.acceleration[j] / (2 * std::abs(js.ddq[j]))));
    }
    ASSERT_NEAR(joint_speed_cap(js, lim, 40.0, nullptr), want, 1e-12 * want);
  }
}

TEST(TcpPath, AMoveThatOnlyTurnsTheToolUsesAnAngularLength) {
  // the tip stays at (10, 5, 0) of the part while the axis turns by θ: the path parameter is
  // the angle (rad), the feed 1 rad/s; x, y, z swing around the pivots to hold the tip
  const Kinematics k{KinematicsKind::kTableTable, {0, 0, 40}, {2, -1, 0}, 20};
  const TcpMove m{{{10, 5, 0}, tilted(20, 0)}, {{10, 5, 0}, tilted(45, 90)}};
  const double theta = make_axis_slerp(m.start.axis, m.end.axis).angle;
  caps_keep_joints_within_limits(k, m, theta, 1.0, 20.0, -2);
  for (const JointSample& js : sample_tcp_move(k, m, theta, {0, 0, 0, 0.3, 0}, 201))
    ASSERT_LT(norm(forward(k, js.q).tip - Vec3{10, 5, 0}), 1e-9);
}

TEST(TcpPath, ThroughTheSingularityCIsNotMoved) {
  const Kinematics k{KinematicsKind::kTableTable, {0, 0, 40}, {0, 0, 0}, 20};
  const TcpMove m{{{0, -5, 0}, tilted(20, 90)}, {{0, 5, 0}, tilted(20, -90)}};
  const auto samples = sample_tcp_move(k, m, 10.0, inverse(k, m.start, {0, 0, 0, 0.3, 1.0}), 2001);
  for (const JointSample& js : samples) {
    ASSERT_NEAR(js.q[kRotary], samples.front().q[kRotary], 1e-12);
    ASSERT_NEAR(js.dq[kRotary], 0.0, 1e-9);
  }
  caps_keep_joints_within_limits(k, m, 10.0, 20.0, 2000.0, -2);
}

}  // namespace
}  // namespace pcnc
