// test_proc_resume_nurbs.cpp — resume inside a NURBS block with the real processes: a
// program with a long slow G5.2 curve runs on pcnc-rt (--clock virtual) and pcnc-host
// --serve; the host is killed (SIGKILL) while the machine is inside the curve; the rt holds
// on the curve (HOST_LOST); a new host resumes; the program completes at its last point, and
// the rt's trace shows no jump in the commanded position and the curve's points on it.
#include <gtest/gtest.h>
#include <signal.h>

#include <chrono>
#include <cmath>
#include <fstream>
#include <iostream>
#include <sstream>
#include <thread>

#include "config/config.hpp"
#include "ipc/segment.hpp"
#include "service_procs.hpp"
#include "test_paths.hpp"

namespace pcnc::test {
namespace {

using namespace std::chrono_literals;



// Lines 1-3 lead in; the curve is lines 4-8 (G5.2 .. G5.3); line 9 leads out.
constexpr int kCurveFirst = 4, kNurbsLast = 9;
const char* kProgram =
    "G21 G90 G17 G54\n"
    "G00 X-8 Y0 Z-1\n"
    "G01 X-7 F15\n"
    "G5.2 X-6 Y7 P1 L4\n"
    "X-2 Y-7 P1\n"
    "X2 Y7 P2\n"
    "X6 Y-7 P1\n"
    "X8 Y0 P1\n"
    "G5.3\n"
    "G01 X9\n"
    "M30\n";

// Runs `program` (its curve on lines kCurveFirst..curve_last, ending at X9 Y0 Z-1), kills the
// host inside the curve, resumes with a new host and checks the run completes without a jump.
void kill_host_inside_the_curve_and_resume(const std::string& tag, const char* program, int curve_last) {
  const int kCurveLast = curve_last;
  ServicePair p(tag);
  const std::string trace = p.dir() + "/trace.csv";
  ASSERT_TRUE(p.start("virtual", {"--trace", trace})) << p.host_log();
  const MachineConfig m = load_config(default_config());
  const std::string prog = write_program(p.dir(), "curve.ngc", program);
  const json run = p.call("run", {{"file", prog}});
  ASSERT_TRUE(run.contains("result")) << run.dump();
  // Inside the curve, some way along it.
  const json inside = p.wait_status(
      [&](const json& s) {
        // (a status without the rt, or before a job, has no line: read with defaults)
        const int line = s.value("line", 0);
        return s.value("state", "") == "RUNNING" && line >= kCurveFirst && line <= kCurveLast &&
               s.value("program_time_s", 0.0) > 8.0;
      },
      60);
  ASSERT_EQ(inside["state"], "RUNNING") << inside.dump();
  const KillAndResume k = kill_host_and_resume(p);
  ASSERT_EQ(k.error, "");
  ASSERT_GE(k.lost.line, static_cast<std::uint32_t>(kCurveFirst));
  ASSERT_LE(k.lost.line, static_cast<std::uint32_t>(kCurveLast)) << "stopped inside the curve";
  EXPECT_GE(k.reply["result"]["line"].get<int>(), kCurveFirst);
  const json& s = k.final;
  const Vec3 expected{12.5 + 9.0, 12.5, 24.0};
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(pos(s, "commanded", i), expected[i], 1e-6);

  // The trace: no step in the commanded position beyond an axis's max velocity over one
  // period, the hold visible, and the machine inside the curve both before and after it.
  p.kill_rt(SIGTERM);
  std::ifstream in(trace);
  std::string line;
  ASSERT_TRUE(std::getline(in, line)) << trace;
  const double dt = m.cycle_period_s();
  double prev_t = -1.0, prev[3] = {0, 0, 0}, worst = 0.0;
  std::size_t rows = 0, lost_rows = 0, curve_rows_after = 0;
  bool seen_lost = false;
  while (std::getline(in, line)) {
    std::stringstream ss(line);
    std::string f[13];
    for (auto& x : f) std::getline(ss, x, ',');
    const double t = std::stod(f[0]);
    double cmd[3];
    for (int i = 0; i < 3; ++i) cmd[i] = std::stod(f[3 + i]);
    if (f[2] == "HOST_LOST") {
      ++lost_rows;
      seen_lost = true;
    }
    const int ln = std::stoi(f[1]);
    if (seen_lost && f[2] == "RUNNING" && ln >= kCurveFirst && ln <= kCurveLast) ++curve_rows_after;
    if (prev_t >= 0.0 && std::abs(t - prev_t - dt) < 0.25 * dt) {
      for (int i = 0; i < 3; ++i) worst = std::max(worst, std::abs(cmd[i] - prev[i]) / (m.axes[i].max_velocity_mm_s * dt));
    }
    prev_t = t;
    for (int i = 0; i < 3; ++i) prev[i] = cmd[i];
    ++rows;
  }
  EXPECT_GT(rows, 1000u);
  EXPECT_GT(lost_rows, 0u);
  EXPECT_GT(curve_rows_after, 100u) << "the rest of the curve was cut after the resume";
  EXPECT_LE(worst, 1.0 + 1e-6) << "a setpoint step beyond the axis's max velocity: a jump";
  std::cout << "[ figures  ] kill host inside a curve (" << tag << "): trace rows " << rows << ", curve cycles after resume "
            << curve_rows_after << ", max setpoint step " << worst << " x vmax*dt\n";
}

TEST(KillHostInNurbs, ANewHostResumesInsideTheCurveAndTheProgramCompletesWithoutAJump) {
  kill_host_inside_the_curve_and_resume("khost-nurbs", kProgram, kNurbsLast);
}

// A smoothed run (issue 14): 60 short G1 moves under M21 with the desktop mill's path tolerance
// become one curve (host/gcode/smoothing.hpp); a host lost inside it resumes there. Square
// corners follow, each its own block, and the program ends at X9 Y0 as the NURBS one does.
std::string smoothed_program() {
  std::ostringstream o;
  o.precision(4);
  o << std::fixed << "G21 G90 G17 G54 M21\nG00 X-8 Y0 Z-1\nG01 X-7 F15\n";
  for (int i = 1; i <= 60; ++i) {
    const double x = -7.0 + 0.25 * i;
    o << "X" << x << " Y" << 2.0 * std::sin((x + 7.0) * 2.0 * M_PI / 15.0) << "\n";
  }
  // square corners after the curve (not smoothed): more blocks than the ring holds, so that the
  // host is still needed when it is killed inside the curve
  o << "G01 X9 Y0\nY1\nX8\nY0\nX9\nY1\nX8\nY0\nX9\nM30\n";
  return o.str();
}

TEST(KillHostInNurbs, ANewHostResumesInsideASmoothedRun) {
  const std::string program = smoothed_program();
  kill_host_inside_the_curve_and_resume("khost-smooth", program.c_str(), kCurveFirst + 59);
}

}  // namespace
}  // namespace pcnc::test
