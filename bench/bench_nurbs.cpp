// bench_nurbs.cpp — NURBS timing figures (never pass/fail):
//  1. the rt's per-cycle cost: curve evaluation + Taylor step with its correction + speed
//     follower (NurbsFollower::step), degree 3, 32 control points (one full block), T = 0.5 ms;
//     min / mean / p50 / p99 / max over every cycle of repeated runs;
//  2. nurbs_parameter_step alone and nurbs_eval alone;
//  3. host preprocessing (plan_nurbs_blocks: validation, dense schedule, split, block
//     schedules) per control point, for curves of 32 .. 1000 control points.

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <random>
#include <vector>

#include "bench_cli.hpp"
#include "geometry/nurbs.hpp"
#include "ipc/block_nurbs.hpp"
#include "motion/nurbs_follower.hpp"
#include "gcode/nurbs_schedule.hpp"

using namespace pcnc;
using Clock = std::chrono::steady_clock;

namespace {

NurbsCurve wavy_curve(int count, int degree, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> d(-1.0, 1.0);
  std::vector<Vec3> pts{{2, 12, 20}};
  for (int i = 1; i < count; ++i) pts.push_back(pts.back() + Vec3{20.0 / count + 0.2 * d(rng) / count * 10, 0.8 * d(rng), 0.05 * d(rng)});
  std::vector<double> w;
  for (int i = 0; i < count; ++i) w.push_back(1.0 + 0.3 * d(rng));
  return make_nurbs(pts, w, degree + 1, KnotRule::kChordLength);
}

NurbsLimits limits(double feed) {
  NurbsLimits lim;
  lim.feed_mm_s = feed;
  lim.period_s = 0.0005;
  lim.chord_tolerance_mm = 0.001;
  lim.axis_velocity_mm_s = {100, 100, 50};
  lim.axis_accel_mm_s2 = {2000, 2000, 1000};
  return lim;
}

void report(const char* what, std::vector<double>& ns) {
  std::sort(ns.begin(), ns.end());
  double sum = 0;
  for (double v : ns) sum += v;
  auto at = [&](double q) { return ns[std::min(ns.size() - 1, static_cast<std::size_t>(q * ns.size()))]; };
  std::printf("%-44s n=%zu  min %.0f  mean %.0f  p50 %.0f  p99 %.0f  max %.0f ns\n", what, ns.size(), ns.front(),
              sum / ns.size(), at(0.5), at(0.99), ns.back());
}

}  // namespace

int main(int argc, char** argv) {
  pcnc::BenchCli app{"NURBS timing: rt cycle cost and host preprocessing"};
  int runs = 20;
  double feed = 60.0;
  app.add_option("--runs", runs, "repetitions of the block run")->show_default();
  app.add_option("--feed", feed, "path feed, mm/s")->show_default();
  if (const int rc = app.parse(argc, argv); rc >= 0) return rc;

  // 1. one 32-point cubic block, run to the end repeatedly, every cycle timed.
  const NurbsCurve curve = wavy_curve(kMaxNurbsPoints, 3, 1);
  const NurbsBlocks nb = plan_nurbs_blocks(curve, limits(feed));
  if (!nb.error.empty() || nb.blocks.size() != 1) {
    std::fprintf(stderr, "bench curve rejected: %s\n", nb.error.c_str());
    return 1;
  }
  const Block& b = nb.blocks[0];
  std::vector<double> cycle_ns, step_ns, eval_ns;
  double sink = 0.0;
  for (int r = 0; r < runs; ++r) {
    NurbsFollower f;
    f.start(b, 0.0);
    while (!f.done()) {
      const auto t0 = Clock::now();
      const Vec3 p = f.step(b, 0.0005, 0.0, 1.0);
      const auto t1 = Clock::now();
      sink += p[0];
      cycle_ns.push_back(std::chrono::duration<double, std::nano>(t1 - t0).count());
    }
  }
  std::printf("degree 3, %d control points, %.1f mm at %.0f mm/s: %zu cycles per run\n", kMaxNurbsPoints, b.length, feed,
              cycle_ns.size() / static_cast<std::size_t>(runs));
  report("rt cycle (eval + Taylor step + follower)", cycle_ns);

  // 2. the parts: parameter step at a typical ds, evaluation with derivatives.
  const NurbsView v = view_of(b.nurbs);
  const double ds = feed * 0.0005;
  for (int r = 0; r < runs; ++r) {
    double u = v.u_min();
    NurbsEval at = nurbs_eval(v, u);
    while (u < v.u_max()) {
      const auto t0 = Clock::now();
      const NurbsStep st = nurbs_parameter_step(v, u, at, ds);
      const auto t1 = Clock::now();
      step_ns.push_back(std::chrono::duration<double, std::nano>(t1 - t0).count());
      if (st.at_end) break;
      u = st.u;
      at = st.eval;
    }
    for (int i = 0; i < 20000; ++i) {
      const double uu = v.u_min() + (v.u_max() - v.u_min()) * (i + 0.5) / 20000.0;
      const auto t0 = Clock::now();
      const NurbsEval e = nurbs_eval(v, uu);
      const auto t1 = Clock::now();
      sink += e.p[1];
      eval_ns.push_back(std::chrono::duration<double, std::nano>(t1 - t0).count());
    }
  }
  report("nurbs_parameter_step (Taylor + Newton)", step_ns);
  report("nurbs_eval (point, C', C'')", eval_ns);

  // 3. host preprocessing per control point.
  for (const int count : {32, 100, 300, 1000}) {
    const NurbsCurve c = wavy_curve(count, 3, 7);
    const int reps = std::max(1, 3000 / count);
    const auto t0 = Clock::now();
    std::size_t blocks = 0;
    for (int r = 0; r < reps; ++r) blocks = plan_nurbs_blocks(c, limits(feed)).blocks.size();
    const auto t1 = Clock::now();
    const double us = std::chrono::duration<double, std::micro>(t1 - t0).count() / reps;
    std::printf("host plan_nurbs_blocks, degree 3, %4d points: %8.0f us per curve, %6.1f us per control point (%zu blocks)\n",
                count, us, us / count, blocks);
  }
  std::printf("(checksum %.3f)\n", sink);
  return 0;
}
