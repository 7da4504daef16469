// test_proc_faults.cpp — faults between the processes with real executables and the real
// socket: kill -9 of pcnc-host mid-program (the rt stops on the path, HOST_LOST, holds; a new
// `pcnc-host --serve` re-attaches and resumes or abandons the program), kill -9 of pcnc-rt
// mid-program (the service reports it, refuses motion, re-attaches to a new rt), and
// segments that are garbage or of another layout version (refused, never trusted). Each
// process fault runs under --clock virtual and --clock real.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/mman.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iostream>
#include <sstream>
#include <thread>

#include "config/config.hpp"
#include "service/rpc.hpp"
#include "ipc/segment.hpp"
#include "service_procs.hpp"
#include "test_paths.hpp"

namespace pcnc::test {
namespace {

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;



// Program for the host-kill tests: long enough to be killed in the middle under either clock.
std::string program_for(const std::string& dir, const std::string& clock) {
  return clock == "virtual" ? zigzag_program(dir, 40, 16.0, 60.0)   // ~700 s machine time
                            : zigzag_program(dir, 4, 16.0, 900.0);  // ~5 s
}

struct TraceCheck {
  std::size_t rows = 0;
  double max_step_ratio = 0.0;   // largest per-cycle setpoint step / (axis max velocity * period)
  double max_ferr = 0.0;         // largest |following error| of any axis, mm
  std::size_t host_lost_rows = 0;
  bool parsed = false;
};

// Reads the rt's trace: setpoints never jump (no step beyond the axis's max velocity over one
// period between consecutive cycles) and the following error stays small.
TraceCheck check_trace(const std::string& path, const MachineConfig& m) {
  TraceCheck c;
  std::ifstream in(path);
  std::string line;
  if (!std::getline(in, line) || line.rfind("t,line,state,cmd_x", 0) != 0) return c;
  const double dt = m.cycle_period_s();
  double prev_t = -1.0;
  double prev_cmd[3] = {0, 0, 0};
  while (std::getline(in, line)) {
    std::stringstream ss(line);
    std::string f[13];
    for (auto& x : f) std::getline(ss, x, ',');
    const double t = std::stod(f[0]);
    double cmd[3], ferr[3];
    for (int i = 0; i < 3; ++i) {
      cmd[i] = std::stod(f[3 + i]);
      ferr[i] = std::stod(f[9 + i]);
      c.max_ferr = std::max(c.max_ferr, std::abs(ferr[i]));
    }
    if (f[2] == "HOST_LOST") ++c.host_lost_rows;
    if (prev_t >= 0.0 && std::abs(t - prev_t - dt) < 0.25 * dt) {  // consecutive cycles only
      for (int i = 0; i < 3; ++i) {
        c.max_step_ratio = std::max(c.max_step_ratio, std::abs(cmd[i] - prev_cmd[i]) / (m.axes[i].max_velocity_mm_s * dt));
      }
    }
    prev_t = t;
    for (int i = 0; i < 3; ++i) prev_cmd[i] = cmd[i];
    ++c.rows;
  }
  c.parsed = true;
  return c;
}

// ---------------------------------------------------------------- kill -9 pcnc-host

class KillHost : public ::testing::TestWithParam<std::string> {};

TEST_P(KillHost, RtHoldsOnThePathAndANewHostResumesTheProgram) {
  const std::string clock = GetParam();
  const std::string tag = "khost-" + clock;
  ServicePair p(tag);
  const std::string trace = p.dir() + "/trace.csv";
  ASSERT_TRUE(p.start(clock, {"--trace", trace})) << p.host_log();
  const MachineConfig m = mill_config();
  const std::string prog = program_for(p.dir(), clock);
  ASSERT_TRUE(p.call("run", {{"file", prog}}).contains("result"));
  const json running = p.wait_status([](const json& s) { return s["state"] == "RUNNING" && s["blocks_done"].get<int>() >= 3; }, 30);
  ASSERT_EQ(running["state"], "RUNNING") << running.dump();

  p.kill_host(SIGKILL);

  // The rt decelerates along the path and holds in HOST_LOST, without a fault.
  Status st = wait_rt_state(tag, MachineState::kHostLost);
  ASSERT_EQ(st.state, MachineState::kHostLost) << to_string(st.state);
  EXPECT_EQ(st.fault, FaultCode::kNone);
  EXPECT_EQ(st.path_speed, 0.0);
  for (int i = 0; i < 3; ++i) EXPECT_LT(std::abs(st.following_error[i]), 0.05) << "axis " << axis_name(i);
  const Vec3 held = st.commanded;
  std::this_thread::sleep_for(300ms);
  ASSERT_TRUE(read_rt_status(tag, st));
  EXPECT_EQ(st.commanded, held) << "keeps holding position";
  EXPECT_EQ(st.state, MachineState::kHostLost);

  // A new service re-attaches and reads the state.
  ASSERT_TRUE(p.start_host()) << p.host_log();
  json s = p.wait_status([](const json& x) { return x["rt"]["state"] == "attached"; }, 10);
  EXPECT_EQ(s["state"], "HOST_LOST");
  ASSERT_TRUE(s["resume"].is_object()) << s.dump();
  EXPECT_EQ(s["resume"]["file"], prog);
  EXPECT_GT(s["resume"]["line"].get<int>(), 0);
  for (int i = 0; i < 3; ++i) EXPECT_DOUBLE_EQ(pos(s, "commanded", i), held[i]);
  EXPECT_EQ(error_code(p.call("jog", {{"axis", "X"}, {"distance", 1}})), rpc::kRefused);
  EXPECT_EQ(error_code(p.call("run", {{"file", prog}})), rpc::kRefused);

  // Resume: the rest of the interrupted block from where the machine stands, then the rest
  // of the program, to its last point.
  const json r = p.call("resume", json::object(), 60);
  ASSERT_TRUE(r.contains("result")) << r.dump() << p.host_log();
  EXPECT_TRUE(r["result"]["resumed"].get<bool>());
  s = p.wait_status(idle_after_job, clock == "virtual" ? 120 : 60);
  ASSERT_TRUE(s["last_job"].is_object()) << s.dump();
  EXPECT_EQ(s["last_job"]["end"], "completed") << s.dump();
  EXPECT_TRUE(s["program_done"].get<bool>());
  const Vec3 expected{12.5, 12.5, 24.0};  // zigzag ends at program X0 Y0 Z-1
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(pos(s, "commanded", i), expected[i], 1e-6);
  EXPECT_TRUE(s["resume"].is_null());

  // The trace of the whole episode: no setpoint jump, no following-error excursion.
  p.kill_rt(SIGTERM);  // flushes the trace
  const TraceCheck t = check_trace(trace, m);
  ASSERT_TRUE(t.parsed) << trace;
  EXPECT_GT(t.rows, 1000u);
  EXPECT_GT(t.host_lost_rows, 0u) << "the trace shows the HOST_LOST hold";
  EXPECT_LE(t.max_step_ratio, 1.0 + 1e-6) << "a setpoint step beyond the axis's max velocity: a jump";
  EXPECT_LT(t.max_ferr, 0.05);
  std::cout << "[ figures  ] kill host (" << clock << "): trace rows " << t.rows << ", max setpoint step "
            << t.max_step_ratio << " x vmax*dt, max |ferr| " << t.max_ferr << " mm\n";
}

INSTANTIATE_TEST_SUITE_P(Clocks, KillHost, ::testing::Values("virtual", "real"));

TEST(KillHostStop, StopAbandonsTheInterruptedProgram) {
  ServicePair p("khost-stop");
  ASSERT_TRUE(p.start("virtual")) << p.host_log();
  const std::string prog = program_for(p.dir(), "virtual");
  ASSERT_TRUE(p.call("run", {{"file", prog}}).contains("result"));
  ASSERT_EQ(p.wait_status([](const json& s) { return s["blocks_done"].get<int>() >= 3; }, 30)["state"], "RUNNING");
  p.kill_host(SIGKILL);
  Status st{};
  for (int i = 0; i < 1000 && !(read_rt_status("khost-stop", st) && st.state == MachineState::kHostLost); ++i) {
    std::this_thread::sleep_for(5ms);
  }
  ASSERT_EQ(st.state, MachineState::kHostLost);
  ASSERT_TRUE(p.start_host());
  p.wait_status([](const json& x) { return x["rt"]["state"] == "attached"; }, 10);
  const json r = p.call("stop");
  ASSERT_TRUE(r.contains("result")) << r.dump();
  EXPECT_TRUE(r["result"]["abandoned"].get<bool>());
  json s = p.wait_status([](const json& x) { return x["state"] == "IDLE"; }, 10);
  EXPECT_EQ(s["state"], "IDLE");
  EXPECT_TRUE(s["resume"].is_null());
  for (int i = 0; i < 3; ++i) EXPECT_DOUBLE_EQ(pos(s, "commanded", i), st.commanded[i]) << "stays where it stopped";
  EXPECT_EQ(error_code(p.call("resume")), rpc::kRefused) << "nothing left to resume";
  // The machine is usable again.
  ASSERT_TRUE(p.call("run", {{"file", source_dir() + "/examples/demo.ngc"}}).contains("result"));
  s = p.wait_status(idle_after_job, 120);
  EXPECT_EQ(s["last_job"]["end"], "completed") << s.dump();
}

// ---------------------------------------------------------------- kill -9 pcnc-rt

class KillRt : public ::testing::TestWithParam<std::string> {};

TEST_P(KillRt, ServiceReportsRefusesMotionAndReattachesToANewRt) {
  const std::string clock = GetParam();
  ServicePair p("krt-" + clock);
  ASSERT_TRUE(p.start(clock)) << p.host_log();
  CtlClient events(p.socket());
  ASSERT_TRUE(events.call("subscribe", {{"rate_hz", 1}}).contains("result"));
  const std::string prog = program_for(p.dir(), clock);
  ASSERT_TRUE(p.call("run", {{"file", prog}}).contains("result"));
  ASSERT_EQ(p.wait_status([](const json& s) { return s["blocks_done"].get<int>() >= 2; }, 30)["state"], "RUNNING");

  const auto t_kill = Clock::now();
  p.kill_rt(SIGKILL);
  json lost;
  std::string line;
  while (lost.is_null() && events.read_line(line, 10.0)) {
    const json n = json::parse(line);
    if (n.value("method", "") == "event" && n["params"]["event"] == "rt_lost") lost = n["params"];
  }
  const double noticed_ms = std::chrono::duration<double, std::milli>(Clock::now() - t_kill).count();
  ASSERT_TRUE(lost.is_object()) << "the service pushes an rt_lost event";
  std::cout << "[ figures  ] kill rt (" << clock << "): rt_lost event received " << noticed_ms
            << " ms after kill(2) returned (reaped); heartbeat age at detection " << lost["heartbeat_age_ms"] << " ms\n";

  json s = p.wait_status([](const json& x) { return !x["job"]["active"].get<bool>(); }, 10);
  EXPECT_EQ(s["rt"]["state"], "lost");
  EXPECT_EQ(s["state"], "NO_RT");
  EXPECT_NE(s["rt"]["message"].get<std::string>().find("gone"), std::string::npos) << s.dump();
  ASSERT_TRUE(s["last_job"].is_object());
  EXPECT_EQ(s["last_job"]["end"], "pcnc-rt lost") << s.dump();
  for (const auto& [method, params] : std::vector<std::pair<std::string, json>>{
           {"jog", {{"axis", "X"}, {"distance", 1}}}, {"run", {{"file", prog}}}, {"pause", json::object()},
           {"resume", json::object()}, {"override", {{"percent", 50}}}, {"reset", json::object()}}) {
    const json r = p.call(method, params);
    EXPECT_EQ(error_code(r), rpc::kRtUnavailable) << method << ": " << r.dump();
  }
  EXPECT_NE(p.host_log().find("pcnc-rt lost"), std::string::npos) << p.host_log();

  // A new rt: the service attaches by itself and runs programs again.
  p.start_rt(clock);
  s = p.wait_status([](const json& x) { return x["rt"]["state"] == "attached" && x["state"] == "IDLE"; }, 20);
  ASSERT_EQ(s["rt"]["state"], "attached") << s.dump() << p.host_log();
  EXPECT_EQ(s["rt"]["pid"], p.rt_pid());
  const std::string short_prog = write_program(p.dir(), "short.ngc", "G21 G90 G54\nG01 X2 Y1 Z-1 F1200\nM30\n");
  ASSERT_TRUE(p.call("run", {{"file", short_prog}}).contains("result"));
  s = p.wait_status(idle_after_job, 60);
  EXPECT_EQ(s["last_job"]["end"], "completed") << s.dump();
  EXPECT_NEAR(pos(s, "commanded", 0), 14.5, 1e-6);
}

INSTANTIATE_TEST_SUITE_P(Clocks, KillRt, ::testing::Values("virtual", "real"));

// ---------------------------------------------------------------- foreign segments

// Creates a segment under the test's name holding `bytes`.
void plant_segment(const std::string& name, const std::vector<unsigned char>& bytes) {
  const int fd = shm_open(name.c_str(), O_CREAT | O_RDWR | O_TRUNC, 0600);
  ASSERT_GE(fd, 0) << std::strerror(errno);
  ASSERT_EQ(ftruncate(fd, static_cast<off_t>(bytes.size())), 0);
  ASSERT_EQ(write(fd, bytes.data(), bytes.size()), static_cast<ssize_t>(bytes.size()));
  close(fd);
}

TEST(ForeignSegment, GarbageAndOtherLayoutVersionsAreRefused) {
  ServicePair p("seg-foreign");
  const std::string name = test_shm_name("seg-foreign");

  // Garbage.
  std::vector<unsigned char> garbage(sizeof(SharedSegment));
  for (std::size_t i = 0; i < garbage.size(); ++i) garbage[i] = static_cast<unsigned char>((i * 2654435761u) >> 13);
  plant_segment(name, garbage);
  ASSERT_TRUE(p.start_host()) << p.host_log();
  json s = p.wait_status([](const json& x) { return x["rt"]["state"] == "refused"; }, 10);
  EXPECT_EQ(s["rt"]["state"], "refused") << s.dump();
  EXPECT_NE(s["rt"]["message"].get<std::string>().find("magic"), std::string::npos) << s.dump();
  const json j = p.call("jog", {{"axis", "X"}, {"distance", 1}});
  EXPECT_EQ(error_code(j), rpc::kRtUnavailable);
  EXPECT_NE(j["error"]["message"].get<std::string>().find("refused"), std::string::npos) << j.dump();

  // The right magic, another layout version.
  std::vector<unsigned char> other(sizeof(SharedSegment), 0);
  const std::uint64_t magic = kSegmentMagic;
  const std::uint32_t version = kLayoutVersion + 1;
  const std::uint64_t size = sizeof(SharedSegment);
  std::memcpy(other.data() + offsetof(SegmentHeader, magic), &magic, sizeof magic);
  std::memcpy(other.data() + offsetof(SegmentHeader, layout_version), &version, sizeof version);
  std::memcpy(other.data() + offsetof(SegmentHeader, total_size), &size, sizeof size);
  plant_segment(name, other);
  s = p.wait_status([](const json& x) { return x["rt"]["message"].get<std::string>().find("layout version") != std::string::npos; }, 10);
  EXPECT_EQ(s["rt"]["state"], "refused");
  EXPECT_NE(s["rt"]["message"].get<std::string>().find("layout version"), std::string::npos) << s.dump();
  EXPECT_EQ(error_code(p.call("run", {{"file", source_dir() + "/examples/demo.ngc"}})), rpc::kRtUnavailable);
  EXPECT_NE(p.host_log().find("refusing pcnc-rt's segment"), std::string::npos) << p.host_log();

  // A real rt replaces the foreign segment; the service attaches to it.
  remove_segment(name);
  p.start_rt("virtual");
  s = p.wait_status([](const json& x) { return x["rt"]["state"] == "attached" && x["state"] == "IDLE"; }, 20);
  EXPECT_EQ(s["rt"]["state"], "attached") << s.dump() << p.host_log();
}

}  // namespace
}  // namespace pcnc::test
