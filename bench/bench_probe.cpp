// bench_probe.cpp — figures for the touch probe (issue 15 items 1-2, docs/probe.md; never
// pass/fail):
//  1. the rt's probing on a 7 x 7 grid over a Gaussian bump (the desktop mill's probe, the
//     workpiece top at machine Z 15 with a 0.5 mm bump of sigma 4 mm at the table's centre),
//     G38.2 straight down at --feed mm/min, in-process (the real Machine cycle): the latched
//     ball centre against the trigger height computed here by bisection on the contact rule
//     (noise-free: what remains is the cycle quantisation and the repeatability noise), the
//     distance travelled past the latch against the overtravel, and the error of reading the
//     surface as "latched Z - R" (no ball-radius correction along the normal) and as
//     "latched Z - (R - pre-travel)";
//  2. the host's cost of the sync points: the 7 x 7 probing program checked and streamed again
//     after each of its 49 results, as ProbeSync does (host/service/probe_sync.hpp);
//  3. the cost of one contact test (scene_gap on the bump), what the rt adds per cycle.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "bench_cli.hpp"
#include "gcode/program.hpp"
#include "geometry/probe_contact.hpp"
#include "machine_runner.hpp"
#include "make_blocks.hpp"

using namespace pcnc;
using Clock = std::chrono::steady_clock;

namespace {

struct Stats {
  double sum = 0.0, sq = 0.0, max_abs = 0.0;
  int n = 0;
  void add(double v) {
    sum += v;
    sq += v * v;
    max_abs = std::max(max_abs, std::abs(v));
    ++n;
  }
  double mean() const { return n ? sum / n : 0.0; }
  double std() const { return n > 1 ? std::sqrt(std::max(0.0, (sq - sum * sum / n) / (n - 1))) : 0.0; }
};

// The ball-centre height at (x, y) where the probe triggers straight down without noise.
double trigger_z(const TableScene& s, const ProbeModel& p, double x, double y) {
  const double r = p.ball_radius_mm - pretravel_mm(p, {0.0, 0.0, -1.0});
  double lo = surface_height(s, x, y) - 1.0, hi = lo + 5.0;  // gap(lo) < r < gap(hi)
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (scene_gap(s, {x, y, mid}) <= r ? lo : hi) = mid;
  }
  return hi;
}

}  // namespace

int main(int argc, char** argv) {
  pcnc::BenchCli app{"bench_probe: figures for the touch probe (docs/probe.md)"};
  double feed = 50.0;
  app.add_option("--feed", feed, "probing feed, mm/min");
  if (const int rc = app.parse(argc, argv); rc >= 0) return rc;

  MachineConfig c = test::default_machine_config();
  c.table.bump_x_mm = 12.5;
  c.table.bump_y_mm = 12.5;
  c.table.bump_height_mm = 0.5;
  c.table.bump_sigma_mm = 4.0;
  const ProbeModel& pm = c.probe.model;
  const double v = feed / 60.0;

  // 1. the grid, probed by the rt
  test::MachineRunner run(c);
  Vec3 at = test::home(c);
  std::uint64_t seq = 0;
  Stats latch, past, raw, pre;
  bool started = false;
  for (int j = 0; j < 7; ++j) {
    for (int i = 0; i < 7; ++i) {
      const double x = 2.5 + i * 20.0 / 6.0, y = 2.5 + j * 20.0 / 6.0;
      test::ProgramBuilder p(c, at);
      p.rapid({x, y, 17.5}).line({x, y, 14.0}, v);
      std::vector<Block> blocks = p.blocks();
      blocks[1].probe_rule = kProbeTowardError;
      for (Block& b : blocks) b.seq += seq;
      seq += blocks.size();
      const std::uint64_t before = run.status().probe_count;
      if (!started) {
        run.start(blocks);
        started = true;
      } else {
        for (const Block& b : blocks) run.ring().try_push(b);
      }
      run.run_while([&](const Status& s) { return s.probe_count == before && s.state != MachineState::kFault; }, 2000000);
      const Status& s = run.status();
      if (s.probe_outcome != ProbeOutcome::kContact) {
        std::fprintf(stderr, "bench_probe: no contact at %.3f %.3f (%s)\n", x, y, to_string(s.state));
        return 1;
      }
      const double z = s.probe_latched[2];
      latch.add(z - trigger_z(c.table, pm, x, y));
      past.add(z - s.probe_stop[2]);
      const double f = surface_height(c.table, x, y);
      raw.add(z - pm.ball_radius_mm - f);
      pre.add(z - (pm.ball_radius_mm - pretravel_mm(pm, {0.0, 0.0, -1.0})) - f);
      at = s.probe_stop;
    }
  }
  std::printf("probing a 7 x 7 grid over a 0.5 mm Gaussian bump (sigma 4 mm), G38.2 down at F%.0f (%.3f mm/s), "
              "R %.3f mm, axial pre-travel %.4f mm, repeatability %.4f mm:\n",
              feed, v, pm.ball_radius_mm, pm.pretravel_axial_mm, pm.repeatability_mm);
  std::printf("  latched - computed trigger height: mean %+.3f um, std %.3f um, max |.| %.3f um "
              "(one cycle at this feed: %.3f um)\n",
              latch.mean() * 1e3, latch.std() * 1e3, latch.max_abs * 1e3, v * c.cycle_period_s() * 1e3);
  std::printf("  travel past the latch: mean %.3f um, max %.3f um (overtravel %.3f mm)\n", past.mean() * 1e3,
              past.max_abs * 1e3, pm.overtravel_mm);
  std::printf("  surface read as latched Z - R: mean %+.2f um, max |.| %.2f um; as latched Z - (R - pre-travel): "
              "mean %+.2f um, max |.| %.2f um (the rest: the ball touches the slope off its axis)\n",
              raw.mean() * 1e3, raw.max_abs * 1e3, pre.mean() * 1e3, pre.max_abs * 1e3);

  // 2. the sync points' cost on the host
  std::string text = "G21 G90 G54 F50\n";
  for (int j = 0; j < 7; ++j)
    for (int i = 0; i < 7; ++i) {
      char line[160];
      std::snprintf(line, sizeof line, "G0 Z-7.5\nG0 X%.4f Y%.4f\nG38.2 Z-11\n(PRINT,#5063)\n", -10.0 + i * 20.0 / 6.0,
                    -10.0 + j * 20.0 / 6.0);
      text += line;
    }
  text += "G0 Z-5\nM2\n";
  JobOptions base;
  base.start_position = test::home(c);
  const CheckResult first = check_program_text(text, "grid.ngc", c, base);
  if (!first.ok) {
    std::fprintf(stderr, "bench_probe: the grid program has errors\n");
    return 1;
  }
  auto results = std::make_shared<ProbeResults>();
  const auto t0 = Clock::now();
  std::uint64_t blocks = 0;
  for (int k = 0; k <= 49; ++k) {
    JobOptions check_options = base;
    auto known = std::make_shared<ProbeResults>(*results);
    check_options.probe = known;
    const CheckResult r = check_program_text(text, "grid.ngc", c, check_options);
    JobOptions stream_options = base;
    auto stop = std::make_shared<ProbeResults>(*results);
    stop->stop_at_unknown = true;
    stream_options.probe = stop;
    BlockStream s(BlockStream::FromText{}, text, "grid.ngc", c, stream_options, r.transform);
    Block b;
    while (s.next(b)) ++blocks;
    if (k < 49) {  // the probe's result: contact 1 mm above its commanded end
      const int i = k % 7, j = k / 7;
      ProbeResult hit;
      hit.latched = hit.stop = {2.5 + i * 20.0 / 6.0, 2.5 + j * 20.0 / 6.0, 15.0};
      results->known.push_back(hit);
    }
  }
  const double sync_s = std::chrono::duration<double>(Clock::now() - t0).count();
  std::printf("host sync points: the %d-line grid program checked and streamed again after each of its 49 probes: "
              "%.1f ms in all, %.2f ms per sync point (%llu blocks made)\n",
              static_cast<int>(std::count(text.begin(), text.end(), '\n')), sync_s * 1e3, sync_s * 1e3 / 50.0,
              static_cast<unsigned long long>(blocks));

  // 3. one contact test
  const int n = 2000000;
  double acc = 0.0;
  const auto t1 = Clock::now();
  for (int k = 0; k < n; ++k) acc += scene_gap(c.table, {12.5 + 1e-6 * k, 12.5, 16.0});
  const double per = std::chrono::duration<double>(Clock::now() - t1).count() / n;
  std::printf("contact test (scene_gap on the bump): %.1f ns per call (checksum %.3f)\n", per * 1e9, acc / n);
  return 0;
}
