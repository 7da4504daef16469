// test_subprocess.cpp — the tests' own process helper (tests/support/subprocess): a background
// process a test started ends with the test, also when the test dies without running its
// destructors (an abort in a library's assertion, a crash, ctest's timeout), so that a failed
// test never leaves a pcnc-rt and a pcnc-host running beside the rest of the suite.
#include <gtest/gtest.h>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <fstream>
#include <string>
#include <thread>

#include "subprocess.hpp"
#include "test_paths.hpp"

namespace pcnc {
namespace {

using namespace test;

// Running (not gone, not a zombie waiting for init to reap it).
bool running(pid_t pid) {
  std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
  std::string pid_field, comm, state;
  if (!(stat >> pid_field >> comm >> state)) return false;
  return state != "Z" && state != "X";
}

TEST(Subprocess, ABackgroundProcessEndsWhenTheTestThatStartedItDies) {
  const std::string dir = make_temp_dir("subproc");
  int fds[2];
  ASSERT_EQ(pipe(fds), 0);
  const pid_t test = fork();
  ASSERT_GE(test, 0);
  if (test == 0) {  // the stand-in for a test: starts a long process, then dies at once
    const BackgroundProcess p = start_process({"/bin/sleep", "60"}, dir + "/sleep");
    (void)!write(fds[1], &p.pid, sizeof p.pid);
    std::this_thread::sleep_for(std::chrono::milliseconds(200));  // the child is running
    _exit(0);  // no destructors, like an abort
  }
  close(fds[1]);
  pid_t child = -1;
  ASSERT_EQ(read(fds[0], &child, sizeof child), static_cast<ssize_t>(sizeof child));
  close(fds[0]);
  ASSERT_GT(child, 0);
  int status = 0;
  ASSERT_EQ(waitpid(test, &status, 0), test);
  bool gone = false;
  for (int i = 0; i < 2000 && !gone; ++i) {  // up to 10 s
    gone = !running(child);
    if (!gone) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  if (!gone) kill(child, SIGKILL);
  EXPECT_TRUE(gone) << "the background process " << child << " outlived the test that started it";
}

TEST(Subprocess, ABackgroundProcessRunsWhileTheTestDoes) {
  const std::string dir = make_temp_dir("subproc2");
  BackgroundProcess p = start_process({"/bin/sleep", "30"}, dir + "/sleep");
  EXPECT_TRUE(running(p.pid));
  kill(p.pid, SIGTERM);
  EXPECT_EQ(wait_for(p, 10.0), 128 + SIGTERM);  // ended by the signal, not by its parent's death
}

}  // namespace
}  // namespace pcnc
