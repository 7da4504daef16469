// test_proc_run.cpp — `pcnc run` end to end with the real executables: both processes start,
// the bundled example runs to its last point, bad G-code moves nothing, and the launcher
// reports a process that dies or fails to start and forwards SIGTERM to both.
#include <gtest/gtest.h>
#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <fstream>
#include <regex>
#include <thread>

#include "ipc/segment.hpp"
#include "subprocess.hpp"
#include "test_paths.hpp"
#include "service_procs.hpp"

namespace pcnc::test {
namespace {


// "  final position    machine X12.5000 Y12.5000 Z24.0000 mm; ..." -> the three numbers
bool parse_position(const std::string& report, const std::string& label, Vec3& out) {
  const std::regex re(label + R"(\s+X(-?[0-9.]+) Y(-?[0-9.]+) Z(-?[0-9.]+))");
  std::smatch m;
  if (!std::regex_search(report, m, re)) return false;
  for (int i = 0; i < 3; ++i) out[i] = std::stod(m[i + 1]);
  return true;
}

// A program that keeps the machine busy for many seconds in real time.
std::string write_slow_program(const std::string& dir) {
  const std::string path = dir + "/slow.ngc";
  std::ofstream f(path);
  f << "G21 G90 G54\nG01 X0 Y0 F60\n";
  for (int i = 0; i < 40; ++i) f << "G01 X" << (i % 2 ? -5 : 5) << " Y" << (i % 4 < 2 ? 3 : -3) << "\n";
  f << "M30\n";
  return path;
}

// Waits for the rt of `tag` to create its segment; returns its pid.
int wait_for_rt_pid(const std::string& tag) {
  for (int i = 0; i < 500; ++i) {
    try {
      HostSegment seg(test_shm_name(tag));
      const int pid = seg.shm().header.rt_pid.load();
      if (pid > 0) return pid;
    } catch (const SegmentError&) {
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return -1;
}

TEST(PcncRun, BundledExampleRunsToItsLastPoint) {
  const std::string dir = make_temp_dir("run");
  const std::string config = write_test_config(dir, "run");
  // --tolerance 0: the seed's rule, as the demo's comments describe it
  const ProcessResult r = run_process(
      {pcnc_exe(), "run", source_dir() + "/examples/demo.ngc", "--clock", "virtual", "--config", config, "--tolerance", "0"},
      300);
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("result            completed"), std::string::npos) << r.out;
  // what its comments and the README say: under M21 the circle (2) and the contour's 18
  // segments turning by 5 degrees flow through; the square's corners and the rapids stop
  EXPECT_NE(r.out.find("junctions         20 passed without stopping, 11 stops"), std::string::npos) << r.out;
  // with the config's path tolerance (0.005 mm) the contour's 18 segments (and the move onto it) are one curve
  const ProcessResult smooth = run_process(
      {pcnc_exe(), "run", source_dir() + "/examples/demo.ngc", "--clock", "virtual", "--config", config}, 300);
  ASSERT_EQ(smooth.exit_code, 0) << smooth.out << smooth.err;
  EXPECT_NE(smooth.out.find("smoothing         tolerance 5.0 um: 19 G1 moves smoothed into 1 blocks"), std::string::npos)
      << smooth.out;
  // demo.ngc ends at program X0 Y0 Z-1; G54 is (12.5, 12.5, 25) on the default machine.
  const Vec3 expected{12.5, 12.5, 24.0};
  Vec3 commanded{}, actual{};
  ASSERT_TRUE(parse_position(r.out, "commanded", commanded)) << r.out;
  ASSERT_TRUE(parse_position(r.out, "final position    machine", actual)) << r.out;
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(commanded[i], expected[i], 1e-4) << "axis " << axis_name(i);
    EXPECT_NEAR(actual[i], expected[i], 0.002) << "axis " << axis_name(i) << " settles at the last point";
  }
  // the segment is gone after a clean exit
  EXPECT_THROW(HostSegment seg(test_shm_name("run")), SegmentError);
}

TEST(PcncRun, BadGcodeNamesLineAndColumnAndMovesNothing) {
  const std::string dir = make_temp_dir("bad");
  const std::string config = write_test_config(dir, "bad");
  const std::string prog = dir + "/bad.ngc";
  std::ofstream(prog) << "G21 G90 G54\nG01 X1 Y1 F300\nG01 X2 Q7\nM30\n";
  const ProcessResult r = run_process({pcnc_exe(), "run", prog, "--clock", "virtual", "--config", config}, 120);
  EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
  EXPECT_NE(r.err.find("bad.ngc:3:"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("nothing was moved"), std::string::npos) << r.err;
  EXPECT_EQ(r.out.find("run report"), std::string::npos) << "no run happened";
}

// pcnc-rt that starts and fails at once: its segment is held by another running pcnc-rt.
// (A bad config never gets this far: pcnc run refuses it itself with exit 2, test_proc_exit_codes.)
TEST(PcncRun, RtThatCannotStartIsReported) {
  const std::string dir = make_temp_dir("nort");
  const std::string config = write_test_config(dir, "nort");
  BackgroundProcess holder =
      start_process({bin_dir() + "/rt/pcnc-rt", "--clock", "virtual", "--config", config}, dir + "/holder");
  Reaped reaped{holder};
  ASSERT_GT(wait_for_rt_pid("nort"), 0) << holder.err();
  const ProcessResult r =
      run_process({pcnc_exe(), "run", source_dir() + "/examples/demo.ngc", "--clock", "virtual", "--config", config}, 60);
  EXPECT_EQ(r.exit_code, 3) << r.out << r.err;
  EXPECT_NE(r.err.find("pcnc-rt failed to start"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("in use by a running pcnc-rt"), std::string::npos) << "the rt's own message names the cause: " << r.err;
  kill(holder.pid, SIGTERM);
  EXPECT_EQ(wait_for(holder, 30), 0) << holder.err();
}

TEST(PcncRun, KilledRtIsReportedAndTheHostStopped) {
  const std::string dir = make_temp_dir("kill");
  const std::string config = write_test_config(dir, "kill");
  BackgroundProcess run = start_process({pcnc_exe(), "run", write_slow_program(dir), "--clock", "real", "--config", config},
                                        dir + "/pcnc");
  const int rt_pid = wait_for_rt_pid("kill");
  ASSERT_GT(rt_pid, 0) << run.err();
  std::this_thread::sleep_for(std::chrono::milliseconds(500));  // let the program start moving
  kill(rt_pid, SIGKILL);
  const int code = run.wait(30);
  EXPECT_EQ(code, 3) << run.out() << run.err();
  EXPECT_NE(run.err().find("pcnc-rt was killed by signal 9"), std::string::npos) << run.err();
}

TEST(PcncRun, SigtermReachesBothProcesses) {
  const std::string dir = make_temp_dir("term");
  const std::string config = write_test_config(dir, "term");
  BackgroundProcess run = start_process({pcnc_exe(), "run", write_slow_program(dir), "--clock", "real", "--config", config},
                                        dir + "/pcnc");
  ASSERT_GT(wait_for_rt_pid("term"), 0) << run.err();
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  kill(run.pid, SIGTERM);
  const int code = run.wait(30);
  EXPECT_EQ(code, 128 + SIGTERM) << run.out() << run.err();
  // the rt removed its segment on the way out
  EXPECT_THROW(HostSegment seg(test_shm_name("term")), SegmentError);
}

TEST(PcncRun, HelpTellsTheCommands) {
  for (const std::string& exe : {bin_dir() + "/rt/pcnc-rt", bin_dir() + "/host/pcnc-host"}) {
    const ProcessResult r = run_process({exe, "--help"}, 30);
    EXPECT_EQ(r.exit_code, 0) << exe;
    EXPECT_NE(r.out.find("--config"), std::string::npos) << exe << ": " << r.out;
    EXPECT_NE(r.out.find(exe.find("pcnc-rt") != std::string::npos ? "--clock" : "--run"), std::string::npos) << r.out;
  }
  const ProcessResult top = run_process({pcnc_exe(), "--help"}, 30);
  EXPECT_EQ(top.exit_code, 0);
  for (const char* sub : {"run", "check"}) EXPECT_NE(top.out.find(sub), std::string::npos) << sub << ": " << top.out;
  const ProcessResult r = run_process({pcnc_exe(), "run", "--help"}, 30);
  for (const char* opt : {"--clock", "--contouring", "--offset", "--fit", "--trace", "--report", "--quiet", "--verbose"}) {
    EXPECT_NE(r.out.find(opt), std::string::npos) << opt;
  }
}

}  // namespace
}  // namespace pcnc::test
