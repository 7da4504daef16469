// bench_kinematics.cpp — the cost of the 5-axis kinematics (issue 16, item 2; never pass/fail):
// ns per inverse, per forward, per forward + Jacobian, per joint rates + accelerations (what a
// tool-centre-point cycle or a feed-forward needs), and per sampled move with its path caps, for
// the XYZAC table-table and XYZBC head-table machines, over seeded random poses; each figure is
// the best of --repeats runs. The figures depend on the computer and its load; the checksum
// keeps the compiler from dropping the work.

#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>
#include <vector>

#include "bench_cli.hpp"
#include "geometry/kinematics.hpp"
#include "geometry/kinematics_rates.hpp"
#include "geometry/tcp_path.hpp"

using namespace pcnc;
using Clock = std::chrono::steady_clock;

namespace {

double ns_per(Clock::time_point t0, Clock::time_point t1, long n) {
  return std::chrono::duration<double, std::nano>(t1 - t0).count() / static_cast<double>(n);
}

void bench(const char* name, const Kinematics& k, int n, int repeats, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> pos(-10.0, 10.0), tilt(-1.5, 1.5), rot(-3.0, 3.0), r(-1.0, 1.0);
  std::vector<Joints> qs(static_cast<std::size_t>(n));
  std::vector<ToolPose> poses(qs.size());
  std::vector<PoseRate> rates(qs.size());
  for (std::size_t i = 0; i < qs.size(); ++i) {
    qs[i] = {pos(rng), pos(rng), pos(rng), tilt(rng), rot(rng)};
    poses[i] = forward(k, qs[i]);
    rates[i] = {{r(rng), r(rng), r(rng)}, cross(poses[i].axis, Vec3{r(rng), r(rng), r(rng)})};
  }
  double sum = 0;
  // each figure: the best of `repeats` runs over all poses (the machine is shared: the best
  // run is the one least disturbed)
  auto best = [&](auto&& body) {
    double ns = 1e300;
    for (int r = 0; r < repeats; ++r) {
      const auto t0 = Clock::now();
      body();
      ns = std::fmin(ns, ns_per(t0, Clock::now(), n));
    }
    return ns;
  };
  const double inv = best([&] {
    for (std::size_t i = 0; i < qs.size(); ++i) sum += inverse(k, poses[i], qs[i == 0 ? 0 : i - 1])[kRotary];
  });
  const double fwd = best([&] {
    for (const Joints& q : qs) sum += forward(k, q).tip[0];
  });
  const double fj = best([&] {
    for (const Joints& q : qs) sum += forward(k, q).tip[1] + jacobian(k, q)[0][kRotary];
  });
  const double ra = best([&] {
    for (std::size_t i = 0; i < qs.size(); ++i) {
      const Joints dq = joint_rates(k, qs[i], rates[i]);
      sum += joint_accels(k, qs[i], dq, rates[i])[kTilt];
    }
  });
  std::printf("%-22s inverse %7.1f ns   forward %7.1f ns   forward+Jacobian %7.1f ns   rates+accels %7.1f ns\n", name,
              inv, fwd, fj, ra);

  const JointLimits lim{{50, 50, 50, 1.5, 3.0}, {500, 500, 500, 10, 20}};
  const TcpMove move{{{-5, 3, 2}, normalized(Vec3{0.1, 0.0, 1.0})}, {{5, 3, 2}, normalized(Vec3{0.5, 0.8, 0.6})}};
  const int moves = 200, samples = 101;
  double move_ns = 1e300;
  for (int r = 0; r < repeats; ++r) {
    const auto t0 = Clock::now();
    for (int i = 0; i < moves; ++i) {
      const auto s = sample_tcp_move(k, move, 10.0, {0, 0, 0, 0.1, 0}, samples);
      sum += tcp_path_caps(s, lim, 40.0, 1000.0).speed;
    }
    move_ns = std::fmin(move_ns, ns_per(t0, Clock::now(), moves));
  }
  std::printf("%-22s one move sampled at %d points with its caps: %.1f us (%.0f ns per sample)   [checksum %.3g]\n",
              name, samples, move_ns / 1000.0, move_ns / samples, sum);
}

}  // namespace

int main(int argc, char** argv) {
  pcnc::BenchCli app{"bench_kinematics: ns per inverse, forward, Jacobian and joint rates of the 5-axis kinematics"};
  int n = 200000, repeats = 5;
  app.add_option("-n", n, "poses per run")->positive();
  app.add_option("--repeats", repeats, "runs per figure; the best is printed")->positive();
  if (const int rc = app.parse(argc, argv); rc >= 0) return rc;
  bench("XYZAC table-table", {KinematicsKind::kTableTable, {0, 0, 40}, {2, -1, 0}, 20}, n, repeats, 1);
  bench("XYZBC head-table", {KinematicsKind::kHeadTable, {0, 0, 80}, {3, 1, 0}, 25}, n, repeats, 2);
  return 0;
}
