// test_proc_exit_codes.cpp — the README's exit status table, kept by every command as real
// processes: a bad option, a bad config and a refused program exit 2 (never the argument
// parser's own 105/106/109), --help exits 0 and shows the table, a missing service is 3; the
// files a command will write are checked before anything starts; stdout carries only the
// output asked for, diagnostics go to stderr (--quiet, --verbose).
#include <gtest/gtest.h>
#include <pty.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>
#include <thread>
#include <vector>

#include "ipc/segment.hpp"
#include "service_procs.hpp"
#include "subprocess.hpp"
#include "test_paths.hpp"
#include "text_lines.hpp"

namespace pcnc::test {
namespace {

using Args = std::vector<std::string>;

// Every command, as the words that start it.
std::vector<Args> all_commands() {
  const std::string p = pcnc_exe();
  return {{p},          {p, "run"},  {p, "check"}, {p, "config"}, {p, "config", "check"}, {p, "ctl"}, {p, "ctl", "status"},
          {p, "ctl", "run"}, {p, "serve"}, {p, "soak"}, {p, "nurbs"}, {p, "biarc"}, {p, "ruled"}, {host_exe()}, {rt_exe()}};
}

std::string show(const Args& a) {
  std::string s;
  for (const auto& w : a) s += (s.empty() ? "" : " ") + w;
  return s;
}

Args plus(Args a, const Args& more) {
  a.insert(a.end(), more.begin(), more.end());
  return a;
}


// The shipped config without [axis.z] (everything from its header on).
std::string write_config_without_z(const std::string& dir, const std::string& tag) {
  const std::string path = write_test_config(dir, tag);
  std::string text = read_file(path);
  text.erase(text.find("[axis.z]"));
  std::ofstream(path) << text;
  return path;
}

std::string bad_program(const std::string& dir) {
  return write_program(dir, "bad.ngc", "G21 G90 G54\nG01 X1 Y1 F300\nG01 X2 Q7\nM30\n");
}

TEST(ExitCodes, ABadOptionExits2ForEveryCommand) {
  for (const Args& cmd : all_commands()) {
    const ProcessResult r = run_process(plus(cmd, {"--no-such-option"}), 30);
    EXPECT_EQ(r.exit_code, 2) << show(cmd) << ": " << r.err;
    EXPECT_FALSE(r.err.empty()) << show(cmd) << " says why";
    EXPECT_TRUE(r.out.empty()) << show(cmd) << ": " << r.out;
  }
  // the parser's other errors: a missing argument, a value not allowed, a file that is not there
  for (const Args& a : {Args{pcnc_exe(), "run"}, Args{pcnc_exe(), "run", "/nonexistent/p.ngc"},
                        Args{pcnc_exe(), "run", source_dir() + "/examples/demo.ngc", "--clock", "sometimes"},
                        Args{pcnc_exe(), "run", source_dir() + "/examples/demo.ngc", "--offset", "1,2"},
                        Args{rt_exe(), "--clock", "sometimes"}, Args{host_exe(), "--wait-rt", "soon"}}) {
    EXPECT_EQ(run_process(a, 30).exit_code, 2) << show(a);
  }
}

TEST(ExitCodes, HelpExits0AndShowsTheTableForEveryCommand) {
  for (const Args& cmd : all_commands()) {
    const ProcessResult r = run_process(plus(cmd, {"--help"}), 30);
    EXPECT_EQ(r.exit_code, 0) << show(cmd) << ": " << r.err;
    EXPECT_TRUE(has(r.out, "Exit status")) << show(cmd) << ": " << r.out;
    for (const char* row : {"  0  ", "  1  ", "  2  ", "  3  ", "  128+N  "}) {
      EXPECT_TRUE(has(r.out, row)) << show(cmd) << " lacks the row '" << row << "'";
    }
  }
}

TEST(ExitCodes, ABadConfigExits2BeforeAnythingStarts) {
  const std::string dir = make_temp_dir("xbadcfg");
  const std::string config = write_config_without_z(dir, "xbadcfg");
  const std::string demo = source_dir() + "/examples/demo.ngc";
  const std::vector<Args> cases = {
      {pcnc_exe(), "run", demo, "--clock", "virtual", "--config", config},
      {pcnc_exe(), "check", demo, "--config", config},
      {pcnc_exe(), "config", "check", config},
      {pcnc_exe(), "serve", "--clock", "virtual", "--config", config},
      {pcnc_exe(), "soak", demo, "--minutes", "0", "--config", config},
      {pcnc_exe(), "nurbs", demo, "--config", config},
      {pcnc_exe(), "ctl", "--config", config, "status"},
      {host_exe(), "--config", config, "--serve"},
      {host_exe(), "--config", config, "--run", demo},
      {rt_exe(), "--clock", "virtual", "--config", config},
  };
  for (const Args& a : cases) {
    const ProcessResult r = run_process(a, 60);
    EXPECT_EQ(r.exit_code, 2) << show(a) << ": " << r.err;
    EXPECT_TRUE(has(r.err, "missing section [axis.z]")) << show(a) << ": " << r.err;
    EXPECT_FALSE(has(r.out, "run report")) << show(a);
  }
  // the segment the rt would have created was never made
  EXPECT_THROW(HostSegment seg(test_shm_name("xbadcfg")), SegmentError);
}

// pcnc serve restarts a process that dies, but not a pcnc-host that refused its config (a
// journal directory that is a file): that would only be refused again.
TEST(ExitCodes, AServiceWhoseHostRefusesItsStateDirectoryExits2) {
  const std::string dir = make_temp_dir("xstate");
  const std::string not_a_dir = dir + "/not-a-directory";
  std::ofstream(not_a_dir) << "x";
  const std::string config =
      write_test_config(dir, "xstate", {{"state_dir = \"" + dir + "/state\"", "state_dir = \"" + not_a_dir + "\""}});
  const ProcessResult r = run_process({pcnc_exe(), "serve", "--clock", "virtual", "--config", config}, 60);
  EXPECT_FALSE(r.timed_out);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_TRUE(has(r.err, "not-a-directory")) << r.err;
  EXPECT_FALSE(has(r.err, "starting pcnc-host again")) << r.err;
}

TEST(ExitCodes, ARefusedProgramExits2) {
  const std::string dir = make_temp_dir("xprog");
  const std::string config = write_test_config(dir, "xprog");
  const std::string bad = bad_program(dir);
  for (const Args& a : {Args{pcnc_exe(), "check", bad, "--config", config},
                        Args{pcnc_exe(), "run", bad, "--clock", "virtual", "--config", config},
                        Args{pcnc_exe(), "nurbs", bad, "--config", config}}) {
    const ProcessResult r = run_process(a, 60);
    EXPECT_EQ(r.exit_code, 2) << show(a) << ": " << r.out << r.err;
    EXPECT_FALSE(has(r.out, "run report")) << show(a);
  }
}

TEST(ExitCodes, ABadToolTableExits2WithItsLineForEveryCommandThatTakesOne) {
  const std::string dir = make_temp_dir("xtools");
  const std::string config = write_test_config(dir, "xtools");
  const std::string table = dir + "/bad.tbl";
  std::ofstream(table) << "T1 P1 Z10 D6\nT2 P2 Z5 Q12\n";
  const std::string program = write_program(dir, "ok.ngc", "G21 G90 G54\nT1 M6 G43\nG0 Z-1\nM30\n");
  for (const Args& a : {Args{pcnc_exe(), "check", program, "--config", config, "--tool-table", table},
                        Args{pcnc_exe(), "run", program, "--clock", "virtual", "--config", config, "--tool-table", table},
                        Args{host_exe(), "--serve", "--config", config, "--tool-table", table}}) {
    const ProcessResult r = run_process(a, 60);
    EXPECT_EQ(r.exit_code, 2) << show(a) << ": " << r.out << r.err;
    EXPECT_TRUE(has(r.err, "bad.tbl:2:10")) << show(a) << ": " << r.err;
  }
}

TEST(ExitCodes, ARefusedProgramExits2FromTheHostAndTheService) {
  ServicePair pair("xsvc");
  ASSERT_TRUE(pair.start("virtual")) << pair.host_log() << pair.rt_log();
  const std::string bad = bad_program(pair.dir());
  const ProcessResult ctl = run_process({pcnc_exe(), "ctl", "--config", pair.config(), "run", bad}, 60);
  EXPECT_EQ(ctl.exit_code, 2) << ctl.out << ctl.err;
  EXPECT_TRUE(has(ctl.err, "bad.ngc:3:")) << ctl.err;
  const ProcessResult bad_request = run_process({pcnc_exe(), "ctl", "--config", pair.config(), "override", "500"}, 60);
  EXPECT_EQ(bad_request.exit_code, 2) << "a parameter out of range: " << bad_request.err;
  pair.kill_host(SIGTERM);  // frees the ring for a pcnc-host --run of its own
  const ProcessResult host = run_process({host_exe(), "--config", pair.config(), "--run", bad}, 60);
  EXPECT_EQ(host.exit_code, 2) << host.out << host.err;
  EXPECT_TRUE(has(host.err, "nothing was moved")) << host.err;
}

// Ctrl-C while `pcnc run` checks a long program (nine million lines run in a loop) ends the
// check there, not after it: the error names the line reached, nothing moves, exit 130.
TEST(ExitCodes, CtrlCDuringTheCheckOfALongProgramExits130AndMovesNothing) {
  const std::string dir = make_temp_dir("xcheck");
  const std::string config = write_test_config(dir, "xcheck");
  const std::string program = loop_program(dir, "long.ngc", 3000000);
  const std::string summary = dir + "/s.json";
  BackgroundProcess run =
      start_process({pcnc_exe(), "run", program, "--clock", "virtual", "--config", config, "--summary", summary}, dir + "/run");
  Reaped reaped{run};
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  ASSERT_EQ(kill(run.pid, SIGINT), 0);
  const int code = wait_for(run, 60);
  EXPECT_EQ(code, 130) << run.err();
  EXPECT_TRUE(has(run.err(), "long.ngc:")) << run.err();
  EXPECT_TRUE(has(run.err(), ": error: the check was interrupted by a stop signal before the end of the program")) << run.err();
  EXPECT_TRUE(has(run.err(), "interrupted; nothing was moved")) << run.err();
  EXPECT_FALSE(has(run.out(), "run report")) << run.out();
  EXPECT_FALSE(std::filesystem::exists(summary)) << "no run, no summary";
}

TEST(ExitCodes, NoServiceOrNoRtExits3) {
  const std::string dir = make_temp_dir("xnone");
  const std::string config = write_test_config(dir, "xnone");
  const ProcessResult ctl = run_process({pcnc_exe(), "ctl", "--config", config, "status"}, 30);
  EXPECT_EQ(ctl.exit_code, 3) << ctl.err;
  const ProcessResult host =
      run_process({host_exe(), "--config", config, "--wait-rt", "0.2", "--run", source_dir() + "/examples/demo.ngc"}, 30);
  EXPECT_EQ(host.exit_code, 3) << host.err;
}

TEST(OutputPaths, AreCheckedBeforeAnythingMoves) {
  const std::string dir = make_temp_dir("xout");
  const std::string config = write_test_config(dir, "xout");
  const std::string demo = source_dir() + "/examples/demo.ngc";
  // Real clock: had the program run, the run report would be on stdout.
  for (const Args& bad : {Args{"--report", "/nonexistent/r.html"}, Args{"--summary", "/nonexistent/s.json"},
                          Args{"--trace", "/nonexistent/t.csv"}, Args{"--report", dir}, Args{"--trace", dir + "/"},
                          Args{"--trace", dir + "/same", "--summary", dir + "/same"}}) {
    const ProcessResult r = run_process(plus({pcnc_exe(), "run", demo, "--clock", "real", "--config", config}, bad), 60);
    EXPECT_EQ(r.exit_code, 2) << show(bad) << ": " << r.err;
    EXPECT_TRUE(r.out.empty()) << show(bad) << ": nothing ran, nothing on stdout: " << r.out;
    EXPECT_TRUE(has(r.err, bad[1].substr(0, 12))) << "the message names the path: " << r.err;
    EXPECT_FALSE(std::filesystem::exists(dir + "/same")) << "the check leaves no file behind";
  }
  EXPECT_THROW(HostSegment seg(test_shm_name("xout")), SegmentError) << "pcnc-rt never started";
  const ProcessResult rt = run_process({rt_exe(), "--clock", "virtual", "--config", config, "--trace", "/nonexistent/t.csv"}, 30);
  EXPECT_EQ(rt.exit_code, 2) << rt.err;
  EXPECT_TRUE(has(rt.err, "/nonexistent")) << rt.err;
  // no pcnc-rt is running: the host would wait for it (exit 3) had it not refused the path first
  const ProcessResult host =
      run_process({host_exe(), "--config", config, "--run", demo, "--summary", "/nonexistent/s.json"}, 30);
  EXPECT_EQ(host.exit_code, 2) << host.err;
  const ProcessResult soak = run_process({pcnc_exe(), "soak", demo, "--config", config, "--summary", "/nonexistent/s.json"}, 30);
  EXPECT_EQ(soak.exit_code, 2) << soak.err;
  const ProcessResult serve = run_process({pcnc_exe(), "serve", "--config", config, "--trace", "/nonexistent/t.csv"}, 30);
  EXPECT_EQ(serve.exit_code, 2) << serve.err;
}

// Runs `argv` on a pseudo-terminal (stdin, stdout and stderr all on it, as in a shell) and
// returns all it wrote there and its exit status.
std::pair<std::string, int> run_on_terminal(const Args& argv) {
  int master = -1;
  const pid_t pid = forkpty(&master, nullptr, nullptr, nullptr);
  if (pid == 0) {
    std::vector<char*> a;
    for (const std::string& w : argv) a.push_back(const_cast<char*>(w.c_str()));
    a.push_back(nullptr);
    setenv("TERM", "xterm", 1);
    execv(a[0], a.data());
    _exit(127);
  }
  std::string text;
  char buf[4096];
  for (;;) {
    const ssize_t n = read(master, buf, sizeof buf);
    if (n <= 0) break;  // EIO once the child has closed the terminal
    text.append(buf, static_cast<std::size_t>(n));
  }
  close(master);
  int status = 0;
  waitpid(pid, &status, 0);
  return {text, WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status)};
}

// `pcnc check` of a program that takes a while (a loop of 1.2 million lines run) shows its
// progress on a terminal and clears it before the verdict; -q shows none, and a stderr that is
// not a terminal gets no bar (only plain lines, the first after 5 s).
TEST(Output, ALongCheckShowsItsProgressOnATerminal) {
  const std::string dir = make_temp_dir("xprogress");
  const std::string config = write_test_config(dir, "xprogress");
  // under a sanitizer the check runs several times slower: fewer lines last as long
  const std::string program = loop_program(dir, "loop.ngc", sanitizer_build() ? 50000 : 400000);
  const Args check = {pcnc_exe(), "check", program, "--config", config};
  const auto [shown, code] = run_on_terminal(check);
  EXPECT_EQ(code, 0) << shown;
  const std::size_t bar = shown.find("checking  [");
  ASSERT_NE(bar, std::string::npos) << shown;
  EXPECT_NE(shown.find(" %  line "), std::string::npos) << shown;
  const std::size_t verdict = shown.find("loop.ngc: OK:");
  ASSERT_NE(verdict, std::string::npos) << shown;
  EXPECT_LT(bar, verdict);
  EXPECT_NE(shown.rfind("\r\x1b[K", verdict), std::string::npos) << "the bar is cleared before the verdict";

  const auto [quiet, quiet_code] = run_on_terminal(plus(check, {"-q"}));
  EXPECT_EQ(quiet_code, 0) << quiet;
  EXPECT_EQ(quiet.find("checking"), std::string::npos) << quiet;
  // piped: no bar; a log line only if the check outlasts 5 s (a slow machine, a sanitizer)
  const ProcessResult piped = run_process(check, 120);
  EXPECT_EQ(piped.exit_code, 0) << piped.err;
  EXPECT_EQ(piped.err.find('\r'), std::string::npos) << piped.err;
  EXPECT_EQ(piped.err.find("checking  ["), std::string::npos) << piped.err;
  for (std::size_t at = piped.err.find("checking"); at != std::string::npos; at = piped.err.find("checking", at + 1))
    EXPECT_EQ(piped.err.compare(at > 6 ? at - 6 : 0, 6, "pcnc: "), 0) << "only plain log lines: " << piped.err;
}

TEST(Output, StdoutCarriesTheReportAndStderrTheDiagnostics) {
  const std::string dir = make_temp_dir("xstd");
  const std::string config = write_test_config(dir, "xstd");
  // F above the machine's maximum is clamped with a warning
  const std::string prog = write_program(dir, "warn.ngc", "G21 G90 G54\nG01 X1 Y1 F99999\nM30\n");
  const Args run = {pcnc_exe(), "run", prog, "--clock", "virtual", "--config", config};
  const ProcessResult plain = run_process(run, 120);
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  EXPECT_TRUE(has(plain.out, "run report")) << plain.out;
  EXPECT_FALSE(has(plain.out, "warning")) << "warnings are not on stdout: " << plain.out;
  EXPECT_TRUE(has(plain.err, "warn.ngc:2:")) << "the warning is on stderr: " << plain.err;
  EXPECT_FALSE(has(plain.err, "[info]")) << plain.err;

  const ProcessResult quiet = run_process(plus(run, {"--quiet"}), 120);
  ASSERT_EQ(quiet.exit_code, 0) << quiet.err;
  EXPECT_TRUE(has(quiet.out, "run report"));
  EXPECT_FALSE(has(quiet.err, "warn.ngc:2:")) << quiet.err;

  const ProcessResult verbose = run_process(plus(run, {"--verbose"}), 120);
  ASSERT_EQ(verbose.exit_code, 0) << verbose.err;
  EXPECT_TRUE(has(verbose.err, "[pcnc-rt] [info]")) << verbose.err;
  EXPECT_FALSE(has(verbose.out, "[info]")) << verbose.out;

  const ProcessResult check = run_process({pcnc_exe(), "check", prog, "--config", config}, 60);
  EXPECT_EQ(check.exit_code, 0);
  EXPECT_FALSE(has(check.out, "warn.ngc:2:")) << "the verdict counts warnings; the warning itself is on stderr: " << check.out;
  EXPECT_TRUE(has(check.err, "warn.ngc:2:")) << check.err;
}

}  // namespace
}  // namespace pcnc::test
