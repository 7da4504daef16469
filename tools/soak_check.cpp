// soak_check.cpp — the end of `pcnc soak`: every trace the rt wrote, checked against the
// blocks of the run it belongs to (on the path, nothing skipped or repeated, no step beyond the
// axes' limits, inside the travel), and the figures printed (see soak_parts.hpp).
#include "soak_parts.hpp"


#include <CLI/CLI.hpp>
#include <spdlog/spdlog.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <numbers>
#include <random>
#include <regex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "config/config.hpp"
#include "ctl.hpp"
#include "gcode/program.hpp"
#include "geometry/nurbs.hpp"
#include "geometry/plane.hpp"
#include "ipc/block_nurbs.hpp"
#include "ipc/segment.hpp"
#include "launcher.hpp"


namespace pcnc::soak {
namespace {

// Where p lies on block b: arc length s from the block's start and the distance d from the
// nearest point of the block's path. `hint` picks the turn of a multi-turn flat arc.
void locate(const Block& b, const Vec3& p, double hint, double& s, double& d) {
  switch (b.kind) {
    case BlockKind::kRapid:
    case BlockKind::kLine: {
      const Vec3 v = b.end - b.start;
      const double len = norm(v);
      const double t = len > 0.0 ? std::clamp(dot(p - b.start, v) / (len * len), 0.0, 1.0) : 0.0;
      s = t * len;
      d = norm(b.start + t * v - p);
      return;
    }
    case BlockKind::kArc: {
      const ArcGeometry& g = b.arc;
      const auto pa = plane_axes(g.normal_axis);
      const int a0 = pa[0], a1 = pa[1], an = g.normal_axis;
      const double two_pi = 2.0 * std::numbers::pi;
      const double sw = std::abs(g.sweep);
      const double th = std::atan2(p[a1] - g.center[a1], p[a0] - g.center[a0]);
      double tr0 = std::remainder((th - g.start_angle) * (g.sweep < 0.0 ? -1.0 : 1.0), two_pi);
      if (tr0 < 0.0) tr0 += two_pi;
      const double r1 = std::hypot(b.end[a0] - g.center[a0], b.end[a1] - g.center[a1]);
      d = 1e300;
      for (int k = -1; k <= static_cast<int>(sw / two_pi) + 1; ++k) {
        const double u = std::clamp((tr0 + two_pi * k) / sw, 0.0, 1.0);
        const double theta = g.start_angle + g.sweep * u;
        const double r = g.radius + (r1 - g.radius) * u;
        Vec3 e = b.start;
        e[a0] = g.center[a0] + r * std::cos(theta);
        e[a1] = g.center[a1] + r * std::sin(theta);
        e[an] = b.start[an] + g.helix * u;
        const double dk = norm(e - p);
        const double sk = u * b.length;
        if (dk < d - 1e-9 || (std::abs(dk - d) <= 1e-9 && std::abs(sk - hint) < std::abs(s - hint))) {
          d = dk;
          s = sk;
        }
      }
      return;
    }
    case BlockKind::kNurbs: {
      const NurbsView v = view_of(b.nurbs);
      const double u = nurbs_project(v, p, &d, 8);
      s = nurbs_arc_length(v, v.u_min(), u);
      return;
    }
    default:
      s = 0.0;
      d = norm(p - b.end);
      return;
  }
}


// ---- the trace --------------------------------------------------------------------------------

struct Row {
  double t = 0.0;
  std::uint32_t line = 0;
  std::string state;
  Vec3 cmd{}, ferr{};
};

std::vector<Row> read_trace(const std::string& path) {
  std::vector<Row> rows;
  std::ifstream in(path);
  std::string line;
  if (!std::getline(in, line)) return rows;
  while (std::getline(in, line)) {
    std::stringstream ss(line);
    std::string f[13];
    int n = 0;
    while (n < 13 && std::getline(ss, f[n], ',')) ++n;
    if (n < 13) continue;  // a line cut by a killed rt
    try {
      Row r;
      r.t = std::stod(f[0]);
      r.line = static_cast<std::uint32_t>(std::stoul(f[1]));
      r.state = f[2];
      for (int i = 0; i < 3; ++i) {
        r.cmd[i] = std::stod(f[3 + i]);
        r.ferr[i] = std::stod(f[9 + i]);
      }
      rows.push_back(r);
    } catch (const std::exception&) {
    }
  }
  return rows;
}

double max_abs(const Vec3& v) { return std::max({std::abs(v[0]), std::abs(v[1]), std::abs(v[2])}); }


}  // namespace

int Soak::analyse() {
  const double dt = cfg_.cycle_period_s();
  const double tol = o_.path_tol_mm;
  double vmax_path = 0.0;
  for (int i = 0; i < 3; ++i) vmax_path += cfg_.axes[i].max_velocity_mm_s * cfg_.axes[i].max_velocity_mm_s;
  const double step_bound = std::sqrt(vmax_path) * dt * 1.01;
  std::size_t rows_checked = 0, off_path_rows = 0, excursion_rows = 0;
  double worst_v = 0.0, worst_a = 0.0, worst_off = 0.0, repeated_mm = 0.0, skipped_mm = 0.0;
  int limit_failures = 0;
  double lost_path_mm = 0.0, lost_time_s = 0.0;

  std::vector<std::vector<Row>> traces;
  for (const auto& path : traces_) traces.push_back(read_trace(path));

  // Limits over every trace (consecutive cycles only).
  for (std::size_t ti = 0; ti < traces.size(); ++ti) {
    const auto& rows = traces[ti];
    for (std::size_t k = 0; k < rows.size(); ++k) {
      for (int i = 0; i < 3; ++i) {
        const AxisConfig& ax = cfg_.axes[i];
        const double x = rows[k].cmd[i];
        if (x < ax.travel_min_mm - 1e-7 || x > ax.travel_max_mm + 1e-7) {
          if (limit_failures++ < 5) failures_.push_back("trace " + std::to_string(ti) + " t=" + std::to_string(rows[k].t) + ": setpoint outside the travel");
        }
        if (k >= 1 && std::abs(rows[k].t - rows[k - 1].t - dt) < 0.25 * dt) {
          const double v = std::abs(x - rows[k - 1].cmd[i]) / dt;
          worst_v = std::max(worst_v, v / ax.max_velocity_mm_s);
          if (v > ax.max_velocity_mm_s * (1.0 + 1e-6) + 1e-6 / dt) {
            if (limit_failures++ < 5) failures_.push_back("trace " + std::to_string(ti) + " t=" + std::to_string(rows[k].t) + ": a setpoint step beyond the velocity limit (a jump) on " + std::string(1, "XYZ"[i]));
          }
          if (k >= 2 && std::abs(rows[k - 1].t - rows[k - 2].t - dt) < 0.25 * dt) {
            const double acc = std::abs(x - 2.0 * rows[k - 1].cmd[i] + rows[k - 2].cmd[i]) / (dt * dt);
            const double slack = 4e-7 / (dt * dt);  // the trace's 0.1 um rounding
            worst_a = std::max(worst_a, std::max(0.0, acc - slack) / ax.max_accel_mm_s2);
            if (acc > ax.max_accel_mm_s2 * (1.0 + 1e-3) + slack) {
              if (limit_failures++ < 5) failures_.push_back("trace " + std::to_string(ti) + " t=" + std::to_string(rows[k].t) + ": acceleration beyond the limit on " + std::string(1, "XYZ"[i]));
            }
          }
        }
      }
    }
  }

  // The path of every run, walked along its blocks.
  for (std::size_t ai = 0; ai < attempts_.size(); ++ai) {
    const Attempt& a = attempts_[ai];
    const auto& rows = traces[static_cast<std::size_t>(a.trace)];
    const auto& path = a.path;
    if (path.empty()) continue;
    std::size_t j = 0;
    double s_cur = 0.0, s_max = 0.0, prev_g = 0.0;
    bool excursion = false, seen = false;
    std::size_t since_on = 0;
    const std::string name = "run " + std::to_string(ai + 1);
    for (const Row& r : rows) {
      if (r.t < a.t_begin - 1e-9 || r.t > a.t_end + 1e-9) continue;
      ++rows_checked;
      ++since_on;
      if (r.state == "JOGGING") {
        excursion = true;
        ++excursion_rows;
        continue;
      }
      if (r.state == "FAULT" || r.state == "ESTOP") {
        failures_.push_back(name + ": the machine went to " + r.state + " at t=" + std::to_string(r.t));
        break;
      }
      std::size_t found = path.size();
      double fs = 0.0, best_d = 1e300;
      std::size_t back = path.size();
      double back_s = 0.0;
      for (std::size_t k = j; k < path.size() && k < j + 64; ++k) {
        double s = 0.0, d = 0.0;
        locate(path[k].b, r.cmd, k == j ? s_cur : 0.0, s, d);
        best_d = std::min(best_d, d);
        if (d > tol) continue;
        if (k == j && s < s_cur - tol) {
          back = k;
          back_s = s;
          continue;
        }
        found = k;
        fs = s;
        break;
      }
      if (found == path.size() && back < path.size()) {
        found = back;
        fs = back_s;
      }
      for (std::size_t k = j; found == path.size() && k-- > 0 && k + 4 > j;) {
        double s = 0.0, d = 0.0;
        locate(path[k].b, r.cmd, 0.0, s, d);
        if (d <= tol) {
          found = k;
          fs = s;
        }
      }
      if (found == path.size()) {
        if (excursion) {
          ++excursion_rows;  // the return leg to the pause point
        } else {
          ++off_path_rows;
          worst_off = std::max(worst_off, best_d);
          if (off_path_rows <= 3) failures_.push_back(name + ": setpoint off the program's path by " + std::to_string(best_d) + " mm at t=" + std::to_string(r.t));
        }
        continue;
      }
      const double g = path[found].s0 + fs;
      if (excursion) {
        // Jogged away: nothing counts until the machine is back on the pause point (the
        // return leg may run along or across the path elsewhere). A run that never gets back
        // fails the coverage check below.
        if (std::abs(g - s_max) > tol) {
          ++excursion_rows;
          continue;
        }
        excursion = false;
      }
      if (seen && g > s_max + step_bound * static_cast<double>(since_on) + tol) {
        skipped_mm += g - s_max;
        failures_.push_back(name + ": path skipped from s=" + std::to_string(s_max) + " to " + std::to_string(g) + " mm");
      }
      if (g < s_max - tol) {
        repeated_mm = std::max(repeated_mm, s_max - g);
        failures_.push_back(name + ": path repeated from s=" + std::to_string(g) + " back from " + std::to_string(s_max) + " mm");
        s_max = g;  // report each regression once
      }
      s_max = std::max(s_max, g);
      prev_g = g;
      since_on = 0;
      seen = true;
      j = found;
      s_cur = fs;
    }
    (void)prev_g;
    if (!a.aborted && a.end == "completed" && s_max < a.total - tol) {
      failures_.push_back(name + ": the trace covers " + std::to_string(s_max) + " of " + std::to_string(a.total) + " mm");
    }
    if (a.aborted) {
      lost_path_mm += s_max;
    }
    std::printf("%s: %s, %zu blocks, path %.3f mm, covered %.3f mm\n", name.c_str(), a.end.c_str(), path.size(), a.total, s_max);
  }

  // Following error at each recovery: the trace from the kill to 1 s after the resume.
  for (Fault& f : faults_) {
    if ((f.kind != "kill -9 host" && f.kind != "HOST_LOST unasked") || f.t_back <= 0.0) continue;
    for (const Row& r : traces[static_cast<std::size_t>(f.trace)]) {
      if (r.t >= f.t_kill - 0.01 && r.t <= f.t_back + 1.0) f.max_ferr_mm = std::max(f.max_ferr_mm, max_abs(r.ferr));
    }
    lost_time_s += f.to_resumed_ms / 1000.0;
  }

  // Figures.
  std::map<std::string, std::pair<int, int>> by_kind;
  for (const Fault& f : faults_) {
    by_kind[f.kind].first++;
    by_kind[f.kind].second += f.survived ? 1 : 0;
  }
  int injected = 0, survived = 0;
  std::printf("\n==== soak figures (seed %llu) ====\n", static_cast<unsigned long long>(o_.seed));
  for (const auto& [k, v] : by_kind) {
    std::printf("  %-18s injected %4d  survived %4d\n", k.c_str(), v.first, v.second);
    injected += v.first;
    survived += v.second;
  }
  std::printf("  %-18s injected %4d  survived %4d\n", "all faults", injected, survived);
  auto stats = [&](const char* label, const std::function<double(const Fault&)>& get, const std::string& kind) {
    std::vector<double> v;
    for (const Fault& f : faults_) {
      if (f.kind == kind && get(f) >= 0.0) v.push_back(get(f));
    }
    if (v.empty()) return;
    double sum = 0.0;
    for (double x : v) sum += x;
    std::printf("  %-36s min %8.1f  mean %8.1f  max %8.1f  (n=%zu)\n", label, *std::min_element(v.begin(), v.end()),
                sum / static_cast<double>(v.size()), *std::max_element(v.begin(), v.end()), v.size());
  };
  stats("host kill -> HOST_LOST, ms", [](const Fault& f) { return f.to_lost_ms; }, "kill -9 host");
  stats("host kill -> resumed, ms", [](const Fault& f) { return f.to_resumed_ms; }, "kill -9 host");
  stats("max |ferr| per host recovery, um", [](const Fault& f) { return f.t_back > 0.0 ? 1000.0 * f.max_ferr_mm : -1.0; }, "kill -9 host");
  stats("rt kill -> seen lost by host, ms", [](const Fault& f) { return f.to_lost_ms; }, "kill -9 rt");
  stats("rt kill -> re-attached, ms", [](const Fault& f) { return f.to_resumed_ms; }, "kill -9 rt");
  stats("restarted rt off last position, mm", [](const Fault& f) { return f.position_jump_mm; }, "kill -9 rt");
  std::printf("  runs %zu (completed %zu, ended by an rt kill %zu)\n", attempts_.size(),
              static_cast<std::size_t>(std::count_if(attempts_.begin(), attempts_.end(), [](const Attempt& a) { return a.end == "completed"; })),
              static_cast<std::size_t>(std::count_if(attempts_.begin(), attempts_.end(), [](const Attempt& a) { return a.aborted; })));
  std::printf("  lost work: %.1f s standing still in host recoveries, %.3f mm of path repeated, %.3f mm of path "
              "cut by runs an rt kill ended\n", lost_time_s, repeated_mm, lost_path_mm);
  std::printf("  trace rows checked %zu, off the path %zu (worst %.6f mm), jog excursions %zu, skipped %.3f mm\n",
              rows_checked, off_path_rows, off_path_rows ? worst_off : 0.0, excursion_rows, skipped_mm);
  std::printf("  worst setpoint velocity %.3f x the axis limit, acceleration %.3f x the axis limit\n", worst_v, worst_a);
  if (!o_.summary.empty()) {
    json j = {{"seed", o_.seed}, {"file", o_.file}, {"minutes", o_.minutes}, {"faults_injected", injected},
              {"faults_survived", survived}, {"repeated_mm", repeated_mm}, {"skipped_mm", skipped_mm},
              {"off_path_rows", off_path_rows}, {"worst_velocity_ratio", worst_v}, {"worst_accel_ratio", worst_a},
              {"lost_time_s", lost_time_s}, {"failures", failures_}};
    json fl = json::array();
    for (const Fault& f : faults_) {
      fl.push_back({{"kind", f.kind}, {"survived", f.survived}, {"note", f.note}, {"to_lost_ms", f.to_lost_ms},
                    {"to_resumed_ms", f.to_resumed_ms}, {"max_ferr_mm", f.max_ferr_mm}, {"position_jump_mm", f.position_jump_mm}});
    }
    j["faults"] = fl;
    std::ofstream(o_.summary) << j.dump(1) << "\n";
  }
  if (!failures_.empty()) {
    std::printf("\nINVARIANTS FAILED (%zu):\n", failures_.size());
    for (const auto& f : failures_) std::printf("  %s\n", f.c_str());
    return 1;
  }
  std::printf("  all invariants held\n");
  return 0;
}


}  // namespace pcnc::soak
