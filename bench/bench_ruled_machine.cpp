// bench_ruled_machine.cpp — issue 17, item 4, measured on the machine (never pass/fail): the
// same zigzag passes run through both real processes (pcnc run, virtual clock, --trace) on
// configs/desktop-5axis.toml (XYZAC trunnion) twice:
//  - ruled: one G5.4 ... G5.5 piece per pass and per link, under TCP (M428): the rt's
//    RuledFollower every cycle;
//  - linear: the conventional off-line method, short G1 X Y Z A C moves between the same set
//    points with TCP off (the joints from the inverse kinematics at the set points, linear in
//    between: what CAM output gives LinuxCNC or grblHAL), F the same number.
// The passes are analytic (tip and tool axis as functions of t, away from the pole of C), so
// the intended ruled surface is known exactly; set points every --spacing mm of X.
// Printed side by side from the traces alone: the machine time over the passes and links; the
// swept tool axis's deviation from the intended surface (the tip's distance to the intended tip
// curve and the distance of the point --lever mm up the tool from the intended ruling there,
// the larger; forward kinematics of the commanded joints and of the measured ones, on the passes);
// and the joint jerk (third differences of the commanded joints over the 0.5 ms cycle, max and
// RMS, X Y Z in mm/s^3 and A C in deg/s^3, over passes and links).

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "bench_cli.hpp"
#include "config/config.hpp"
#include "config/joint_map.hpp"
#include "geometry/kinematics.hpp"
#include "ipc/trace_format.hpp"
#include "five_axis_trace.hpp"

using namespace pcnc;

namespace {

constexpr double kPi = 3.14159265358979323846;
const Vec3 kG54{12.5, 12.5, 25.0};

struct Pose {
  Vec3 tip, axis;
};

// Pass k of `passes`: t in [0, 1] runs +X on even passes, -X on odd ones.
struct Passes {
  Pose start;  // the pose the joints give before the first pass
  double length = 8.0, step = 1.0;
  int count = 3;
  Pose at(int k, double t) const {
    const double x = (k % 2 == 0) ? length * t : length * (1.0 - t);
    Pose p;
    p.tip = start.tip + Vec3{x, k * step + 0.5 * std::sin(2.0 * kPi * t), -0.4 * std::sin(kPi * t)};
    p.axis = normalized(start.axis + (0.15 * std::sin(kPi * t)) * Vec3{0.0, 1.0, 0.0} +
                        (0.08 * std::sin(2.0 * kPi * t)) * Vec3{1.0, 0.0, 0.0});
    return p;
  }
  // The swept axis's deviation at (tip, axis) from pass k's intended surface (see the header).
  double deviation(int k, const Vec3& tip, const Vec3& axis, double lever) const {
    auto d = [&](double t) { return norm(at(k, t).tip - tip); };
    double best = 0.0, bd = 1e300;
    for (int i = 0; i <= 2000; ++i) {
      const double t = i / 2000.0;
      if (d(t) < bd) bd = d(t), best = t;
    }
    double lo = std::max(0.0, best - 1e-3), hi = std::min(1.0, best + 1e-3);
    for (int i = 0; i < 60; ++i) {
      const double a = hi - 0.618 * (hi - lo), b = lo + 0.618 * (hi - lo);
      if (d(a) < d(b)) hi = b; else lo = a;
    }
    const Pose p = at(k, 0.5 * (lo + hi));
    return std::max(norm(p.tip - tip), norm(p.tip + lever * p.axis - (tip + lever * axis)));
  }
};

struct Program {
  std::string text;
  std::map<int, int> pass_of_line;  // source line -> pass index (passes only; links -1)
  int first_line = 0;               // the first line of the passes
};

// Both programs: the same approach with TCP off (G0 to the start joints, G1 A C), then the passes.
Program make_program(const Passes& ps, const MachineConfig& cfg, const Vec3& xyz0, const Rot3& rot0, double spacing,
                     double feed, bool ruled) {
  Program p;
  std::ostringstream o;
  int n = 0;
  auto line = [&](const std::string& s) {
    o << s << "\n";
    return ++n;
  };
  char buf[240];
  line("G21 G90 G94");
  std::snprintf(buf, sizeof buf, "G0 X%.6f Y%.6f Z%.6f", xyz0[0] - kG54[0], xyz0[1] - kG54[1], xyz0[2] - kG54[2]);
  line(buf);
  std::snprintf(buf, sizeof buf, "G1 A%.6f C%.6f F3600", rot0[0] * 180.0 / kPi, rot0[2] * 180.0 / kPi);
  line(buf);
  const int per_pass = std::max(2, static_cast<int>(std::ceil(ps.length / spacing)));
  const Kinematics kin = kinematics_with_tool(cfg, 0.0);
  Joints q = to_joints(cfg, xyz0, rot0);
  auto g1 = [&](const Pose& pose, int pass) {
    q = inverse(kin, ToolPose{pose.tip, pose.axis}, q, cfg.rotary_travel());
    Vec3 xyz{};
    Rot3 rot{};
    from_joints(cfg, q, xyz, rot);
    std::snprintf(buf, sizeof buf, "G1 X%.6f Y%.6f Z%.6f A%.6f C%.6f F%.0f", xyz[0] - kG54[0], xyz[1] - kG54[1],
                  xyz[2] - kG54[2], rot[0] * 180.0 / kPi, rot[2] * 180.0 / kPi, feed);
    const int l = line(buf);
    if (p.first_line == 0) p.first_line = l;
    p.pass_of_line[l] = pass;
  };
  auto piece = [&](const std::vector<Pose>& poses, int pass) {
    std::snprintf(buf, sizeof buf, "G5.4 F%.0f", feed);
    const int l = line(buf);
    if (p.first_line == 0) p.first_line = l;
    p.pass_of_line[l] = pass;
    for (const Pose& s : poses) {
      const Vec3 t = s.tip - kG54;
      std::snprintf(buf, sizeof buf, "X%.6f Y%.6f Z%.6f I%.9f J%.9f K%.9f", t[0], t[1], t[2], s.axis[0], s.axis[1], s.axis[2]);
      line(buf);
    }
    line("G5.5");
  };
  if (ruled) line("M428");
  for (int k = 0; k < ps.count; ++k) {
    std::vector<Pose> poses;
    for (int i = 0; i <= per_pass; ++i) poses.push_back(ps.at(k, static_cast<double>(i) / per_pass));
    if (ruled) {
      piece(poses, k);
    } else {
      for (std::size_t i = 1; i < poses.size(); ++i) g1(poses[i], k);
    }
    if (k + 1 < ps.count) {  // the link: straight in Y, the axis kept (it is the start axis at both ends)
      const Pose a = ps.at(k, 1.0), b = ps.at(k + 1, 0.0);
      if (ruled) {
        piece({a, Pose{0.5 * (a.tip + b.tip), a.axis}, b}, -1);
      } else {
        g1(b, -1);
      }
    }
  }
  if (ruled) line("M429");
  line("M2");
  p.text = o.str();
  return p;
}

struct Figures {
  double time_s = 0.0;
  double dev_cmd = 0.0, dev_act = 0.0;  // mm
  double jerk_lin_max = 0.0, jerk_lin_rms = 0.0, jerk_rot_max = 0.0, jerk_rot_rms = 0.0;
  int rows = 0;
  std::string error;
};

Figures measure(const Passes& ps, const Program& prog, const MachineConfig& cfg, const std::string& config_path,
                const std::string& dir, const std::string& tag, double lever, const std::string& contouring) {
  Figures f;
  const std::string path = dir + "/" + tag + ".ngc", trace = dir + "/" + tag + ".csv";
  std::ofstream(path) << prog.text;
  const test::ProcessResult r =
      test::run_process({test::bin_dir() + "/tools/pcnc", "run", path, "--config", config_path, "--clock", "virtual", "--trace", trace,
                         "--contouring", contouring}, 600);
  if (r.exit_code != 0) {
    f.error = "pcnc run exited " + std::to_string(r.exit_code) + ": " + r.out + r.err;
    return f;
  }
  std::vector<std::pair<TraceSample, TraceJoints>> rows;
  for (const test::FiveAxisRow& row : test::read_five_axis_trace(trace, cfg.rotary_mask())) {
    const TraceSample& ts = row.s;
    if (ts.line >= static_cast<std::uint32_t>(prog.first_line) && ts.state == MachineState::kRunning &&
        prog.pass_of_line.count(static_cast<int>(ts.line)) != 0) {
      rows.emplace_back(ts, row.j);
    }
  }
  if (rows.size() < 4) {
    f.error = "too few trace rows on the passes";
    return f;
  }
  const Kinematics kin = kinematics_with_tool(cfg, 0.0);
  const double dt = cfg.cycle_period_s();
  f.time_s = rows.back().first.t - rows.front().first.t + dt;
  f.rows = static_cast<int>(rows.size());
  double sum_lin = 0.0, sum_rot = 0.0;
  int nj = 0;
  std::vector<Joints> q(rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i) q[i] = to_joints(cfg, rows[i].first.commanded, rows[i].second.commanded);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const int pass = prog.pass_of_line.at(static_cast<int>(rows[i].first.line));
    if (pass >= 0 && i % 4 == 0) {  // every 4th cycle: the deviation search is the bench's cost
      const ToolPose c = forward(kin, q[i]);
      const ToolPose a = forward(kin, to_joints(cfg, rows[i].first.actual, rows[i].second.actual));
      f.dev_cmd = std::max(f.dev_cmd, ps.deviation(pass, c.tip, c.axis, lever));
      f.dev_act = std::max(f.dev_act, ps.deviation(pass, a.tip, a.axis, lever));
    }
    if (i >= 3 && std::abs(rows[i].first.t - rows[i - 3].first.t - 3 * dt) < 1e-6) {
      for (std::size_t j = 0; j < 5; ++j) {
        const double jerk = (q[i][j] - 3.0 * q[i - 1][j] + 3.0 * q[i - 2][j] - q[i - 3][j]) / (dt * dt * dt);
        if (j < 3) {
          f.jerk_lin_max = std::max(f.jerk_lin_max, std::abs(jerk));
          sum_lin += jerk * jerk;
        } else {
          const double deg = jerk * 180.0 / kPi;
          f.jerk_rot_max = std::max(f.jerk_rot_max, std::abs(deg));
          sum_rot += deg * deg;
        }
      }
      ++nj;
    }
  }
  f.jerk_lin_rms = nj > 0 ? std::sqrt(sum_lin / (3.0 * nj)) : 0.0;
  f.jerk_rot_rms = nj > 0 ? std::sqrt(sum_rot / (2.0 * nj)) : 0.0;
  return f;
}

}  // namespace

int main(int argc, char** argv) {
  pcnc::BenchCli app{"issue 17 item 4 on the machine: ruled blocks against short 5-axis G1 moves (TCP off, linear joints), "
               "the same passes through pcnc run (virtual clock) on configs/desktop-5axis.toml"};
  double spacing = 1.0, feed = 600.0, lever = 10.0;
  int passes = 3;
  std::string contouring = "on";
  app.add_option("--spacing", spacing, "set points every this many mm along a pass")->show_default();
  app.add_option("--feed", feed, "F, mm/min")->show_default();
  app.add_option("--passes", passes, "zigzag passes, 1 mm apart")->show_default();
  app.add_option("--lever", lever, "the point this many mm up the tool measures the axis's deviation")->show_default();
  app.add_option("--contouring", contouring,
                 "pcnc run --contouring for both runs: on (M21, the G1 moves flow through their junctions under the "
                 "look-ahead across rotary blocks) or off (every G1 junction stops; the ruled pieces flow either way)")
      ->one_of({"on", "off"})
      ->show_default();
  if (const int rc = app.parse(argc, argv); rc >= 0) return rc;

  const std::string dir = test::make_temp_dir("bench-ruled");
  const std::string config = test::write_five_axis_config(dir, "bench-ruled");
  const MachineConfig cfg = load_config(config);

  const Vec3 xyz0 = Vec3{-4.0, -2.0, -5.0} + kG54;
  const Rot3 rot0{12.0 * kPi / 180.0, 0.0, 35.0 * kPi / 180.0};
  Passes ps;
  ps.count = passes;
  const ToolPose p0 = forward(kinematics_with_tool(cfg, 0.0), to_joints(cfg, xyz0, rot0));
  ps.start = {p0.tip, p0.axis};

  const Program ruled = make_program(ps, cfg, xyz0, rot0, spacing, feed, true);
  const Program linear = make_program(ps, cfg, xyz0, rot0, spacing, feed, false);
  const Figures fr = measure(ps, ruled, cfg, config, dir, "ruled", lever, contouring);
  const Figures fl = measure(ps, linear, cfg, config, dir, "linear", lever, contouring);
  if (!fr.error.empty() || !fl.error.empty()) {
    std::fprintf(stderr, "bench_ruled_machine: %s %s\n", fr.error.c_str(), fl.error.c_str());
    return 1;
  }
  std::printf("bench_ruled_machine: %d passes of %.0f mm, set points every %.2f mm, F%.0f, desktop-5axis, virtual clock, "
              "--contouring %s\n",
              passes, ps.length, spacing, feed, contouring.c_str());
  std::printf("%-44s %16s %16s\n", "", "ruled (G5.4)", "linear (G1 A C)");
  std::printf("%-44s %16.3f %16.3f\n", "machine time over passes and links, s", fr.time_s, fl.time_s);
  std::printf("%-44s %16.4f %16.4f\n", "swept axis off the surface, commanded, um", fr.dev_cmd * 1e3, fl.dev_cmd * 1e3);
  std::printf("%-44s %16.4f %16.4f\n", "swept axis off the surface, measured, um", fr.dev_act * 1e3, fl.dev_act * 1e3);
  std::printf("%-44s %16.4g %16.4g\n", "joint jerk X Y Z max, mm/s^3", fr.jerk_lin_max, fl.jerk_lin_max);
  std::printf("%-44s %16.4g %16.4g\n", "joint jerk X Y Z RMS, mm/s^3", fr.jerk_lin_rms, fl.jerk_lin_rms);
  std::printf("%-44s %16.4g %16.4g\n", "joint jerk A C max, deg/s^3", fr.jerk_rot_max, fl.jerk_rot_max);
  std::printf("%-44s %16.4g %16.4g\n", "joint jerk A C RMS, deg/s^3", fr.jerk_rot_rms, fl.jerk_rot_rms);
  std::printf("(deviation: the larger of the tip's distance to the intended tip curve and of the point %.0f mm up the "
              "tool from the intended ruling there; every 4th cycle of the passes)\n",
              lever);
  return 0;
}
