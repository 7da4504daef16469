// test_proc_five_axis.cpp — a 5-axis program with tool-centre-point control through the real
// pcnc-host and pcnc-rt (virtual clock) on configs/desktop-5axis.toml (XYZAC trunnion), checked
// from the trace alone: the joints' columns are there, the tool tip (forward kinematics of the
// commanded and of the measured joints, tool length from the tool table) stays on the programmed
// line of every TCP move, and no joint leaves its travel or exceeds its velocity on any cycle.
// The program: a tilted line leaving the pole of C, a line through the singularity (A +20 to
// -20 at constant C), a move turning C with the tool tilted, and a tilted helix whose C follows
// the angle. A second program with TCP off checks the joints' linear interpolation. A third, dense
// one (360 short moves under M21) checks that TCP blocks flow through their junctions within every
// joint's velocity and acceleration; `pcnc check --fit` scales a TCP program that is too large.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

#include "config/config.hpp"
#include "config/joint_map.hpp"
#include "gcode/tcp_move.hpp"
#include "geometry/kinematics.hpp"
#include "ipc/trace_format.hpp"
#include "five_axis_trace.hpp"
#include "service_procs.hpp"
#include "test_constants.hpp"

namespace pcnc::test {
namespace {


// A program written line by line, with each line's number.
struct ProgramText {
  std::ostringstream text;
  int lines = 0;
  int line(const std::string& s) {
    text << s << "\n";
    return ++lines;
  }
};

struct Segment {
  Vec3 a, b;  // machine (= workpiece) coordinates of the tool tip, mm
};

double distance_to_segment(const Vec3& p, const Segment& s) {
  const Vec3 d = s.b - s.a;
  const double n = dot(d, d);
  const double t = n > 0.0 ? std::clamp(dot(p - s.a, d) / n, 0.0, 1.0) : 0.0;
  return norm(p - (s.a + t * d));
}

using Row = FiveAxisRow;

std::vector<Row> read_trace(const std::string& path, RotaryMask mask, std::string& header) {
  return read_five_axis_trace(path, mask, &header);
}

constexpr double kToolLength = 4.25;  // T2 of configs/desktop-mill.tbl

TEST(FiveAxisRun, TcpProgramKeepsTheTipOnTheLineAndTheJointsWithinTheirLimits) {
  const std::string dir = make_temp_dir("five");
  const std::string config = write_five_axis_config(dir, "five");
  const MachineConfig cfg = load_config(config);
  ASSERT_EQ(cfg.kinematics.kind, KinematicsKind::kTableTable);

  // the program, and the tip's programmed segment per source line (program point + G54)
  ProgramText prog;
  std::map<int, Segment> lines;
  auto line = [&](const std::string& text) { return prog.line(text); };
  Vec3 at{0.0, 0.0, -8.0};
  auto tcp = [&](const Vec3& p, double a, double c, double f) {
    char buf[160];
    std::snprintf(buf, sizeof buf, "G1 X%.4f Y%.4f Z%.4f A%.3f C%.3f F%.0f", p[0], p[1], p[2], a, c, f);
    lines[line(buf)] = Segment{at + kG54, p + kG54};
    at = p;
  };
  line("G21 G90 G94");
  line("T2 M6");
  line("G0 X0 Y0 Z-8");
  line("G1 C30 F3600");
  line("G43.4 H2");
  at = {0.0, 0.0, -8.0 - kToolLength};  // the tip, 4.25 mm below the gauge point: G43.4 moved nothing
  tcp({4.0, 2.0, -9.0}, 20.0, 30.0, 300.0);     // leaves the pole along C = 30
  tcp({-4.0, 3.0, -9.0}, -20.0, 30.0, 300.0);   // through the singularity: A changes sign, C stays
  tcp({-2.0, -3.0, -8.0}, -20.0, 120.0, 400.0);  // C turns with the tool tilted
  for (int k = 0; k <= 12; ++k) {                // a tilted helix, C following the angle
    const double t = (120.0 + 30.0 * k) * kRadPerDeg;
    tcp({3.0 * std::cos(t), 3.0 * std::sin(t), -8.0 - 0.1 * k}, -15.0, 120.0 + 30.0 * k, 400.0);
  }
  tcp({0.0, 0.0, -7.0}, 0.0, 480.0, 400.0);  // back onto the pole, C kept
  line("M429");
  line("M2");
  const std::string path = dir + "/five.ngc";
  std::ofstream(path) << prog.text.str();

  const std::string trace = dir + "/five.csv";
  const ProcessResult r = run_process({pcnc_exe(), "run", path, "--config", config, "--tool-table",
                                       source_dir() + "/configs/desktop-mill.tbl", "--clock", "virtual", "--trace", trace},
                                      300);
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("result            completed"), std::string::npos) << r.out;

  std::string header;
  const std::vector<Row> rows = read_trace(trace, cfg.rotary_mask(), header);
  EXPECT_EQ(header, std::string(kTraceCsvHeader) + ",cmd_a,act_a,ferr_a,cmd_c,act_c,ferr_c");
  ASSERT_GT(rows.size(), 1000u);

  const Kinematics kin = kinematics_with_tool(cfg, kToolLength);
  const RotaryAxisConfig& A = *cfg.rotary[0];
  double worst_cmd = 0.0, worst_act = 0.0;
  int on_tcp = 0;
  std::map<int, int> rows_per_line;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const Row& row = rows[i];
    const Joints qc = to_joints(cfg, row.s.commanded, row.j.commanded);
    const Joints qa = to_joints(cfg, row.s.actual, row.j.actual);
    // every joint inside its travel, commanded and measured, on every cycle; within its velocity
    // (the commanded joints' difference over one cycle)
    ASSERT_EQ(commanded_joint_violation(cfg, rows, i), "");
    for (int ax = 0; ax < kAxes; ++ax) {
      const AxisConfig& ac = cfg.axes[static_cast<std::size_t>(ax)];
      ASSERT_GE(qa[ax], ac.travel_min_mm - 1e-3) << "row " << i;
      ASSERT_LE(qa[ax], ac.travel_max_mm + 1e-3) << "row " << i;
    }
    ASSERT_GE(qa[kTilt], A.travel_min_rad - 1e-4) << "row " << i;
    ASSERT_LE(qa[kTilt], A.travel_max_rad + 1e-4) << "row " << i;
    // the tool tip on the programmed line of a TCP move
    const auto seg = lines.find(static_cast<int>(row.s.line));
    if (seg == lines.end() || row.s.state != MachineState::kRunning) continue;
    ++on_tcp;
    ++rows_per_line[seg->first];
    worst_cmd = std::max(worst_cmd, distance_to_segment(forward(kin, qc).tip, seg->second));
    worst_act = std::max(worst_act, distance_to_segment(forward(kin, qa).tip, seg->second));
  }
  EXPECT_EQ(rows_per_line.size(), lines.size()) << "every TCP line ran";
  EXPECT_GT(on_tcp, 5000);
  EXPECT_LT(worst_cmd, 1e-4) << "commanded tip off the line, mm";
  EXPECT_LT(worst_act, 0.005) << "measured tip off the line, mm";
  // the rotary joints really moved: C turned through 450 degrees, A through +-20
  double cmax = -1e9, amin = 1e9;
  for (const Row& row : rows) {
    cmax = std::max(cmax, row.j.commanded[2]);
    amin = std::min(amin, row.j.commanded[0]);
  }
  EXPECT_NEAR(cmax * kDegPerRad, 480.0, 1e-6);
  EXPECT_NEAR(amin * kDegPerRad, -20.0, 1e-6);
  std::printf("[ figures ] TCP rows %d, tip off the line: commanded %.3g um, measured %.3g um\n", on_tcp,
              worst_cmd * 1e3, worst_act * 1e3);
}

// TCP off: the joints run linearly with the path parameter, and a move that only turns the
// tool runs at F in deg/min.
TEST(FiveAxisRun, TcpOffJointsInterpolateLinearly) {
  const std::string dir = make_temp_dir("five-off");
  const std::string config = write_five_axis_config(dir, "five-off");
  const MachineConfig cfg = load_config(config);
  const std::string path = dir + "/off.ngc";
  std::ofstream(path) << "G21 G90 G94\nG0 X0 Y0 Z-5\nG1 A30 F1800\nG1 X5 C90 F300\nG1 A0 C0 F3600\nM2\n";
  const std::string trace = dir + "/off.csv";
  const ProcessResult r = run_process(
      {pcnc_exe(), "run", path, "--config", config, "--clock", "virtual", "--trace", trace, "--report", dir + "/off.html"},
      300);
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_GT(read_file(dir + "/off.html").size(), 1000u) << "the report reads a trace with the joints' columns";
  std::string header;
  const std::vector<Row> rows = read_trace(trace, cfg.rotary_mask(), header);
  int on3 = 0, on4 = 0;
  double worst = 0.0, a_rate = 0.0;
  for (std::size_t i = 1; i < rows.size(); ++i) {
    const Row& row = rows[i];
    if (row.s.line == 4) {  // X 12.5 -> 17.5 while C 0 -> 90 deg: C = 18 deg per mm of X
      ++on4;
      worst = std::max(worst, std::abs(row.j.commanded[2] * kDegPerRad - 18.0 * (row.s.commanded[0] - 12.5)));
      EXPECT_NEAR(row.j.commanded[0] * kDegPerRad, 30.0, 1e-9);
    }
    if (row.s.line == 3) {  // A alone at 1800 deg/min = 30 deg/s at most
      ++on3;
      a_rate = std::max(a_rate, std::abs(row.j.commanded[0] - rows[i - 1].j.commanded[0]) / cfg.cycle_period_s());
      EXPECT_NEAR(row.s.commanded[0], 12.5, 1e-12);
    }
  }
  EXPECT_GT(on4, 100);
  EXPECT_GT(on3, 100);
  EXPECT_LT(worst, 1e-6) << "deg";
  EXPECT_NEAR(a_rate * kDegPerRad, 30.0, 1e-6);
  const Row& last = rows.back();
  EXPECT_NEAR(last.j.commanded[0], 0.0, 1e-12);
  EXPECT_NEAR(last.j.commanded[2], 0.0, 1e-12);
  EXPECT_NEAR(last.j.actual[0], 0.0, 5e-4);
}

// Dense 5-axis CAM-like output under TCP and M21: 360 short G1 X Y Z A C moves (0.05 mm of tip
// travel each) on a tilted helix whose tilt waves and whose C turns at half its angle. The rt
// passes their junctions at the joint-space junction speed instead of stopping at each: no cycle
// inside the run stands still and the tip keeps near the feed, while on every cycle of the whole
// run no joint exceeds its velocity or acceleration (the commanded joints' first and second
// differences) and the tip stays on the programmed lines.
TEST(FiveAxisRun, DenseTcpProgramFlowsThroughItsJunctions) {
  const std::string dir = make_temp_dir("five-dense");
  const std::string config = write_five_axis_config(dir, "five-dense");
  const MachineConfig cfg = load_config(config);
  ProgramText prog;
  std::map<int, Segment> lines;
  auto line = [&](const std::string& text) { return prog.line(text); };
  constexpr double kFeed = 600.0;  // mm/min: 10 mm/s
  auto point = [](int k) {
    const double t = k * kRadPerDeg;
    return Vec3{3.0 * std::cos(t), 3.0 * std::sin(t), -8.0 + 0.002 * k};
  };
  line("G21 G90 G94 M21");
  line("G0 X3 Y0 Z-8");
  line("M428");
  line("G1 A-15 F3600");  // the tool tilts about the tip, which stands at the helix's start
  Vec3 at = point(0);
  std::map<int, int> index;  // source line -> k
  int first = 0, last = 0;
  for (int k = 1; k <= 360; ++k) {
    const Vec3 p = point(k);
    const double a = -15.0 + 5.0 * std::sin(2.0 * k * kRadPerDeg), c = 0.5 * k;
    char buf[160];
    std::snprintf(buf, sizeof buf, "G1 X%.5f Y%.5f Z%.5f A%.5f C%.5f F%.0f", p[0], p[1], p[2], a, c, kFeed);
    const int ln = line(buf);
    if (k == 1) first = ln;
    last = ln;
    lines[ln] = Segment{at + kG54, p + kG54};
    index[ln] = k;
    at = p;  // the program's 5 decimals: within 0.005 um of it
  }
  line("M429");
  line("M2");
  const std::string path = dir + "/dense.ngc";
  std::ofstream(path) << prog.text.str();
  const std::string trace = dir + "/dense.csv";
  const ProcessResult r = run_process({pcnc_exe(), "run", path, "--config", config, "--clock", "virtual", "--trace", trace}, 300);
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  std::string header;
  const std::vector<Row> rows = read_trace(trace, cfg.rotary_mask(), header);
  ASSERT_GT(rows.size(), 100u);

  const Kinematics kin = kinematics_with_tool(cfg, 0.0);
  const double dt = cfg.cycle_period_s();
  const JointLimits limits = joint_limits(cfg);
  const Joints& vmax = limits.velocity;
  const Joints& amax = limits.acceleration;
  double worst_v = 0.0, worst_a = 0.0;  // the largest share of a joint's limit on any cycle
  double helix_v = 0.0, helix_a = 0.0;  // the same on the helix's moves
  double worst_cmd = 0.0, worst_act = 0.0, slowest = 1e9;
  int inner = 0, still = 0, first_row = -1, last_row = -1;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const Joints q = to_joints(cfg, rows[i].s.commanded, rows[i].j.commanded);
    if (i >= 1) {
      const Joints p = to_joints(cfg, rows[i - 1].s.commanded, rows[i - 1].j.commanded);
      for (int j = 0; j < kJoints; ++j) {
        const auto k = static_cast<std::size_t>(j);
        const double share_v = std::abs(q[k] - p[k]) / dt / vmax[k];
        worst_v = std::max(worst_v, share_v);
        const bool on_helix = lines.count(static_cast<int>(rows[i].s.line)) > 0;
        if (on_helix) helix_v = std::max(helix_v, share_v);
        if (i >= 2) {
          const Joints pp = to_joints(cfg, rows[i - 2].s.commanded, rows[i - 2].j.commanded);
          const double share_a = std::abs(q[k] - 2.0 * p[k] + pp[k]) / (dt * dt) / amax[k];
          worst_a = std::max(worst_a, share_a);
          if (on_helix) helix_a = std::max(helix_a, share_a);
        }
      }
    }
    const int ln = static_cast<int>(rows[i].s.line);
    if (ln == first && first_row < 0) first_row = static_cast<int>(i);
    if (ln == last) last_row = static_cast<int>(i);
    const auto seg = lines.find(ln);
    if (seg == lines.end() || rows[i].s.state != MachineState::kRunning) continue;
    ++inner;
    worst_cmd = std::max(worst_cmd, distance_to_segment(forward(kin, q).tip, seg->second));
    worst_act = std::max(worst_act, distance_to_segment(forward(kin, to_joints(cfg, rows[i].s.actual, rows[i].j.actual)).tip, seg->second));
    // the tool tip's speed over this cycle
    const Joints p = to_joints(cfg, rows[i - 1].s.commanded, rows[i - 1].j.commanded);
    const double v = norm(forward(kin, q).tip - forward(kin, p).tip) / dt;
    const int k = index[ln];
    if (k >= 10 && k <= 350) slowest = std::min(slowest, v);  // away from the start and the stop
    if (k >= 2 && k <= 359 && v < 1e-9) ++still;
  }
  EXPECT_EQ(lines.size(), 360u);
  EXPECT_GT(inner, 1000);
  EXPECT_EQ(still, 0) << "no cycle of the run's inner moves stands still";
  // the joints' velocity steps at the junctions (the table turns 9.5 deg per mm of tip travel, the
  // linear axes swing with it) allow about 7.5 mm/s there, and the ring's 4 blocks of 0.05 mm
  // bound the braking distance: the tip never comes near a stop
  EXPECT_GT(slowest, 0.25 * kFeed / 60.0) << "the tip's slowest speed through the junctions, mm/s";
  EXPECT_LE(worst_v, 1.0 + 1e-9) << "a joint over its velocity limit (share of it)";
  EXPECT_LE(worst_a, 1.0 + 1e-3) << "a joint over its acceleration limit (share of it)";
  EXPECT_LT(worst_cmd, 1e-4) << "commanded tip off the line, mm";
  EXPECT_LT(worst_act, 0.005) << "measured tip off the line, mm";
  std::printf("[ figures ] dense TCP run: %d cycles from the first to the last move (%.3f s), slowest tip %.3f mm/s at the "
              "inner junctions, tip off the line %.3g um commanded / %.3g um measured, worst joint %.5f of its velocity "
              "and %.5f of its acceleration limit (on the helix's moves %.3f and %.3f)\n",
              last_row - first_row + 1, (last_row - first_row + 1) * dt, slowest, worst_cmd * 1e3, worst_act * 1e3, worst_v,
              worst_a, helix_v, helix_a);
}

// The program's X Y Z words times `factor` (A, C and F kept).
std::string scale_xyz(const std::string& text, double factor) {
  std::string out;
  for (std::size_t i = 0; i < text.size();) {
    const char ch = text[i];
    if (ch == '(') {  // comments as they are
      const std::size_t close = text.find(')', i);
      out += text.substr(i, close - i + 1);
      i = close + 1;
      continue;
    }
    out += ch;
    ++i;
    if (ch != 'X' && ch != 'Y' && ch != 'Z') continue;
    std::size_t used = 0;
    const double v = std::stod(text.substr(i), &used);
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.4f", v * factor);
    out += buf;
    i += used;
  }
  return out;
}

double fit_scale(const std::string& check_out) {
  const std::string key = "transform: machine = ";
  const auto at = check_out.find(key);
  return at == std::string::npos ? -1.0 : std::stod(check_out.substr(at + key.size()));
}

// --fit of a tool-centre-point program: the impeller blade (as committed) three times its size leaves the joints'
// travel as written; --fit finds a scale under 1 (the angles kept) with which the whole program
// passes the preflight, every joint at every sample of every TCP move inside its travel. The blade
// as written fits (scale 1). A 5-axis program with TCP off is refused at the first line that moves
// the linear axes while a joint is turned.
TEST(FiveAxisRun, FitScalesATcpProgramUntilEveryJointIsInsideItsTravel) {
  const std::string dir = make_temp_dir("five-fit");
  const std::string config = write_five_axis_config(dir, "five-fit");
  // the example as committed turns C first, with TCP off, to where its first move leaves the pole
  const std::string blade = read_file(source_dir() + "/examples/5axis/impeller-blade.ngc");
  ASSERT_NE(blade.find("G0 C-12.5000"), std::string::npos);
  const std::string big = dir + "/big.ngc";
  std::ofstream(big) << scale_xyz(blade, 3.0);
  const ProcessResult as_written = run_process({pcnc_exe(), "check", big, "--config", config}, 120);
  EXPECT_EQ(as_written.exit_code, 2) << as_written.out << as_written.err;
  EXPECT_NE(as_written.err.find("along the TCP move"), std::string::npos) << as_written.err;

  const ProcessResult fit = run_process({pcnc_exe(), "check", big, "--config", config, "--fit"}, 120);
  EXPECT_EQ(fit.exit_code, 0) << fit.out << fit.err;
  const double s = fit_scale(fit.out);
  EXPECT_GT(s, 0.1) << fit.out;
  EXPECT_LT(s, 0.9) << fit.out;

  const std::string small = dir + "/blade.ngc";
  std::ofstream(small) << blade;
  const ProcessResult fits = run_process({pcnc_exe(), "check", small, "--config", config, "--fit"}, 120);
  EXPECT_EQ(fits.exit_code, 0) << fits.out << fits.err;
  EXPECT_DOUBLE_EQ(fit_scale(fits.out), 1.0) << fits.out;

  const std::string off = dir + "/off.ngc";
  std::ofstream(off) << "G21 G90 G94\nG0 X0 Y0 Z-5\nG1 A30 F1800\nG1 X5 C90 F300\nM2\n";
  const ProcessResult refused = run_process({pcnc_exe(), "check", off, "--config", config, "--fit"}, 120);
  EXPECT_EQ(refused.exit_code, 2) << refused.out << refused.err;
  // line 3 only turns A (the linear axes stand still: kept, like "turn C first"); line 4 moves X
  // while C turns with TCP off
  EXPECT_NE(refused.err.find("off.ngc:4: error: --fit: line 4: a move with tool-centre-point control off"), std::string::npos)
      << refused.err;
  EXPECT_NE(refused.err.find("joint values do not scale"), std::string::npos) << refused.err;
  std::printf("[ figures ] --fit of the impeller blade x3: scale %.6f\n", s);
}

// A 3-axis machine refuses A/B/C words and M428 with the line and column.
TEST(FiveAxisRun, AThreeAxisMachineRefusesRotaryWords) {
  const std::string dir = make_temp_dir("five-3ax");
  const std::string path = dir + "/a.ngc";
  std::ofstream(path) << "G21 G90\nG1 X1 A30 F100\nM2\n";
  const ProcessResult r = run_process({pcnc_exe(), "check", path, "--config", default_config()}, 120);
  EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
  EXPECT_NE(r.err.find("a.ngc:2:7: error: the machine has no A axis"), std::string::npos) << r.err;
  std::ofstream(path) << "G21 G90\nM428\nM2\n";
  const ProcessResult m = run_process({pcnc_exe(), "check", path, "--config", default_config()}, 120);
  EXPECT_EQ(m.exit_code, 2) << m.out << m.err;
  EXPECT_NE(m.err.find("a.ngc:2:1: error: M428: tool-centre-point control needs rotary joints"), std::string::npos) << m.err;
}

}  // namespace
}  // namespace pcnc::test
