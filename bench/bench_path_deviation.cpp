// bench_path_deviation.cpp — a figure for tools/bench_surfacing.sh (never pass/fail): how far
// a run's traced path (commanded and measured) stays from the programmed path. The programmed
// path is the program's own moves (checked with path tolerance 0: no smoothing, no merging),
// lines as they are, arcs and NURBS curves densely sampled, in machine coordinates with the
// same --fit transform the run used (the --fit measuring pass ignores the tolerance).
//
// Usage: bench_path_deviation PROGRAM TRACE.csv [--config F] [--fit] [--contouring on|off]
// Prints: "cmd_max_um act_max_um rows" (rows of the trace while a feed move ran); with
// --worst N, also (to stderr) the N trace rows farthest from the path, measured, with their time,
// line, speed and the commanded row's distance (where the servo lags: a diagnostic); with
// --worst-cmd as well, the N rows farthest by their commanded position.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "bench_cli.hpp"
#include "config/config.hpp"
#include "gcode/program.hpp"
#include "run_job_options.hpp"
#include "geometry/nurbs.hpp"
#include "geometry/plane.hpp"
#include "geometry/spline_fit.hpp"
#include "ipc/block_nurbs.hpp"

using namespace pcnc;

namespace {

// Appends the block's path (after its start point) to `pts`, `lines` the source line per point.
void append_path(const Block& b, std::vector<Vec3>& pts) {
  if (b.kind == BlockKind::kLine || b.kind == BlockKind::kRapid) {
    pts.push_back(b.end);
  } else if (b.kind == BlockKind::kArc) {
    const auto pa = plane_axes(b.arc.normal_axis);
    const int n = std::max(8, static_cast<int>(std::ceil(std::abs(b.arc.sweep) * b.arc.radius / 0.002)));
    for (int k = 1; k <= n; ++k) {
      const double f = static_cast<double>(k) / n;
      const double a = b.arc.start_angle + f * b.arc.sweep;
      Vec3 p = b.arc.center;
      p[static_cast<std::size_t>(pa[0])] += b.arc.radius * std::cos(a);
      p[static_cast<std::size_t>(pa[1])] += b.arc.radius * std::sin(a);
      p[static_cast<std::size_t>(b.arc.normal_axis)] = b.start[static_cast<std::size_t>(b.arc.normal_axis)] + f * b.arc.helix;
      pts.push_back(k == n ? b.end : p);
    }
  } else if (b.kind == BlockKind::kNurbs) {
    const NurbsCurve c = from_geometry(b.nurbs);
    const int n = std::max(16, static_cast<int>(std::ceil(b.length / 0.002)));
    for (int k = 1; k <= n; ++k) pts.push_back(nurbs_point(c.view(), c.u_min() + (c.u_max() - c.u_min()) * k / n));
  }
}

}  // namespace

int main(int argc, char** argv) {
  pcnc::BenchCli app{"distance of a traced path from the programmed path"};
  std::string program, trace, config_path = default_config_path(), contouring = "on";
  bool fit = false;
  app.add_option("PROGRAM", program)->required();
  app.add_option("TRACE", trace)->required();
  app.add_option("--config", config_path);
  app.add_option("--contouring", contouring);
  app.add_flag("--fit", fit);
  std::size_t worst_n = 0;
  app.add_option("--worst", worst_n);
  bool by_cmd = false;  // --worst lists the rows farthest by their commanded position instead
  app.add_flag("--worst-cmd", by_cmd);
  if (const int rc = app.parse(argc, argv); rc >= 0) return rc;
  MachineConfig c = load_config(config_path);
  set_operator_tolerance(c.motion, 0.0);
  const JobOptions o = run_job_options(c, fit, contouring == "on");
  std::vector<Vec3> pts;
  bool first = true;
  const CheckResult r = check_program(program, c, o, [&](const Block& b) {
    const bool motion = b.kind == BlockKind::kLine || b.kind == BlockKind::kRapid || b.kind == BlockKind::kArc ||
                        b.kind == BlockKind::kNurbs;
    if (!motion) return;
    if (first) pts.push_back(b.start), first = false;
    append_path(b, pts);
  });
  if (!r.ok || pts.size() < 2) {
    std::fprintf(stderr, "bench_path_deviation: %s does not check\n", program.c_str());
    return 2;
  }
  std::ifstream in(trace);
  std::string line;
  std::getline(in, line);
  double cmd_max = 0.0, act_max = 0.0;
  std::size_t j = 0, rows = 0;
  struct Row {
    double act_um, cmd_um;
    std::string t, line, speed;
  };
  std::vector<Row> worst;
  while (std::getline(in, line)) {
    std::stringstream ss(line);
    std::string f[13];
    for (auto& x : f) std::getline(ss, x, ',');
    if (f[2] != "RUNNING") continue;
    const Vec3 cmd{std::stod(f[3]), std::stod(f[4]), std::stod(f[5])};
    const Vec3 act{std::stod(f[6]), std::stod(f[7]), std::stod(f[8])};
    // the nearest segment, searched in a window that moves with the trace
    double best = 1e300;
    std::size_t best_i = j;
    const std::size_t lo = j > 100 ? j - 100 : 0, hi = std::min(pts.size() - 1, j + 400);
    for (std::size_t i = lo; i < hi; ++i) {
      const double d = point_segment_distance(cmd, pts[i], pts[i + 1]);
      if (d < best) best = d, best_i = i;
    }
    double best_act = 1e300;
    for (std::size_t i = lo; i < hi; ++i) best_act = std::min(best_act, point_segment_distance(act, pts[i], pts[i + 1]));
    // Lost track (the window fell behind on a long run of short segments or arc samples, or
    // farther than 4 um: every larger distance is checked against the whole path):
    // search the whole path once.
    if (best > 0.004 || best_act > 0.004) {
      for (std::size_t i = 0; i + 1 < pts.size(); ++i) {
        const double d = point_segment_distance(cmd, pts[i], pts[i + 1]);
        if (d < best) best = d, best_i = i;
        best_act = std::min(best_act, point_segment_distance(act, pts[i], pts[i + 1]));
      }
    }
    j = best_i;
    cmd_max = std::max(cmd_max, best);
    act_max = std::max(act_max, best_act);
    ++rows;
    if (worst_n > 0) {
      worst.push_back({best_act * 1000.0, best * 1000.0, f[0], f[1], f[12]});
      if (worst.size() > 4 * worst_n) {
        std::partial_sort(worst.begin(), worst.begin() + static_cast<std::ptrdiff_t>(worst_n), worst.end(),
                          [by_cmd](const Row& a, const Row& b) { return by_cmd ? a.cmd_um > b.cmd_um : a.act_um > b.act_um; });
        worst.resize(worst_n);
      }
    }
  }
  std::sort(worst.begin(), worst.end(),
            [by_cmd](const Row& a, const Row& b) { return by_cmd ? a.cmd_um > b.cmd_um : a.act_um > b.act_um; });
  for (std::size_t k = 0; k < std::min(worst_n, worst.size()); ++k) {
    std::fprintf(stderr, "t %s line %s speed %s: act %.2f um, cmd %.2f um\n", worst[k].t.c_str(), worst[k].line.c_str(),
                 worst[k].speed.c_str(), worst[k].act_um, worst[k].cmd_um);
  }
  std::printf("%.2f %.2f %zu\n", cmd_max * 1000.0, act_max * 1000.0, rows);
  return 0;
}
