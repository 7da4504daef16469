// test_proc_rt_restart.cpp — a restarted pcnc-rt takes up the machine where the dead one last
// measured it (issue 19): the simulated plant's state lives in the shared segment, so after
// kill -9 of the rt, a new rt on the same config finds the stale segment and starts at rest
// at the last published actual position (as absolute encoders would report after a drive's
// power loss), IDLE, the program not resumed by the rt itself; the service re-attaches. With
// no stale segment (a clean exit) it starts at home as before.
#include <gtest/gtest.h>
#include <signal.h>
#include <unistd.h>

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

bool attached_idle(const json& s) { return s["rt"]["state"] == "attached" && s["state"] == "IDLE"; }


void expect_at(const json& s, const Vec3& where, const MachineConfig& m, const char* what) {
  for (int i = 0; i < 3; ++i) {
    const double count = m.axes[i].encoder_resolution_mm;
    EXPECT_NEAR(pos(s, "actual", i), where[i], count + 1e-12) << what << ", axis " << axis_name(i) << ": " << s.dump();
    EXPECT_NEAR(pos(s, "commanded", i), where[i], count + 1e-12) << what << ", axis " << axis_name(i);
    EXPECT_EQ(pos(s, "velocity", i), 0.0) << what << ", axis " << axis_name(i);
  }
  EXPECT_EQ(s["path_speed"].get<double>(), 0.0);
}

class RtRestart : public ::testing::TestWithParam<std::string> {};

TEST_P(RtRestart, ANewRtStartsAtRestWhereTheKilledOneLastMeasured) {
  const std::string clock = GetParam();
  const std::string tag = "restart-" + clock;
  const MachineConfig m = mill_config();
  ServicePair p(tag);
  ASSERT_TRUE(p.start(clock)) << p.host_log();
  // Jog away from home (12.5, 12.5, 25).
  for (const auto& [axis, d] : std::vector<std::pair<std::string, double>>{{"X", -7.0}, {"Y", 5.5}, {"Z", -3.25}}) {
    const json r = p.call("jog", {{"axis", axis}, {"distance", d}});
    ASSERT_TRUE(r.contains("result")) << r.dump();
    ASSERT_EQ(p.wait_status([](const json& s) { return s["state"] == "IDLE"; }, 30)["state"], "IDLE");
  }
  std::this_thread::sleep_for(100ms);  // settled
  p.kill_rt(SIGKILL);
  Status last{};
  ASSERT_TRUE(read_rt_status(tag, last)) << "the killed rt's segment is still there";
  EXPECT_NEAR(last.actual[0], 5.5, 0.001);
  EXPECT_NEAR(last.actual[1], 18.0, 0.001);
  EXPECT_NEAR(last.actual[2], 21.75, 0.001);

  p.start_rt(clock);
  const json s = p.wait_status(attached_idle, 20);
  ASSERT_TRUE(attached_idle(s)) << s.dump() << p.host_log();
  EXPECT_EQ(s["rt"]["pid"], p.rt_pid());
  expect_at(s, last.actual, m, "after the restart");
  EXPECT_NE(p.rt_log().find("the axes stand where pcnc-rt last measured them"), std::string::npos) << p.rt_log();
  // The machine is usable from there: a jog moves relative to where it stands.
  ASSERT_TRUE(p.call("jog", {{"axis", "X"}, {"distance", 1.0}}).contains("result"));
  const json after = p.wait_status([](const json& x) { return x["state"] == "IDLE"; }, 30);
  EXPECT_NEAR(pos(after, "commanded", 0), last.actual[0] + 1.0, 1e-9) << after.dump();
}

INSTANTIATE_TEST_SUITE_P(Clocks, RtRestart, ::testing::Values("virtual", "real"));

// Killed in the middle of a move at 50 mm/s: the new rt stands where the old one last
// measured the axes (a few hundredths of a millimetre after its last status, as a drive
// without power coasts; the simulation has no coasting), at rest, and its trace starts there
// without a jump.
TEST(RtRestartMidMove, ANewRtStartsAtRestWhereTheMovingOneWasLastMeasured) {
  const std::string tag = "restart-move";
  const MachineConfig m = mill_config();
  ServicePair p(tag);
  ASSERT_TRUE(p.start("real")) << p.host_log();
  const std::string prog = zigzag_program(p.dir(), 8, 20.0, 3000.0);
  ASSERT_TRUE(p.call("run", {{"file", prog}}).contains("result"));
  const json running = p.wait_status([](const json& s) { return s["state"] == "RUNNING" && s["path_speed"].get<double>() > 40.0; }, 30);
  ASSERT_EQ(running["state"], "RUNNING") << running.dump();
  p.kill_rt(SIGKILL);
  Status last{};
  ASSERT_TRUE(read_rt_status(tag, last));
  EXPECT_EQ(last.state, MachineState::kRunning);
  EXPECT_GT(last.path_speed, 0.0);

  const std::string trace = p.dir() + "/trace-after.csv";
  p.start_rt("real", {"--trace", trace});
  json s = p.wait_status(attached_idle, 20);
  ASSERT_TRUE(attached_idle(s)) << s.dump() << p.host_log();
  expect_at(s, last.actual, m, "after the restart");
  EXPECT_FALSE(s["program_active"].get<bool>()) << "the rt does not resume the program by itself";
  ASSERT_TRUE(s["last_job"].is_object()) << s.dump();
  EXPECT_EQ(s["last_job"]["end"], "pcnc-rt lost");
  std::this_thread::sleep_for(200ms);
  s = p.status();
  expect_at(s, last.actual, m, "holding there");
  p.kill_rt(SIGTERM);  // at rest: exits at once, flushes the trace
  std::ifstream in(trace);
  std::string line;
  ASSERT_TRUE(std::getline(in, line));
  ASSERT_TRUE(std::getline(in, line)) << "the new rt's first cycle";
  std::stringstream ss(line);
  std::string f[13];
  for (auto& x : f) std::getline(ss, x, ',');
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(std::stod(f[3 + i]), last.actual[i], m.axes[i].encoder_resolution_mm) << "first commanded " << axis_name(i);
    EXPECT_NEAR(std::stod(f[6 + i]), last.actual[i], m.axes[i].encoder_resolution_mm) << "first measured " << axis_name(i);
  }
  std::cout << "[ figures  ] rt killed at " << last.path_speed << " mm/s at X" << last.actual[0] << " Y" << last.actual[1]
            << " Z" << last.actual[2] << "; the new rt's first row: X" << f[6] << " Y" << f[7] << " Z" << f[8] << "\n";
}

// A clean exit removes the segment: the next rt starts at home, as before.
TEST(RtRestartClean, AfterACleanExitTheNextRtStartsAtHome) {
  const std::string tag = "restart-clean";
  ServicePair p(tag);
  ASSERT_TRUE(p.start("virtual")) << p.host_log();
  ASSERT_TRUE(p.call("jog", {{"axis", "X"}, {"distance", -4.0}}).contains("result"));
  ASSERT_EQ(p.wait_status([](const json& s) { return s["state"] == "IDLE"; }, 30)["state"], "IDLE");
  p.kill_rt(SIGTERM);
  p.start_rt("virtual");
  const json s = p.wait_status(attached_idle, 20);
  ASSERT_TRUE(attached_idle(s)) << s.dump();
  EXPECT_NEAR(pos(s, "actual", 0), 12.5, 1e-9);
}

}  // namespace
}  // namespace pcnc::test
