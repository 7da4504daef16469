// test_proc_five_axis.cpp — a 5-axis program with tool-centre-point control through the real
// pcnc-host and pcnc-rt (virtual clock) on configs/desktop-5axis.toml (XYZAC trunnion), checked
// from the trace alone: the joints' columns are there, the tool tip (forward kinematics of the
// commanded and of the measured joints, tool length from the tool table) stays on the programmed
// line of every TCP move, and no joint leaves its travel or exceeds its velocity on any cycle.
// The program: a tilted line leaving the pole of C, a line through the singularity (A +20 to
// -20 at constant C), a move turning C with the tool tilted, and a tilted helix whose C follows
// the angle. A second program with TCP off checks the joints' linear interpolation.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

#include "config/config.hpp"
#include "config/joint_map.hpp"
#include "geometry/kinematics.hpp"
#include "ipc/trace_format.hpp"
#include "five_axis_trace.hpp"

namespace pcnc::test {
namespace {

std::string pcnc_exe() { return bin_dir() + "/tools/pcnc"; }

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
const Vec3 kG54{12.5, 12.5, 25.0};

TEST(FiveAxisRun, TcpProgramKeepsTheTipOnTheLineAndTheJointsWithinTheirLimits) {
  const std::string dir = make_temp_dir("five");
  const std::string config = write_five_axis_config(dir, "five");
  const MachineConfig cfg = load_config(config);
  ASSERT_EQ(cfg.kinematics.kind, KinematicsKind::kTableTable);

  // the program, and the tip's programmed segment per source line (program point + G54)
  std::ostringstream prog;
  std::map<int, Segment> lines;
  int n = 0;
  auto line = [&](const std::string& text) {
    prog << text << "\n";
    return ++n;
  };
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
  std::ofstream(path) << prog.str();

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
