// test_report_joints.cpp — the run report of a 5-axis trace: a synthetic trace in the documented
// format (the 3-axis columns, then cmd_a,act_a,ferr_a,cmd_c,act_c,ferr_c in degrees) of one
// tool-centre-point move on desktop-5axis.toml is read and digested: the joint columns are
// found, the joints' following error keeps its peaks, the tool-axis marks lie every N mm on the
// programmed tip line with the programmed (great-circle) axis; the page draws them and plots
// the joints; the same rows without the joint columns digest to the same 3-axis figures and
// give the page without the 5-axis sections, byte for byte. Malformed joint headers and rows
// are refused.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>
#include <vector>

#include <unistd.h>

#include "config/config.hpp"
#include "config/joint_map.hpp"
#include "geometry/axis_slerp.hpp"
#include "geometry/tcp_path.hpp"
#include "report/report_html.hpp"
#include "report/run_outputs.hpp"
#include "report/run_summary.hpp"
#include "report/trace_joints.hpp"
#include "report/trace_reader.hpp"
#include "test_paths.hpp"
#include "test_constants.hpp"

namespace pcnc {
namespace {

namespace fs = std::filesystem;

struct Synthetic {
  Kinematics kin;
  TcpMove move;
  double length = 0.0;
  int rows = 4000;        // 2 s at 2 kHz
  double peak_a = 0.002;  // deg: ferr_a's amplitude
  double peak_c = 0.004;  // deg: ferr_c's one spike
};

Synthetic synthetic() {
  Synthetic s;
  s.kin = load_config(test::source_dir() + "/configs/desktop-5axis.toml").kinematics;
  const Vec3 a0 = forward(s.kin, {0, 0, 0, 10 * kDeg, 0}).axis, a1 = forward(s.kin, {0, 0, 0, 40 * kDeg, 90 * kDeg}).axis;
  s.move = TcpMove{{{10.0, 11.0, 5.0}, a0}, {{14.0, 13.0, 9.0}, a1}};  // 6 mm
  s.length = norm(s.move.end.tip - s.move.start.tip);
  return s;
}

std::string num(double v) {
  char b[40];
  std::snprintf(b, sizeof b, "%.10g", v);
  return b;
}

// Writes the trace: 5 idle rows, the move's rows RUNNING, 5 idle rows; with or without joints.
void write_trace(const Synthetic& s, const std::string& path, bool joints) {
  std::ofstream f(path);
  f << kTraceCsvHeader << (joints ? ",cmd_a,act_a,ferr_a,cmd_c,act_c,ferr_c" : "") << "\n";
  const AxisSlerp axes = make_axis_slerp(s.move.start.axis, s.move.end.axis);
  Joints q{12.5, 12.5, 25.0, 0.0, 0.0};
  auto row = [&](int i, MachineState state, double u) {
    const ToolPose pose = tcp_pose(s.move, axes, u);
    q = inverse(s.kin, pose, q);
    TraceSample r;
    r.t = 1.0 + i * 0.0005;
    r.line = 10;
    r.state = state;
    r.commanded = {q[0], q[1], q[2]};
    r.following_error = {0.001 * std::sin(i * 0.01), -0.0005, 0.0002 * std::cos(i * 0.02)};
    r.actual = r.commanded - r.following_error;
    r.speed = state == MachineState::kRunning ? s.length / 2.0 : 0.0;
    f << trace_csv_row(r);
    if (joints) {
      const double fa = s.peak_a * std::sin(2.0 * std::numbers::pi * i / 1000.0);
      const double fc = i == 2500 ? s.peak_c : 0.001 * std::cos(i * 0.003);
      const double a = q[kTilt] / kDeg, c = q[kRotary] / kDeg;
      f << "," << num(a) << "," << num(a - fa) << "," << num(fa) << "," << num(c) << "," << num(c - fc) << "," << num(fc);
    }
    f << "\n";
  };
  int i = 0;
  for (int k = 0; k < 5; ++k) row(i++, MachineState::kIdle, 0.0);
  for (int k = 0; k < s.rows; ++k) row(i++, MachineState::kRunning, static_cast<double>(k) / (s.rows - 1));
  for (int k = 0; k < 5; ++k) row(i++, MachineState::kIdle, 1.0);
}

DigestOptions options(const Synthetic& s) {
  DigestOptions o;
  o.joints.has_kinematics = true;
  o.joints.kinematics = s.kin;
  o.joints.axis_every_mm = 0.5;
  o.joints.axis_length_mm = 2.0;
  return o;
}

ReportPage page_of(const TraceDigest& d) {
  ReportPage p;
  p.summary.program = "tcp.ngc";
  p.summary.machine = "desktop-5axis";
  p.summary.end = "completed";
  p.summary.min_point = {10, 11, 5};
  p.summary.max_point = {14, 13, 9};
  p.has_trace = true;
  p.trace = d;
  p.view3d = false;  // no three.js needed
  return p;
}

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

struct Files {
  fs::path dir;
  std::string five, three;
  Files() {
    dir = fs::temp_directory_path() / ("pcnc_report_joints_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    five = (dir / "five.csv").string();
    three = (dir / "three.csv").string();
  }
  ~Files() {
    std::error_code ec;
    fs::remove_all(dir, ec);
  }
};

TEST(ReportJoints, TheJointColumnsAreDigested) {
  const Synthetic s = synthetic();
  const Files f;
  write_trace(s, f.five, true);
  const TraceDigest d = digest_trace(f.five, options(s));
  ASSERT_EQ(d.joints.letters, (std::vector<char>{'A', 'C'}));
  EXPECT_EQ(d.program_rows, static_cast<std::uint64_t>(s.rows));
  EXPECT_NEAR(d.joints.ferr_abs_max[0], s.peak_a, 1e-9);
  EXPECT_NEAR(d.joints.ferr_abs_max[1], s.peak_c, 1e-12);
  // the spike survives the buckets
  double hi_c = 0.0;
  for (const JointBucket& b : d.joints.buckets) hi_c = std::max(hi_c, b.ferr_max[1]);
  EXPECT_NEAR(hi_c, s.peak_c, 1e-12);
  ASSERT_TRUE(d.joints.tool_axis);
  EXPECT_NEAR(d.joints.tip_path_mm, s.length, 1e-6);
  // marks every 0.5 mm of the 6 mm line: 13, each on the programmed line with the programmed axis
  ASSERT_EQ(d.joints.marks.size(), 13u);
  const AxisSlerp axes = make_axis_slerp(s.move.start.axis, s.move.end.axis);
  for (std::size_t k = 0; k < d.joints.marks.size(); ++k) {
    const ToolAxisMark& m = d.joints.marks[k];
    EXPECT_NEAR(m.s_mm, 0.5 * k, 2e-3) << k;  // a row is 1.5 µm of path
    const double u = m.s_mm / s.length;
    const ToolPose want = tcp_pose(s.move, axes, u);
    EXPECT_LT(norm(m.tip - want.tip), 1e-6) << k;
    EXPECT_LT(norm(m.axis - want.axis), 1e-7) << k;
  }
  // the tip path runs from the start to the end of the line
  ASSERT_GE(d.joints.tip_path.size(), 2u);
  EXPECT_LT(norm(d.joints.tip_path.front() - s.move.start.tip), 1e-6);
  EXPECT_LT(norm(d.joints.tip_path.back() - s.move.end.tip), 1e-6);
}

TEST(ReportJoints, ThePageDrawsTheToolAxisAndPlotsTheJoints) {
  const Synthetic s = synthetic();
  const Files f;
  write_trace(s, f.five, true);
  const std::string html = render_report_html(page_of(digest_trace(f.five, options(s))));
  // the figure: PCNC_REPORT_JOINTS_OUT=page.html keeps the page (examples/5axis/README.md)
  if (const char* out = std::getenv("PCNC_REPORT_JOINTS_OUT")) std::ofstream(out) << html;
  EXPECT_EQ(count(html, "id=\"tool-axis-view\""), 1u);
  EXPECT_EQ(count(html, "<line class=\"tool-axis\""), 13u);
  EXPECT_EQ(count(html, "<polyline class=\"tip-path\""), 1u);
  EXPECT_EQ(count(html, "id=\"joint-ferr\""), 1u);
  EXPECT_NE(html.find("joint-ferr-plot"), std::string::npos);
  EXPECT_NE(html.find("A 2.00 m°"), std::string::npos);  // the largest joint errors, stated
  EXPECT_NE(html.find("C 4.00 m°"), std::string::npos);
}

TEST(ReportJoints, AThreeAxisTraceGivesTheSameDigestAndThePageWithoutTheJoints) {
  const Synthetic s = synthetic();
  const Files f;
  write_trace(s, f.five, true);
  write_trace(s, f.three, false);
  const TraceDigest five = digest_trace(f.five, options(s));
  const TraceDigest three = digest_trace(f.three, options(s));
  EXPECT_TRUE(three.joints.letters.empty());
  EXPECT_TRUE(three.joints.marks.empty());
  EXPECT_EQ(three.rows, five.rows);
  EXPECT_EQ(three.program_rows, five.program_rows);
  EXPECT_EQ(three.buckets.size(), five.buckets.size());
  EXPECT_EQ(three.path.size(), five.path.size());
  EXPECT_EQ(three.ferr_abs_max, five.ferr_abs_max);
  const std::string html3 = render_report_html(page_of(three));
  std::string html5 = render_report_html(page_of(five));
  EXPECT_EQ(html3.find("tool-axis"), std::string::npos);
  EXPECT_EQ(html3.find("joint-ferr"), std::string::npos);
  // cut the 5-axis sections out: what is left is the 3-axis page, byte for byte
  const std::size_t from = html5.find("<section class=\"card dark\" id=\"tool-axis\">");
  const std::size_t to = html5.find("<footer>");
  ASSERT_NE(from, std::string::npos);
  ASSERT_NE(to, std::string::npos);
  html5.erase(from, to - from);
  EXPECT_EQ(html5, html3);
}

// Under TCP the machine runs the tool tip with the tool table's length (G43.4 H), not the
// config's (0): the run's summary records the TCP blocks' tool length, and the report page built
// from the summary and the trace (load_report_page, as `pcnc run --report` builds it) draws the
// tip from the commanded joints with it. A trace whose joints carry a 20 mm tool along a line
// gives marks on that line with the recorded length, and 5 mm and more off it with 0.
TEST(ReportJoints, TheToolAxisViewUsesTheToolLengthTheProgramRanWith) {
  const std::string config_path = test::source_dir() + "/configs/desktop-5axis.toml";
  Synthetic s = synthetic();
  s.kin = kinematics_with_tool(load_config(config_path), 20.0);
  const Files f;
  write_trace(s, f.five, true);
  RunSummary summary;
  summary.program = "tcp.ngc";
  summary.config_path = config_path;
  summary.min_point = {10, 11, 5};
  summary.max_point = {14, 13, 9};
  const std::string summary_path = (f.dir / "summary.json").string();
  // the largest distance of a mark's tip from the programmed line
  auto off_line = [&](double tool_length) {
    summary.tcp_tool_length_mm = tool_length;
    write_run_summary(summary, summary_path);
    const ReportPage page = load_report_page(summary_path, f.five);
    EXPECT_TRUE(page.trace.joints.tool_axis);
    EXPECT_GT(page.trace.joints.marks.size(), 10u);
    double worst = 0.0;
    const Vec3 d = normalized(s.move.end.tip - s.move.start.tip);
    for (const ToolAxisMark& m : page.trace.joints.marks) {
      const Vec3 r = m.tip - s.move.start.tip;
      worst = std::max(worst, norm(r - dot(r, d) * d));
    }
    return worst;
  };
  EXPECT_LT(off_line(20.0), 1e-6);
  EXPECT_GT(off_line(0.0), 5.0);  // what the view drew before: the gauge point, not the tip
  // the summary keeps the length (and an older summary without it reads as 0)
  summary.tcp_tool_length_mm = 20.0;
  EXPECT_EQ(run_summary_from_json(to_json(summary)).tcp_tool_length_mm, 20.0);
  nlohmann::json j = to_json(summary);
  j.at("check").erase("tcp_tool_length_mm");
  EXPECT_EQ(run_summary_from_json(j).tcp_tool_length_mm, 0.0);
}

TEST(ReportJoints, MalformedJointColumnsAreRefused) {
  std::vector<char> l;
  const std::string base = kTraceCsvHeader;
  EXPECT_TRUE(parse_trace_joint_header(base, l));
  EXPECT_TRUE(l.empty());
  EXPECT_TRUE(parse_trace_joint_header(base + ",cmd_b,act_b,ferr_b", l));
  EXPECT_EQ(l, (std::vector<char>{'B'}));
  EXPECT_FALSE(parse_trace_joint_header(base + ",cmd_a,act_a", l));
  EXPECT_FALSE(parse_trace_joint_header(base + ",cmd_a,act_c,ferr_a", l));
  EXPECT_FALSE(parse_trace_joint_header(base + ",cmd_a,act_a,ferr_a,cmd_a,act_a,ferr_a", l));
  EXPECT_FALSE(parse_trace_joint_header(base + ",cmd_d,act_d,ferr_d", l));
  std::string_view b;
  TraceJointRow j;
  const std::string row = "0.5,3,RUNNING,1,2,3,1,2,3,0,0,0,4";
  const std::string full = row + ",10.5,10.25,0.25";  // b points into it
  ASSERT_TRUE(split_trace_joint_row(full, 1, b, j));
  EXPECT_EQ(b, row);
  EXPECT_EQ(j.cmd[0], 10.5);
  EXPECT_EQ(j.act[0], 10.25);
  EXPECT_EQ(j.ferr[0], 0.25);
  EXPECT_FALSE(split_trace_joint_row(row + ",10.5,10.25", 1, b, j));
  EXPECT_FALSE(split_trace_joint_row(row + ",10.5,10.25,0.25,1", 1, b, j));
  EXPECT_FALSE(split_trace_joint_row(row + ",10.5,x,0.25", 1, b, j));
  EXPECT_FALSE(split_trace_joint_row(row, 1, b, j));
  // a trace whose rows lack the joint columns its header declares is not read
  const Files f;
  {
    std::ofstream o(f.five);
    o << base << ",cmd_a,act_a,ferr_a\n" << row << "\n";
  }
  EXPECT_THROW(digest_trace(f.five), std::runtime_error);
}

}  // namespace
}  // namespace pcnc
