// test_proc_one_host.cpp — the rt serves one host at a time (issue 19): while a service feeds
// the rt, a second pcnc-host is refused (it would mask the first one's loss with its own
// heartbeat); when the first is killed the rt raises HOST_LOST as usual, and a new host takes
// the claim over. Real processes, real segment.
#include <gtest/gtest.h>
#include <signal.h>

#include <chrono>
#include <thread>

#include "ipc/segment.hpp"
#include "service_procs.hpp"
#include "test_paths.hpp"

namespace pcnc::test {
namespace {

using namespace std::chrono_literals;

MachineState rt_state(const std::string& tag) {
  Status st;
  return read_rt_status(tag, st) ? st.state : MachineState::kStarting;
}

TEST(OneHost, ASecondHostIsRefusedAndTheFirstOnesLossIsStillSeen) {
  ServicePair p("one-host");
  ASSERT_TRUE(p.start("virtual")) << p.host_log();
  const std::string prog = zigzag_program(p.dir(), 40, 16.0, 60.0);  // ~700 s of machine time
  ASSERT_TRUE(p.call("run", {{"file", prog}}).contains("result"));
  const json running = p.wait_status([](const json& s) { return s["state"] == "RUNNING" && s["blocks_done"].get<int>() >= 3; }, 30);
  ASSERT_EQ(running["state"], "RUNNING") << running.dump();

  const ProcessResult second = run_process({host_exe(), "--config", p.config(), "--run", prog}, 30.0);
  EXPECT_NE(second.exit_code, 0);
  EXPECT_NE(second.err.find("already served by pcnc-host pid " + std::to_string(p.host_pid())), std::string::npos)
      << second.err;
  EXPECT_EQ(p.status()["state"], "RUNNING") << "the first host's program runs on";

  p.kill_host(SIGKILL);
  MachineState st = MachineState::kStarting;
  for (int i = 0; i < 1000 && st != MachineState::kHostLost; ++i) {
    st = rt_state(p.tag());
    std::this_thread::sleep_for(5ms);
  }
  EXPECT_EQ(st, MachineState::kHostLost) << to_string(st);

  // the claim of a host that is gone is taken over
  ASSERT_TRUE(p.start_host()) << p.host_log();
  const json s = p.wait_status([](const json& j) { return j["rt"]["state"] == "attached"; }, 20);
  EXPECT_EQ(s["rt"]["state"], "attached") << s.dump();
  EXPECT_EQ(s["state"], "HOST_LOST") << s.dump();
}

TEST(OneHostClaim, FreeOrAbandonedClaimsAreTakenLiveOnesAreNot) {
  SegmentHeader h;
  EXPECT_EQ(claim_host(h, 1234567), 0);       // free
  EXPECT_EQ(h.host_pid.load(), 1234567);
  EXPECT_EQ(claim_host(h, getpid()), 0);      // pid 1234567 does not run: taken over
  EXPECT_EQ(h.host_pid.load(), getpid());
  EXPECT_EQ(claim_host(h, 1234568), getpid());  // held by a running process
  EXPECT_EQ(h.host_pid.load(), getpid());
  release_host(h, 1234568);                   // not the holder: no effect
  EXPECT_EQ(h.host_pid.load(), getpid());
  release_host(h, getpid());
  EXPECT_EQ(h.host_pid.load(), 0);
}

}  // namespace
}  // namespace pcnc::test
