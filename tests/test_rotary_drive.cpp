// test_rotary_drive.cpp — the rotary joint through the same plant and servo as the linear axes
// (rt/drive, PlantModel and PidGains in rad): the plant J·dω/dt = Kt·i − b·ω − Tc·sign(ω)
// against an independent fine RK4 integration and against the analytic friction reversal, its
// stiction, current limit and rotary encoder; the PID's feed-forward in rad; and the closed loop
// of configs/desktop-5axis.toml's A and C on a step and on a full-speed move (following errors).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "config/config.hpp"
#include "drive/plant.hpp"
#include "drive/servo_pid.hpp"
#include "test_paths.hpp"
#include "machine_runner.hpp"

namespace pcnc {
namespace {

constexpr double kDt = 0.0005;  // the 2 kHz cycle


// RK4 of J·dω/dt = Kt·i − b·ω − Tc·sign(ω) with the current held over `h_total` (ω keeps its sign).
void rk4(const RotaryAxisConfig& j, double current, double h_total, double& th, double& w) {
  const int n = 500;
  const double h = h_total / n;
  auto f = [&](double ww) {
    const double s = ww > 0 ? 1.0 : (ww < 0 ? -1.0 : 0.0);
    return (j.torque_constant_nm_per_a * current - j.viscous_friction_nm_s_per_rad * ww - j.coulomb_friction_nm * s) /
           j.inertia_kg_m2;
  };
  for (int k = 0; k < n; ++k) {
    const double k1w = f(w), k1t = w;
    const double k2w = f(w + 0.5 * h * k1w), k2t = w + 0.5 * h * k1w;
    const double k3w = f(w + 0.5 * h * k2w), k3t = w + 0.5 * h * k2w;
    const double k4w = f(w + h * k3w), k4t = w + h * k3w;
    th += h / 6.0 * (k1t + 2 * k2t + 2 * k3t + k4t);
    w += h / 6.0 * (k1w + 2 * k2w + 2 * k3w + k4w);
  }
}

TEST(RotaryPlant, ExactZohAgainstAFineIndependentIntegration) {
  for (int idx : {0, 2}) {
    const RotaryAxisConfig j = *test::five_axis_config().rotary[static_cast<std::size_t>(idx)];
    AxisPlant plant(plant_model(j), kDt, 1, 0.3);
    // currents that always beat Coulomb friction: from rest the joint breaks away and turns one way
    const double i_min = 1.5 * j.coulomb_friction_nm / j.torque_constant_nm_per_a;
    double th = 0.3, w = 0.0;
    double max_dth = 0.0, max_dw = 0.0;
    for (int k = 0; k < 400; ++k) {
      const double i = i_min + 0.3 * j.current_limit_a * (1.0 + std::sin(k / 7.0)) / 2.0;
      plant.step(i, true);
      if (k == 0) w = 1e-300;  // past the breakaway the sign of ω is known: positive
      rk4(j, i, kDt, th, w);
      max_dth = std::max(max_dth, std::abs(plant.position() - th));
      max_dw = std::max(max_dw, std::abs(plant.velocity() - w));
    }
    EXPECT_GT(w, 1.0) << "it turned: " << j.letter;
    EXPECT_LT(max_dth, 1e-9) << j.letter;
    EXPECT_LT(max_dw, 1e-7 * std::max(1.0, std::abs(w))) << j.letter;
  }
}

// b = 0: constant deceleration through zero speed, then stiction decides, by hand.
TEST(RotaryPlant, FrictionReversalMatchesTheAnalyticSolution) {
  RotaryAxisConfig j = *test::five_axis_config().rotary[2];  // C: J 2e-4, Kt 0.15, Tc 0.01
  j.viscous_friction_nm_s_per_rad = 0.0;
  const double J = j.inertia_kg_m2, kt = j.torque_constant_nm_per_a, tc = j.coulomb_friction_nm;
  AxisPlant plant(plant_model(j), kDt, 1, 0.0);
  for (int k = 0; k < 10; ++k) plant.step(1.0, true);  // 5 ms at (Kt − Tc)/J
  const double a1 = (kt * 1.0 - tc) / J, t1 = 10 * kDt;
  const double w1 = a1 * t1, th1 = 0.5 * a1 * t1 * t1;
  EXPECT_NEAR(plant.velocity(), w1, 1e-9);
  EXPECT_NEAR(plant.position(), th1, 1e-12);
  for (int k = 0; k < 40; ++k) plant.step(-0.5, true);  // 20 ms: decelerate, stop, turn back
  const double d = (kt * 0.5 + tc) / J;                 // friction helps the brake
  const double t0 = w1 / d;                             // speed zero here
  const double a2 = (kt * 0.5 - tc) / J;                // from rest: the drive beats friction
  const double T = 40 * kDt;
  ASSERT_LT(t0, T);
  EXPECT_NEAR(plant.velocity(), -a2 * (T - t0), 1e-9);
  EXPECT_NEAR(plant.position(), th1 + w1 * t0 - 0.5 * d * t0 * t0 - 0.5 * a2 * (T - t0) * (T - t0), 1e-12);
}

TEST(RotaryPlant, StictionCurrentLimitAndTheRotaryEncoder) {
  const RotaryAxisConfig a = *test::five_axis_config().rotary[0];
  AxisPlant plant(plant_model(a), kDt, 1, 0.5);
  const double below = 0.9 * a.coulomb_friction_nm / a.torque_constant_nm_per_a;
  for (int k = 0; k < 100; ++k) plant.step(below, true);
  EXPECT_EQ(plant.position(), 0.5) << "a torque under the Coulomb friction does not move it";
  plant.step(100.0, true);
  EXPECT_EQ(plant.applied_current(), a.current_limit_a);
  // 0.0003 deg per count, in rad
  const double res = 0.0003 * std::numbers::pi / 180.0;
  for (double x : {0.1234567, -1.5, 2.0 * std::numbers::pi + 1e-7}) {
    plant.place(x);
    EXPECT_NEAR(plant.encoder(), std::nearbyint(x / res) * res, 1e-15);
    EXPECT_LE(std::abs(plant.encoder() - x), 0.5 * res + 1e-15);
  }
}

TEST(RotaryServo, FeedForwardAloneAtZeroErrorPerRadian) {
  const RotaryAxisConfig a = *test::five_axis_config().rotary[0];
  AxisPid pid(pid_gains(a), kDt);
  const double w = 2.0, acc = 50.0;  // rad/s, rad/s^2
  EXPECT_NEAR(pid.update(1.0, 1.0, w, acc),
              a.velocity_ff_a_s_per_rad * w + a.accel_ff_a_s2_per_rad * acc + a.friction_ff_a, 1e-12);
  // per radian: J/Kt of current per rad/s^2 accelerates the inertia
  EXPECT_NEAR(a.accel_ff_a_s2_per_rad * a.torque_constant_nm_per_a, a.inertia_kg_m2, 1e-6 * a.inertia_kg_m2);
}

struct RotaryLoop {
  explicit RotaryLoop(int idx)
      : j(*test::five_axis_config().rotary[static_cast<std::size_t>(idx)]), pid(pid_gains(j), kDt), plant(plant_model(j), kDt, 1, 0.0) {}
  double step(double sp, double v = 0.0, double acc = 0.0) {
    const double y = plant.encoder();
    plant.step(pid.update(sp, y, v, acc), true);
    return y;
  }
  RotaryAxisConfig j;
  AxisPid pid;
  AxisPlant plant;
};

TEST(RotaryServo, StepResponseSettlesOnAAndC) {
  for (int idx : {0, 2}) {
    RotaryLoop L(idx);
    const double step = 0.01 * std::numbers::pi / 180.0;  // 0.01 deg: 33 encoder counts
    for (int k = 0; k < 200; ++k) L.step(0.0);
    double peak = 0.0;
    for (int k = 0; k < 200; ++k) peak = std::max(peak, L.step(step));  // 100 ms
    EXPECT_NEAR(L.plant.position(), step, 3.0 * L.j.encoder_resolution_rad) << L.j.letter;
    EXPECT_LT(peak, 1.6 * step) << L.j.letter;  // overshoot under 60 %, as the linear axes
    EXPECT_GT(peak, step - 2.0 * L.j.encoder_resolution_rad) << "it reached the step: " << L.j.letter;
  }
}

// A trapezoidal move at the joint's limits (A: 90 deg at 180 deg/s and 3600 deg/s^2; C: a full
// turn at 360 deg/s and 7200 deg/s^2), with the setpoint's velocity and acceleration as feed-
// forward, as the rt's cycle gives them: the following error stays under a bound.
struct Profile {
  double distance, v, a;
  void at(double t, double& p, double& vel, double& acc) const {
    const double ta = v / a, da = 0.5 * a * ta * ta, tc = (distance - 2 * da) / v, total = 2 * ta + tc;
    if (t < ta) {
      p = 0.5 * a * t * t, vel = a * t, acc = a;
    } else if (t < ta + tc) {
      p = da + v * (t - ta), vel = v, acc = 0.0;
    } else if (t < total) {
      const double r = total - t;
      p = distance - 0.5 * a * r * r, vel = a * r, acc = -a;
    } else {
      p = distance, vel = 0.0, acc = 0.0;
    }
  }
};

double max_following_error(int idx, double distance, double& final_error) {
  RotaryLoop L(idx);
  const Profile prof{distance, L.j.max_velocity_rad_s, L.j.max_accel_rad_s2};
  double worst = 0.0;
  for (int k = 0; k < 4000; ++k) {  // 2 s
    double p, v, a;
    prof.at(k * kDt, p, v, a);
    const double y = L.step(p, v, a);
    worst = std::max(worst, std::abs(p - y));
  }
  final_error = std::abs(L.plant.position() - distance);
  return worst;
}

TEST(RotaryServo, FollowingErrorOfAFullSpeedMoveOnAAndC) {
  const double deg = 180.0 / std::numbers::pi;
  double final_a = 0.0, final_c = 0.0;
  const double fa = max_following_error(0, std::numbers::pi / 2, final_a);
  const double fc = max_following_error(2, 2 * std::numbers::pi, final_c);
  std::printf("max following error: A %.5f deg (%.2f um at 25 mm), C %.5f deg (%.2f um at 25 mm); at rest A %.6f, "
              "C %.6f deg\n",
              fa * deg, fa * 25e3, fc * deg, fc * 25e3, final_a * deg, final_c * deg);
  // measured 0.00075 deg on A and 0.0021 deg on C (0.3 and 0.9 um at 25 mm from the axis); the
  // bounds are twice that, and under a hundredth of the config's following-error limit (0.2 deg);
  // at rest within a few encoder counts
  EXPECT_LT(fa * deg, 0.0015);
  EXPECT_LT(fc * deg, 0.004);
  EXPECT_LT(final_a, 4 * test::five_axis_config().rotary[0]->encoder_resolution_rad);
  EXPECT_LT(final_c, 4 * test::five_axis_config().rotary[2]->encoder_resolution_rad);
}

}  // namespace
}  // namespace pcnc
