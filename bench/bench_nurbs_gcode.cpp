// bench_nurbs_gcode.cpp — host preprocessing time of NURBS programs through the real G-code
// front end (never pass/fail): a G5.2 program of N control points (cubic, L4, a wavy curve
// inside the desktop mill's travel) is checked (pass 1: lexer, parser, interpreter, curve
// validation, extreme points for the soft limits) and streamed (pass 2: the same plus the
// feed schedule, knot insertion into ring-sized pieces, block schedules) by check_program_text
// and BlockStream, as `pcnc check` / `pcnc run` do. Prints the fastest of several runs, per
// program and per control point. Then the rt side: the blocks of the 1000-point cubic run
// through Machine::cycle (executor with the exact curve evaluation and parameter step, three
// PIDs, plant, safety), every cycle timed: p50/p99/max compute time per cycle on NURBS blocks.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "bench_cli.hpp"
#include "config/config.hpp"
#include "loop/machine.hpp"
#include "gcode/program.hpp"

using namespace pcnc;
using Clock = std::chrono::steady_clock;

namespace {

// N control points: x from -10 to 10, y a few sines, within the 25 mm travel (G54 at its centre).
std::string wavy_program(int n, int order) {
  std::string p = "G21 G90 G17\nG0 X-10 Y0 Z-5\nG1 F1200\n";
  p += "G5.2 P1 L" + std::to_string(order) + "\n";
  char buf[96];
  for (int i = 1; i < n; ++i) {
    const double x = -10.0 + 20.0 * i / (n - 1);
    const double y = 4.0 * std::sin(0.7 * i) * std::cos(0.13 * i);
    std::snprintf(buf, sizeof buf, "X%.4f Y%.4f P%.3f\n", x, y, 1.0 + 0.3 * std::sin(1.3 * i));
    p += buf;
  }
  return p + "G5.3\nG0 Z0\nM2\n";
}

template <class F>
double best_of(int reps, F&& f) {
  double best = 1e300;
  for (int r = 0; r < reps; ++r) {
    const auto t0 = Clock::now();
    f();
    best = std::min(best, std::chrono::duration<double>(Clock::now() - t0).count());
  }
  return best;
}

}  // namespace

int main(int argc, char** argv) {
  pcnc::BenchCli app{"NURBS programs through the G-code front end: host time per control point"};
  std::string config_path = default_config_path();
  int reps = 5;
  app.add_option("--config", config_path, "machine config");
  app.add_option("--reps", reps, "runs per figure (the fastest is shown)");
  if (const int rc = app.parse(argc, argv); rc >= 0) return rc;
  const MachineConfig cfg = load_config(config_path);
  JobOptions o;
  o.start_position = cfg.gcode.work_offsets[0];

  std::printf("host preprocessing of one G5.2 curve through check_program + BlockStream (fastest of %d)\n", reps);
  std::printf("%8s %6s %8s %12s %12s %14s %14s\n", "points", "order", "blocks", "check ms", "stream ms",
              "check us/pt", "stream us/pt");
  for (const int order : {3, 4}) {
    for (const int n : {32, 100, 1000, 10000}) {
      const std::string text = wavy_program(n, order);
      CheckResult chk;
      const double t_check = best_of(reps, [&] { chk = check_program_text(text, "bench.ngc", cfg, o); });
      if (!chk.ok) {
        std::fprintf(stderr, "program of %d points rejected: %s\n", n,
                     chk.diagnostics.empty() ? "?" : chk.diagnostics.front().message.c_str());
        return 1;
      }
      std::size_t blocks = 0;
      const double t_stream = best_of(reps, [&] {
        BlockStream s(BlockStream::FromText{}, text, "bench.ngc", cfg, o, chk.transform);
        Block b;
        blocks = 0;
        while (s.next(b)) blocks += b.kind == BlockKind::kNurbs;
      });
      std::printf("%8d %6d %8zu %12.3f %12.3f %14.2f %14.2f\n", n, order, blocks, 1e3 * t_check, 1e3 * t_stream,
                  1e6 * t_check / n, 1e6 * t_stream / n);
    }
  }

  // rt: Machine::cycle on the NURBS blocks of the 1000-point cubic (feed 20 mm/s).
  {
    JobOptions ro;
    Vec3 home{};
    for (int i = 0; i < kAxes; ++i) home[static_cast<std::size_t>(i)] = cfg.axes[static_cast<std::size_t>(i)].home_mm;
    ro.start_position = home;
    const std::string text = wavy_program(1000, 4);
    const CheckResult chk = check_program_text(text, "bench.ngc", cfg, ro);
    BlockStream s(BlockStream::FromText{}, text, "bench.ngc", cfg, ro, chk.transform);
    std::vector<Block> blocks;
    Block b;
    while (s.next(b)) {
      b.seq = blocks.size() + 1;
      blocks.push_back(b);
    }
    std::vector<double> nurbs_ns, other_ns;
    for (int rep = 0; rep < reps; ++rep) {
      Machine m(cfg);
      MotionRing ring;
      Command c;
      c.id = 1;
      c.kind = CommandKind::kProgramStart;
      m.command(c);
      std::size_t next = 0;
      for (long k = 0; k < 10'000'000 && !m.status().program_done; ++k) {
        while (next < blocks.size() && ring.try_push(blocks[next])) ++next;
        const bool on_curve = !ring.empty() && ring.peek(0).kind == BlockKind::kNurbs;
        const auto t0 = Clock::now();
        m.cycle(ring);
        const double ns = std::chrono::duration<double, std::nano>(Clock::now() - t0).count();
        (on_curve ? nurbs_ns : other_ns).push_back(ns);
      }
      if (!m.status().program_done) {
        std::fprintf(stderr, "the rt run did not finish: %s\n", m.fault_reason());
        return 1;
      }
    }
    auto q = [](std::vector<double> v, double f) {
      std::sort(v.begin(), v.end());
      return v.empty() ? 0.0 : v[std::min(v.size() - 1, static_cast<std::size_t>(f * static_cast<double>(v.size())))];
    };
    std::printf("\nrt Machine::cycle (executor + 3 PID + plant + safety), 1000-point cubic from the front end, "
                "%zu NURBS blocks:\n", static_cast<std::size_t>(std::count_if(blocks.begin(), blocks.end(),
                [](const Block& x) { return x.kind == BlockKind::kNurbs; })));
    std::printf("  on NURBS blocks  n=%zu  p50 %.0f ns  p99 %.0f ns  max %.0f ns\n", nurbs_ns.size(), q(nurbs_ns, 0.5),
                q(nurbs_ns, 0.99), q(nurbs_ns, 1.0));
    std::printf("  other cycles     n=%zu  p50 %.0f ns  p99 %.0f ns  max %.0f ns\n", other_ns.size(), q(other_ns, 0.5),
                q(other_ns, 0.99), q(other_ns, 1.0));
  }
  return 0;
}
