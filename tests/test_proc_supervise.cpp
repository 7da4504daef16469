// test_proc_supervise.cpp — `pcnc serve` keeps the service up when one of its processes
// dies (issue 19): kill -9 of pcnc-host mid-program leaves the rt running (it brings the
// machine to rest, HOST_LOST) and a new host is started that resumes the program; kill -9 of
// pcnc-rt starts a new rt the host re-attaches to; a process that keeps dying ends the service
// with exit 3; SIGTERM ends it with 128+15. Real launcher, real processes, real socket.
#include <gtest/gtest.h>
#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "service_procs.hpp"
#include "test_paths.hpp"

namespace pcnc::test {
namespace {

using namespace std::chrono_literals;

// The children of `pid` whose command name is `comm` (pcnc-rt or pcnc-host).
std::vector<pid_t> children_named(pid_t pid, const std::string& comm) {
  std::vector<pid_t> out;
  std::ifstream in("/proc/" + std::to_string(pid) + "/task/" + std::to_string(pid) + "/children");
  pid_t c;
  while (in >> c) {
    std::ifstream cin("/proc/" + std::to_string(c) + "/comm");
    std::string name;
    std::getline(cin, name);
    if (name == comm) out.push_back(c);
  }
  return out;
}

// Waits until the launcher has exactly one child named `comm` other than `not_this`.
pid_t wait_child(pid_t launcher, const std::string& comm, pid_t not_this, double timeout_s) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  while (std::chrono::steady_clock::now() < deadline) {
    const auto kids = children_named(launcher, comm);
    if (kids.size() == 1 && kids[0] != not_this) return kids[0];
    std::this_thread::sleep_for(10ms);
  }
  return 0;
}

bool alive(pid_t pid) { return kill(pid, 0) == 0; }

struct Serve {
  ServicePair pair;  // only for its private config, folder and socket
  BackgroundProcess launcher;
  explicit Serve(const std::string& tag) : pair(tag) {
    launcher = start_process({pcnc_exe(), "serve", "--config", pair.config(), "--clock", "virtual"}, pair.dir() + "/serve");
  }
  ~Serve() {
    if (launcher.pid > 0 && kill(launcher.pid, 0) == 0 && launcher.wait(0.0) < 0) {
      kill(launcher.pid, SIGTERM);
      if (launcher.wait(15.0) < 0) kill(launcher.pid, SIGKILL), launcher.wait(5.0);
    }
  }
  bool ready() {
    const json s = pair.wait_status([](const json& s) { return s["rt"]["state"] == "attached" && s["state"] == "IDLE"; }, 20.0);
    return s["rt"]["state"] == "attached" && s["state"] == "IDLE";
  }
};

TEST(Supervise, AHostKilledMidProgramIsRestartedAndResumesWhileTheRtStaysUp) {
  Serve s("sup-host");
  ASSERT_TRUE(s.ready()) << s.launcher.err();
  const pid_t rt = wait_child(s.launcher.pid, "pcnc-rt", 0, 5.0);
  const pid_t host = wait_child(s.launcher.pid, "pcnc-host", 0, 5.0);
  ASSERT_GT(rt, 0);
  ASSERT_GT(host, 0);

  const std::string prog = zigzag_program(s.pair.dir(), 40, 16.0, 60.0);  // ~700 s of machine time
  ASSERT_TRUE(s.pair.call("run", {{"file", prog}}).contains("result"));
  const json running =
      s.pair.wait_status([](const json& j) { return j["state"] == "RUNNING" && j["blocks_done"].get<int>() >= 3; }, 30);
  ASSERT_EQ(running["state"], "RUNNING") << running.dump();

  const auto t_kill = std::chrono::steady_clock::now();
  ASSERT_EQ(kill(host, SIGKILL), 0);
  const pid_t host2 = wait_child(s.launcher.pid, "pcnc-host", host, 15.0);
  ASSERT_GT(host2, 0) << "no new pcnc-host; launcher said: " << s.launcher.err();
  EXPECT_TRUE(alive(rt)) << "the rt must not be killed with the host";
  EXPECT_EQ(wait_child(s.launcher.pid, "pcnc-rt", 0, 1.0), rt) << "the same rt";

  // The new host finds the machine at rest on the path in HOST_LOST and resumes it.
  const json lost = s.pair.wait_status([](const json& j) { return j["state"] == "HOST_LOST"; }, 20);
  ASSERT_EQ(lost["state"], "HOST_LOST") << lost.dump();
  std::cout << "[ figures  ] kill -9 pcnc-host under pcnc serve: the new host answers status (HOST_LOST) "
            << std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t_kill).count()
            << " ms after the kill\n";
  EXPECT_EQ(lost["path_speed"].get<double>(), 0.0) << lost.dump();
  const json resumed = s.pair.call("resume");
  ASSERT_TRUE(resumed.contains("result")) << resumed.dump();
  const json done = s.pair.wait_status(
      [](const json& j) { return j["state"] == "IDLE" && !j["job"]["active"].get<bool>() && j["last_job"].is_object(); }, 60);
  ASSERT_TRUE(done["last_job"].is_object()) << done.dump();
  EXPECT_EQ(done["last_job"]["end"], "completed") << done.dump();
  EXPECT_NE(s.launcher.err().find("starting pcnc-host again"), std::string::npos) << s.launcher.err();

  // SIGTERM ends the service: both children end, exit 128+15.
  ASSERT_EQ(kill(s.launcher.pid, SIGTERM), 0);
  EXPECT_EQ(s.launcher.wait(20.0), 128 + SIGTERM);
  EXPECT_FALSE(alive(rt));
  EXPECT_FALSE(alive(host2));
}

TEST(Supervise, AnRtKilledIsRestartedAndTheHostReattaches) {
  Serve s("sup-rt");
  ASSERT_TRUE(s.ready()) << s.launcher.err();
  const pid_t rt = wait_child(s.launcher.pid, "pcnc-rt", 0, 5.0);
  const pid_t host = wait_child(s.launcher.pid, "pcnc-host", 0, 5.0);
  ASSERT_GT(rt, 0);
  const auto t_kill = std::chrono::steady_clock::now();
  ASSERT_EQ(kill(rt, SIGKILL), 0);
  const pid_t rt2 = wait_child(s.launcher.pid, "pcnc-rt", rt, 15.0);
  ASSERT_GT(rt2, 0) << "no new pcnc-rt; launcher said: " << s.launcher.err();
  const json st = s.pair.wait_status(
      [rt2](const json& j) { return j["rt"]["state"] == "attached" && j["rt"]["pid"] == rt2 && j["state"] == "IDLE"; }, 20);
  EXPECT_EQ(st["rt"]["pid"], rt2) << st.dump();
  std::cout << "[ figures  ] kill -9 pcnc-rt under pcnc serve: the host is attached to the new rt (IDLE) "
            << std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t_kill).count()
            << " ms after the kill\n";
  EXPECT_EQ(wait_child(s.launcher.pid, "pcnc-host", 0, 1.0), host) << "the same host re-attached";
  // and it moves again
  const json jog = s.pair.call("jog", {{"axis", "X"}, {"distance", 1.0}, {"feed", 300.0}});
  EXPECT_TRUE(jog.contains("result")) << jog.dump();
}

TEST(Supervise, AProcessThatKeepsDyingEndsTheServiceWithExit3) {
  Serve s("sup-give-up");
  ASSERT_TRUE(s.ready()) << s.launcher.err();
  pid_t host = wait_child(s.launcher.pid, "pcnc-host", 0, 5.0);
  int kills = 0, exit_code = -1;
  while (host > 0 && kills < 10) {
    kill(host, SIGKILL);
    ++kills;
    const auto deadline = std::chrono::steady_clock::now() + 10s;
    pid_t next = 0;
    while (std::chrono::steady_clock::now() < deadline && next == 0 && exit_code < 0) {
      const auto kids = children_named(s.launcher.pid, "pcnc-host");
      if (kids.size() == 1 && kids[0] != host) next = kids[0];
      exit_code = s.launcher.wait(0.01);
    }
    host = next;
  }
  if (exit_code < 0) exit_code = s.launcher.wait(20.0);
  EXPECT_EQ(exit_code, 3) << s.launcher.err();
  EXPECT_EQ(kills, 6) << "5 restarts within 60 s, then give up";
  EXPECT_NE(s.launcher.err().find("giving up"), std::string::npos) << s.launcher.err();
}

}  // namespace
}  // namespace pcnc::test
