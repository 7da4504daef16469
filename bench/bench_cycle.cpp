// bench_cycle.cpp — cost of one rt cycle (Machine::cycle: executor + 3 PID + plant + safety)
// and how fast --clock virtual can replay a long program.
//
// Builds a long program in memory (M21 polygon circles, full arcs, helices, a zig-zag pocket
// of lines, rapids; blocks projected on the axis limits like the host does), feeds it through
// the 4-slot ring the way the virtual-clock loop does (refill before each cycle), and times
// every cycle. Prints p50/p99/max compute time per cycle and simulated seconds per wall second.
// Then the same per-cycle timing for 5 axes: a tilted helix under tool-centre-point control
// (M428), made by the real front end on configs/desktop-5axis.toml (the rt runs the inverse
// kinematics every cycle and steps the A and C drives too).
//   bench_cycle [--config F] [--repeats N] [--five-config F]
// With --program FILE instead: that program's blocks, made by the real front end as `pcnc run FILE
// --contouring on [--fit] [--tolerance MM]` makes them, run through Machine::cycle alone (no trace,
// no second process), RUNS times: the fastest run's thread CPU time, per cycle and per program (the
// rt's own share of a virtual-clock replay, docs/replay.md).
//   bench_cycle --program FILE [--fit] [--tolerance MM] [--runs N] [--config F]
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <vector>

#include <sstream>
#include <string>

#include "bench_cli.hpp"
#include "config/config.hpp"
#include "gcode/program.hpp"
#include "loop/machine.hpp"
#include "run_job_options.hpp"

using namespace pcnc;

namespace {

// Minimal block builder with the host's projection rule (speed/accel so no axis exceeds its limits).
struct Builder {
  const MachineConfig& c;
  Vec3 pos;
  std::vector<Block> out;
  std::uint64_t seq = 0;

  Block base(BlockKind k) {
    Block b{};
    b.seq = ++seq;
    b.line = static_cast<std::uint32_t>(seq);
    b.kind = k;
    b.contouring = 1;
    b.start = pos;
    b.end = pos;
    return b;
  }
  void line(const Vec3& e, double feed, BlockKind k = BlockKind::kLine) {
    Block b = base(k);
    b.end = e;
    b.length = norm(e - pos);
    if (b.length <= 0.0) return;
    const Vec3 u = normalized(e - pos);
    double v = feed, a = std::numeric_limits<double>::infinity();
    for (int i = 0; i < kAxes; ++i) {
      if (std::abs(u[i]) < 1e-12) continue;
      v = std::min(v, c.axes[i].max_velocity_mm_s / std::abs(u[i]));
      a = std::min(a, c.axes[i].max_accel_mm_s2 / std::abs(u[i]));
    }
    b.speed = v;
    b.accel = a;
    b.dir_start = b.dir_end = u;
    // The seed's driving-axis plan, which the rt's block check cross-checks (block.hpp).
    const Vec3 d = e - pos;
    int w = 0, moving = 0;
    for (int i = 0; i < kAxes; ++i) {
      moving += std::abs(d[i]) > 1e-9;
      if (std::abs(d[i]) > std::abs(d[w])) w = i;
    }
    b.motion_class = static_cast<MotionClass>(moving);
    b.driving_axis = static_cast<std::uint8_t>(w);
    b.driving_dir = d[w] < 0.0 ? -1 : 1;
    b.driving_speed = v * std::abs(u[w]);
    b.driving_accel = a * std::abs(u[w]);
    const double brake = v * v / (2.0 * a);
    b.decel_start = pos[w] + u[w] * (2.0 * brake >= b.length ? 0.5 * b.length : b.length - brake);
    out.push_back(b);
    pos = e;
  }
  // Full XY circle (G03) about `center` from the current point, with helix dz.
  void circle(const Vec3& center, double feed, double dz) {
    Block b = base(BlockKind::kArc);
    const double r = std::hypot(pos[0] - center[0], pos[1] - center[1]);
    const double th = std::atan2(pos[1] - center[1], pos[0] - center[0]);
    const double sweep = 2.0 * std::numbers::pi;
    b.end = {pos[0], pos[1], pos[2] + dz};
    b.length = std::hypot(r * sweep, dz);
    const double q = r * sweep / b.length, h = std::abs(dz) / b.length;
    const double ap = std::min(c.axes[0].max_accel_mm_s2, c.axes[1].max_accel_mm_s2);
    const double vp = std::min(c.axes[0].max_velocity_mm_s, c.axes[1].max_velocity_mm_s);
    double v = std::min({feed, vp / q, std::sqrt(0.5 * ap * r) / q}), a = 0.5 * ap / q;
    if (h > 1e-12) {
      v = std::min(v, c.axes[2].max_velocity_mm_s / h);
      a = std::min(a, c.axes[2].max_accel_mm_s2 / h);
    }
    b.speed = v;
    b.accel = a;
    b.arc.center = {center[0], center[1], pos[2]};
    b.arc.radius = r;
    b.arc.start_angle = th;
    b.arc.sweep = sweep;
    b.arc.helix = dz;
    b.arc.normal_axis = 2;
    const Vec3 t = normalized(Vec3{-std::sin(th) * r * sweep, std::cos(th) * r * sweep, dz});
    b.dir_start = b.dir_end = t;
    // The angular and driving-axis plans, which the rt's block check cross-checks (block.hpp).
    const double rho = b.length / sweep;
    b.arc.angular_speed = v / rho;
    b.arc.angular_accel = a / rho;
    const double brake = b.arc.angular_speed * b.arc.angular_speed / (2.0 * b.arc.angular_accel);
    b.arc.decel_start_angle = 2.0 * brake >= sweep ? 0.5 * sweep : sweep - brake;
    b.motion_class = std::abs(dz) > 1e-9 ? MotionClass::kSpace : MotionClass::kPlane;
    b.driving_axis = 2;
    b.driving_dir = dz < 0.0 ? -1 : 1;
    b.driving_speed = v * h;
    b.driving_accel = a * h;
    b.decel_start = pos[2] + dz * b.arc.decel_start_angle / sweep;
    out.push_back(b);
    pos = b.end;
  }
  void end() { out.push_back(base(BlockKind::kEnd)); }
};

std::vector<Block> long_program(const MachineConfig& c, int repeats) {
  Builder b{c, {c.axes[0].home_mm, c.axes[1].home_mm, c.axes[2].home_mm}, {}};
  for (int r = 0; r < repeats; ++r) {
    // polygon circle, 180 segments, r 5 mm, F1500
    b.line({17.5, 12.5, 20.0}, 1e9, BlockKind::kRapid);
    for (int k = 1; k <= 180; ++k) {
      const double th = 2.0 * std::numbers::pi * k / 180.0;
      b.line({12.5 + 5.0 * std::cos(th), 12.5 + 5.0 * std::sin(th), 20.0}, 25.0);
    }
    // a true circle and a helix down 2 mm
    b.circle({12.5, 12.5, 20.0}, 500.0 / 60.0, 0.0);
    b.circle({12.5, 12.5, 20.0}, 20.0, -2.0);
    // zig-zag pocket
    b.line({3.0, 3.0, 18.0}, 1e9, BlockKind::kRapid);
    for (int k = 0; k < 20; ++k) {
      b.line({22.0, 3.0 + k, 18.0}, 40.0);
      b.line({22.0, 3.5 + k, 18.0}, 40.0);
      b.line({3.0, 3.5 + k, 18.0}, 40.0);
      b.line({3.0, 4.0 + k, 18.0}, 40.0);
    }
  }
  b.line({12.5, 12.5, 25.0}, 1e9, BlockKind::kRapid);
  b.end();
  return b.out;
}

// A tilted helix under TCP, `turns` times round: the tip on a helix of radius 3 mm, the tool
// leaning 15 degrees, C following the angle (12 moves per turn).
std::string five_axis_program(int turns) {
  std::ostringstream p;
  p << "G21 G90 G94\nG0 X0 Y0 Z-8\nG1 A-15 C120 F3600\nM428\n";
  char buf[160];
  const double pi = std::numbers::pi;
  std::snprintf(buf, sizeof buf, "G1 X%.4f Y%.4f Z-8 F400\n", 3.0 * std::cos(120.0 * pi / 180.0), 3.0 * std::sin(120.0 * pi / 180.0));
  p << buf;
  for (int k = 1; k <= 12 * turns; ++k) {
    const double deg = 120.0 + 30.0 * k;
    std::snprintf(buf, sizeof buf, "G1 X%.4f Y%.4f Z%.4f A-15 C%.1f\n", 3.0 * std::cos(deg * pi / 180.0),
                  3.0 * std::sin(deg * pi / 180.0), -8.0 + 0.5 * std::sin(k * 0.2), deg);
    p << buf;
  }
  p << "M429\nM2\n";
  return p.str();
}

struct CycleTimes {
  std::size_t cycles = 0;
  double mean = 0.0, p50 = 0.0, p99 = 0.0, p999 = 0.0, max = 0.0;
  bool done = false;
};

// A fresh machine's program start, as the host's run command gives it.
void start_program(Machine& m) {
  Command start;
  start.id = 1;
  start.kind = CommandKind::kProgramStart;
  m.command(start);
}

// Runs `program` on `m` to its end (or a fault, or max_cycles), the ring refilled before each
// cycle as the virtual-clock loop does; returns the cycles run.
std::uint64_t run_to_end(Machine& m, const std::vector<Block>& program, std::uint64_t max_cycles) {
  MotionRing ring;
  std::size_t next = 0;
  std::uint64_t cycles = 0;
  while (!m.status().program_done && cycles < max_cycles && m.status().state != MachineState::kFault) {
    while (next < program.size() && ring.try_push(program[next])) ++next;
    m.set_host_alive(true);
    m.cycle(ring);
    ++cycles;
  }
  return cycles;
}

// Compute time of each cycle of `program` on a fresh machine.
CycleTimes time_cycles(const MachineConfig& cfg, const std::vector<Block>& program, std::size_t max_cycles) {
  Machine m(cfg);
  MotionRing ring;
  start_program(m);
  std::vector<double> us;
  us.reserve(1 << 20);
  std::size_t next = 0;
  while (!m.status().program_done && us.size() < max_cycles && m.status().state != MachineState::kFault) {
    while (next < program.size() && ring.try_push(program[next])) ++next;
    m.set_host_alive(true);
    const auto t0 = std::chrono::steady_clock::now();
    m.cycle(ring);
    us.push_back(std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count());
  }
  CycleTimes t;
  t.done = m.status().program_done != 0;
  if (!t.done) std::fprintf(stderr, "program did not finish: state %s, %s\n", to_string(m.status().state), m.fault_reason());
  std::sort(us.begin(), us.end());
  auto pct = [&](double p) { return us[std::min(us.size() - 1, static_cast<std::size_t>(p * static_cast<double>(us.size())))]; };
  double sum = 0.0;
  for (double x : us) sum += x;
  t.cycles = us.size();
  t.mean = sum / static_cast<double>(us.size());
  t.p50 = pct(0.5);
  t.p99 = pct(0.99);
  t.p999 = pct(0.999);
  t.max = us.back();
  return t;
}

double clock_s(clockid_t id) {
  timespec t{};
  clock_gettime(id, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}
double now_s() { return clock_s(CLOCK_MONOTONIC); }
double cpu_s() { return clock_s(CLOCK_THREAD_CPUTIME_ID); }

// `pcnc run FILE --clock virtual` without its processes: the blocks of FILE, then the cycles
// until the program is done, fastest of `runs` by thread CPU time.
int time_program(MachineConfig cfg, const std::string& file, bool fit, double tolerance, int runs) {
  if (tolerance >= 0.0) set_operator_tolerance(cfg.motion, tolerance);
  const JobOptions opts = run_job_options(cfg, fit, true);
  const CheckResult check = check_program(file, cfg, opts);
  if (!check.ok) {
    for (const Diagnostic& d : check.diagnostics) std::fprintf(stderr, "%s\n", format_diagnostic(d).c_str());
    return 1;
  }
  std::vector<Block> blocks;
  BlockStream s(file, cfg, opts, check.transform);
  for (Block b; s.next(b);) blocks.push_back(b);
  double best = std::numeric_limits<double>::infinity();
  std::uint64_t cycles = 0;
  for (int r = 0; r < runs; ++r) {
    Machine m(cfg);
    start_program(m);
    const double c0 = cpu_s();
    cycles = run_to_end(m, blocks, std::numeric_limits<std::uint64_t>::max());
    best = std::min(best, cpu_s() - c0);
    if (!m.status().program_done) {
      std::fprintf(stderr, "program did not finish: state %s, %s\n", to_string(m.status().state), m.fault_reason());
      return 1;
    }
  }
  const double sim = static_cast<double>(cycles) * cfg.cycle_period_s();
  std::printf("%s: %zu blocks, %llu cycles (%.3f s machine time); Machine::cycle thread CPU %.1f ms (fastest of %d) = "
              "%.3f us/cycle, %.0fx real time\n",
              file.c_str(), blocks.size(), static_cast<unsigned long long>(cycles), sim, best * 1e3, runs,
              best * 1e6 / static_cast<double>(cycles), sim / best);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  pcnc::BenchCli app{"rt cycle compute time and virtual-clock speed"};
  std::string config_path = default_config_path();
  int repeats = 20;
  app.add_option("--config", config_path, "machine config");
  app.add_option("--repeats", repeats, "how many times the test pattern repeats")->show_default();
  std::string five_path = std::string(PCNC_BENCH_SOURCE_DIR) + "/configs/desktop-5axis.toml";
  int turns = 40;
  app.add_option("--five-config", five_path, "the 5-axis machine config for the TCP pass")->show_default();
  app.add_option("--turns", turns, "turns of the TCP helix")->show_default();
  std::string program_path;
  bool fit = false;
  double tolerance = -1.0;
  int runs = 5;
  app.add_option("--program", program_path, "time this G-code program's cycles instead (as pcnc run --contouring on)");
  app.add_flag("--fit", fit, "with --program: as pcnc run --fit");
  app.add_option("--tolerance", tolerance, "with --program: as pcnc run --tolerance MM (default: the config's)");
  app.add_option("--runs", runs, "with --program: runs, the fastest counts")->show_default();
  if (const int rc = app.parse(argc, argv); rc >= 0) return rc;

  if (!program_path.empty()) return time_program(load_config(config_path), program_path, fit, tolerance, std::max(1, runs));
  const MachineConfig cfg = load_config(config_path);
  const std::vector<Block> program = long_program(cfg, repeats);
  const std::size_t max_cycles = 50'000'000;

  // Pass 1: virtual-clock replay speed (no per-cycle timing overhead).
  double sim_s = 0.0, wall_s = 0.0;
  std::uint64_t cycles = 0;
  {
    Machine m(cfg);
    start_program(m);
    const double t0 = now_s(), c0 = cpu_s();
    cycles = run_to_end(m, program, max_cycles);
    wall_s = now_s() - t0;
    const double cpu = cpu_s() - c0;
    sim_s = static_cast<double>(cycles) * cfg.cycle_period_s();
    if (!m.status().program_done) {
      std::fprintf(stderr, "program did not finish: state %s, %s\n", to_string(m.status().state), m.fault_reason());
      return 1;
    }
    std::printf("program: %zu blocks, %.1f s of machine time (%llu cycles), max ferr X %.2f Y %.2f Z %.2f um\n",
                program.size(), sim_s, static_cast<unsigned long long>(cycles), m.status().max_following_error[0] * 1e3,
                m.status().max_following_error[1] * 1e3, m.status().max_following_error[2] * 1e3);
    std::printf("virtual clock: %.1f simulated s in %.3f wall s = %.0fx real time (thread CPU %.3f s = %.0fx; the\n"
                "               difference is time this thread was not scheduled on the shared cores)\n",
                sim_s, wall_s, sim_s / wall_s, cpu, sim_s / cpu);
  }

  // Pass 2: compute time of each cycle, 3 axes.
  const CycleTimes t3 = time_cycles(cfg, program, max_cycles);
  std::printf("cycle compute time over %zu cycles: mean %.3f us, p50 %.3f us, p99 %.3f us, p99.9 %.3f us, max %.3f us\n",
              t3.cycles, t3.mean, t3.p50, t3.p99, t3.p999, t3.max);

  // Pass 3: 5 axes under TCP, blocks from the real front end.
  const MachineConfig five = load_config(five_path);
  JobOptions opts;
  opts.start_position = Vec3{five.axes[0].home_mm, five.axes[1].home_mm, five.axes[2].home_mm};
  const std::string text = five_axis_program(turns);
  const CheckResult check = check_program_text(text, "tcp-helix.ngc", five, opts);
  if (!check.ok) {
    for (const Diagnostic& d : check.diagnostics) std::fprintf(stderr, "%s\n", format_diagnostic(d).c_str());
    return 1;
  }
  std::vector<Block> blocks;
  BlockStream s(BlockStream::FromText{}, text, "tcp-helix.ngc", five, opts, check.transform);
  for (Block b; s.next(b);) blocks.push_back(b);
  const CycleTimes t5 = time_cycles(five, blocks, max_cycles);
  if (!t5.done) return 1;
  std::printf("5 axes, TCP (%s, %zu blocks): cycle compute time over %zu cycles: mean %.3f us, p50 %.3f us, p99 %.3f us, "
              "p99.9 %.3f us, max %.3f us\n",
              five.name.c_str(), blocks.size(), t5.cycles, t5.mean, t5.p50, t5.p99, t5.p999, t5.max);
  std::printf("rt compute p99 per cycle: 3 axes %.3f us, 5 axes (TCP) %.3f us\n", t3.p99, t5.p99);
  return 0;
}
