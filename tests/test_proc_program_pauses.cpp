// test_proc_program_pauses.cpp — a program's M0/M1 under `pcnc run`, which serves no control
// socket to resume from (docs/gcode.md, "Pauses under `pcnc run`"): --pauses continue comes to rest
// there and goes on, exactly as a dwell of 0 s would; --pauses ask waits at rest for Enter on
// stdin and stops the program there when no one answers or a stop signal comes. Both real
// processes run.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/stat.h>

#include <chrono>
#include <fstream>
#include <thread>
#include <nlohmann/json.hpp>
#include <regex>

#include "subprocess.hpp"
#include "test_paths.hpp"
#include "service_procs.hpp"
#include "text_lines.hpp"

namespace pcnc::test {
namespace {


// Three moves with `stop1` on line 3 and `stop2` on line 5 between them.
std::string write_stop_program(const std::string& dir, const std::string& name, const std::string& stop1,
                          const std::string& stop2) {
  const std::string path = dir + "/" + name;
  std::ofstream(path) << "G21 G90 G54\nG1 X1 Y1 F600\n" << stop1 << "\nG1 X2 Y1\n" << stop2 << "\nG1 X3 Y2\nG1 X4 Y2\nM30\n";
  return path;
}


// "  commanded         X15.5000 Y14.5000 Z25.0000 mm" -> X and Y
std::pair<double, double> commanded_xy(const std::string& report) {
  std::smatch m;
  if (!std::regex_search(report, m, std::regex(R"(commanded\s+X(-?[0-9.]+) Y(-?[0-9.]+))"))) return {-1e9, -1e9};
  return {std::stod(m[1]), std::stod(m[2])};
}

TEST(ProgramPauses, ContinueComesToRestAndGoesOnLikeADwellOfZeroSeconds) {
  const std::string dir = make_temp_dir("pauses");
  const std::string config = write_test_config(dir, "pauses");
  const std::string paused = write_stop_program(dir, "paused.ngc", "M0", "M1");
  const std::string dwelled = write_stop_program(dir, "dwelled.ngc", "G4 P0", "G4 P0");
  auto run = [&](const std::string& prog, const std::string& summary, std::vector<std::string> extra) {
    std::vector<std::string> argv{pcnc_exe(), "run", prog, "--clock", "virtual", "--config", config, "--summary", summary};
    argv.insert(argv.end(), extra.begin(), extra.end());
    return run_process(argv, 120);
  };
  // without --pauses: under the virtual clock the pauses are gone on from (no hang)
  const ProcessResult p = run(paused, dir + "/p.json", {});
  ASSERT_EQ(p.exit_code, 0) << p.out << p.err;
  EXPECT_TRUE(has(p.out, "result            completed")) << p.out;
  EXPECT_TRUE(has(p.out, "pauses            2 (M0/M1 on lines 3, 5): the machine came to rest there and went on")) << p.out;
  const ProcessResult d = run(dwelled, dir + "/d.json", {"--pauses", "continue"});
  ASSERT_EQ(d.exit_code, 0) << d.out << d.err;
  EXPECT_FALSE(has(d.out, "pauses  ")) << d.out;

  const nlohmann::json ps = nlohmann::json::parse(read_file(dir + "/p.json"));
  const nlohmann::json ds = nlohmann::json::parse(read_file(dir + "/d.json"));
  EXPECT_EQ(ps["job"]["pauses"]["count"], 2);
  EXPECT_EQ(ps["job"]["pauses"]["mode"], "continue");
  EXPECT_EQ(ps["job"]["pauses"]["lines"], nlohmann::json::array({3, 5}));
  EXPECT_FALSE(ds["job"].contains("pauses"));
  // the same stops at rest, the same cycles: the machine times are equal to the cycle
  EXPECT_EQ(ps["status"]["program_time_s"].get<double>(), ds["status"]["program_time_s"].get<double>());
  EXPECT_EQ(ps["status"]["blocks_done"], ds["status"]["blocks_done"]);
  EXPECT_EQ(commanded_xy(p.out), commanded_xy(d.out));
}

TEST(ProgramPauses, AskWaitsForEnterAndStopsThereWhenNoOneAnswers) {
  const std::string dir = make_temp_dir("ask");
  const std::string config = write_test_config(dir, "ask");
  const std::string prog = write_stop_program(dir, "ask.ngc", "M0", "M1");
  auto run_with_stdin = [&](const std::string& answers) {
    const std::string in = dir + "/stdin.txt";
    std::ofstream(in) << answers;
    return run_process({"/bin/sh", "-c",
                        "exec \"$0\" run \"$1\" --clock virtual --config \"$2\" --pauses ask < \"$3\"", pcnc_exe(), prog,
                        config, in},
                       120);
  };
  // two Enters: both pauses resumed, the program completes
  const ProcessResult both = run_with_stdin("\n\n");
  ASSERT_EQ(both.exit_code, 0) << both.out << both.err;
  EXPECT_TRUE(has(both.out, "result            completed")) << both.out;
  EXPECT_TRUE(has(both.err, "paused at line 3 (M0)")) << both.err;
  EXPECT_TRUE(has(both.err, "paused at line 5 (M1, optional stop)")) << both.err;
  EXPECT_TRUE(has(both.out, "2 (M0/M1 on lines 3, 5): the machine waited at rest for the operator")) << both.out;
  const auto end = commanded_xy(both.out);
  EXPECT_NEAR(end.first, 12.5 + 4.0, 1e-4);

  // one Enter, then stdin ends: the M1 on line 5 is not resumed; the machine stays where it
  // stood there (program X2 Y1), the run ends "stopped" with exit status 1
  const ProcessResult one = run_with_stdin("\n");
  EXPECT_EQ(one.exit_code, 1) << one.out << one.err;
  EXPECT_TRUE(has(one.out, "result            stopped: stopped at the M1 on line 5: the operator did not resume")) << one.out;
  const auto at = commanded_xy(one.out);
  EXPECT_NEAR(at.first, 12.5 + 2.0, 1e-4);
  EXPECT_NEAR(at.second, 12.5 + 1.0, 1e-4);
}

TEST(ProgramPauses, AStopSignalWhileTheOperatorIsAskedStopsTheProgramAtThePause) {
  const std::string dir = make_temp_dir("asksig");
  const std::string config = write_test_config(dir, "asksig");
  const std::string prog = write_stop_program(dir, "asksig.ngc", "M0", "M1");
  // stdin: a FIFO that the shell also holds open for writing, so it never ends and never speaks
  const std::string fifo = dir + "/stdin";
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  BackgroundProcess run = start_process(
      {"/bin/sh", "-c", "exec 3<>\"$4\"; exec \"$0\" run \"$1\" --clock virtual --config \"$2\" --pauses \"$3\" < \"$4\"",
       pcnc_exe(), prog, config, "ask", fifo},
      dir + "/pcnc");
  Reaped reaped{run};
  bool asked = false;
  for (int i = 0; i < 600 && !asked; ++i) {  // up to 60 s
    asked = has(run.err(), "paused at line 3 (M0)");
    if (!asked) std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  ASSERT_TRUE(asked) << run.err();
  kill(run.pid, SIGTERM);
  const int code = wait_for(run, 60);
  EXPECT_EQ(code, 128 + SIGTERM) << run.out() << run.err();
  EXPECT_TRUE(has(run.out(), "result            interrupted: stopped along the path")) << run.out();
  const auto at = commanded_xy(run.out());
  EXPECT_NEAR(at.first, 12.5 + 1.0, 1e-4) << "the machine stays at the M0 on line 3";
  EXPECT_NEAR(at.second, 12.5 + 1.0, 1e-4);
}

}  // namespace
}  // namespace pcnc::test
