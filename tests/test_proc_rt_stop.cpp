// test_proc_rt_stop.cpp — pcnc-rt never has its power cut while the machine moves (issue 19):
// the first SIGTERM/SIGINT brings a moving machine to rest along its path (as a stop does),
// then the process exits 0; a second signal ends it at once. Real processes, real traces:
// `pcnc run` whose host is killed -9 mid-move (the launcher then asks the rt to end), and
// SIGTERM straight to a running rt, under the real and the virtual clock, at 50 mm/s and at
// the maximum feed. The traces' last rows show the speed reaching 0 and no setpoint step
// beyond the axis's maximum velocity over one period.
#include <gtest/gtest.h>
#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <fstream>
#include <functional>
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


using Clock = std::chrono::steady_clock;

// X strokes across most of the travel at `feed` mm/min (program zero is the travel's centre).
std::string strokes_program(const std::string& dir, int strokes, double feed) {
  std::ostringstream p;
  p << "G21 G90 G17 G54\nG00 Z-1\nG00 X-11 Y-8\n";
  for (int i = 0; i < strokes; ++i) {
    p << "G01 X" << (i % 2 == 0 ? 11 : -11) << " F" << feed << "\n";
    p << "G01 Y" << (i % 2 == 0 ? 8 : -8) << "\n";
  }
  p << "M30\n";
  return write_program(dir, "strokes.ngc", p.str());
}

struct TraceEnd {
  bool parsed = false;
  std::size_t rows = 0;
  double max_step_ratio = 0.0;    // largest per-cycle setpoint step / (axis max velocity * period)
  double max_speed = 0.0;         // over the whole trace, mm/s
  double last_speed = -1.0;       // the last row's commanded speed
  std::string last_state;
  std::size_t rest_rows_at_end = 0;   // trailing rows with speed 0 and the setpoint unchanged
  double stop_speed = 0.0;        // the speed of the last RUNNING row (the stop began after it), mm/s
  double decel_s = 0.0;           // from the last RUNNING row to the first row of the final rest
};

TraceEnd read_trace(const std::string& path, const MachineConfig& m) {
  TraceEnd c;
  std::ifstream in(path);
  std::string line;
  if (!std::getline(in, line) || line.rfind("t,line,state,cmd_x", 0) != 0) return c;
  const double dt = m.cycle_period_s();
  double prev_t = -1.0, prev_cmd[3] = {0, 0, 0};
  double t_running = 0.0, t_rest = -1.0;
  while (std::getline(in, line)) {
    std::stringstream ss(line);
    std::string f[13];
    for (auto& x : f) std::getline(ss, x, ',');
    if (f[12].empty()) continue;  // a torn last line cannot happen: the rt drains and closes
    const double t = std::stod(f[0]);
    double cmd[3];
    for (int i = 0; i < 3; ++i) cmd[i] = std::stod(f[3 + i]);
    const double speed = std::stod(f[12]);
    bool same = prev_t >= 0.0;
    if (prev_t >= 0.0 && std::abs(t - prev_t - dt) < 0.25 * dt) {
      for (int i = 0; i < 3; ++i) {
        c.max_step_ratio = std::max(c.max_step_ratio, std::abs(cmd[i] - prev_cmd[i]) / (m.axes[i].max_velocity_mm_s * dt));
      }
    }
    for (int i = 0; i < 3; ++i) same = same && cmd[i] == prev_cmd[i];
    if (speed == 0.0 && same) {
      if (c.rest_rows_at_end++ == 0) t_rest = t;
    } else {
      c.rest_rows_at_end = 0;
    }
    if (speed > c.max_speed) c.max_speed = speed;
    if (f[2] == "RUNNING") {
      t_running = t;
      c.stop_speed = speed;
    }
    c.last_speed = speed;
    c.last_state = f[2];
    prev_t = t;
    for (int i = 0; i < 3; ++i) prev_cmd[i] = cmd[i];
    ++c.rows;
  }
  c.decel_s = t_rest >= t_running ? t_rest - t_running : 0.0;
  c.parsed = true;
  return c;
}


// Polls the rt's status until `pred` holds (or timeout); returns whether it did.
bool wait_rt(const std::string& tag, const std::function<bool(const Status&)>& pred, double timeout_s, Status& st) {
  const auto deadline = Clock::now() + std::chrono::duration<double>(timeout_s);
  while (Clock::now() < deadline) {
    if (read_rt_status(tag, st) && pred(st)) return true;
    std::this_thread::sleep_for(2ms);
  }
  return false;
}

void expect_brought_to_rest(const TraceEnd& t, double min_speed) {
  ASSERT_TRUE(t.parsed);
  EXPECT_GT(t.stop_speed, min_speed) << "the machine was moving when the rt was asked to end";
  EXPECT_EQ(t.last_speed, 0.0) << "the trace ends at rest, state " << t.last_state;
  EXPECT_GE(t.rest_rows_at_end, 10u) << "a few cycles standing still before the exit";
  EXPECT_NE(t.last_state, "RUNNING");
  EXPECT_LE(t.max_step_ratio, 1.0 + 1e-6) << "a setpoint step beyond the axis's max velocity: a jump";
}

// ---------------------------------------------------------------- pcnc run, host killed

TEST(RtStop, PcncRunWhoseHostIsKilledMidMoveLeavesTheMachineAtRest) {
  const std::string tag = "stop-run";
  const std::string dir = make_temp_dir(tag);
  const std::string config = write_test_config(dir, tag);
  const std::string trace = dir + "/trace.csv";
  const MachineConfig m = mill_config();
  BackgroundProcess run = start_process(
      {pcnc_exe(), "run", strokes_program(dir, 20, 3000.0), "--clock", "real", "--config", config, "--trace", trace},
      dir + "/pcnc");
  Reaped guard{run};
  Status st{};
  ASSERT_TRUE(wait_rt(tag, [](const Status& s) { return s.state == MachineState::kRunning && s.path_speed > 45.0; }, 30, st))
      << run.err();
  int host = 0;
  {
    HostSegment seg(test_shm_name(tag));
    host = seg.shm().header.host_pid.load();
  }
  ASSERT_GT(host, 0);
  const auto t_kill = Clock::now();
  kill(host, SIGKILL);
  const int code = wait_for(run, 30);
  const double exit_ms = std::chrono::duration<double, std::milli>(Clock::now() - t_kill).count();
  EXPECT_EQ(code, 128 + SIGKILL) << "the host's end is the run's status\n" << run.err();
  EXPECT_EQ(run.err().find("while stopping"), std::string::npos) << "pcnc-rt ended cleanly: " << run.err();
  EXPECT_NE(run.err().find("brought the machine to rest before exiting"), std::string::npos) << run.err();
  const TraceEnd t = read_trace(trace, m);
  expect_brought_to_rest(t, 45.0);
  std::cout << "[ figures  ] pcnc run, host killed at " << t.stop_speed << " mm/s: setpoint at rest " << t.decel_s * 1e3
            << " ms after the last RUNNING row, launcher exited " << exit_ms << " ms after kill; max step " << t.max_step_ratio
            << " x vmax*dt; last state " << t.last_state << "\n";
}

// ---------------------------------------------------------------- SIGTERM to a running rt

struct Case {
  std::string clock;
  double feed;  // mm/min
  int sig;
};

class SigtermRt : public ::testing::TestWithParam<Case> {};

TEST_P(SigtermRt, ComesToRestAlongThePathThenExitsZero) {
  const Case c = GetParam();
  const std::string tag = "stop-" + c.clock + "-" + std::to_string(static_cast<int>(c.feed)) + "-" + std::to_string(c.sig);
  const std::string dir = make_temp_dir(tag);
  const std::string config = write_test_config(dir, tag);
  const std::string trace = dir + "/trace.csv";
  const MachineConfig m = mill_config();
  BackgroundProcess rt = start_process({rt_exe(), "--config", config, "--clock", c.clock, "--trace", trace}, dir + "/rt");
  BackgroundProcess host =
      start_process({host_exe(), "--config", config, "--run", strokes_program(dir, c.clock == "virtual" ? 400 : 20, c.feed)},
                    dir + "/host");
  Reaped g1{rt}, g2{host};
  const double cruise = std::min(c.feed / 60.0, m.axes[0].max_velocity_mm_s);
  Status st{};
  ASSERT_TRUE(wait_rt(tag, [&](const Status& s) { return s.state == MachineState::kRunning && s.path_speed > 0.9 * cruise; },
                      30, st))
      << rt.err() << host.err();
  const auto t_term = Clock::now();
  kill(rt.pid, c.sig);
  const int code = wait_for(rt, 20);
  const double exit_ms = std::chrono::duration<double, std::milli>(Clock::now() - t_term).count();
  EXPECT_EQ(code, 0) << rt.err();
  EXPECT_NE(rt.err().find("brought the machine to rest before exiting"), std::string::npos) << rt.err();
  EXPECT_THROW(HostSegment seg(test_shm_name(tag)), SegmentError) << "a clean exit removes the segment";
  const TraceEnd t = read_trace(trace, m);
  // On the virtual clock the rt runs ~1000x real time, so the microseconds between seeing the
  // cruise speed and the signal landing can be seconds of machine time: the signal may find
  // it slowing for a corner. It must be moving; the rest holds as for the real clock.
  expect_brought_to_rest(t, c.clock == "virtual" ? 1.0 : 0.9 * cruise);
  // At most the deceleration from the cruise speed at the configured acceleration, plus the
  // settling; under load the real clock takes longer in wall time, never in machine time.
  const double v = t.stop_speed, a = m.axes[0].max_accel_mm_s2;
  EXPECT_LT(t.decel_s, v / a + 0.005) << "decelerates at the machine's acceleration, not slower";
  std::cout << "[ figures  ] SIG" << sigabbrev_np(c.sig) << " to pcnc-rt (" << c.clock << ") at " << t.stop_speed
            << " mm/s: setpoint at rest " << t.decel_s * 1e3 << " ms after the last RUNNING row (v/a = " << v / a * 1e3
            << " ms), rt exited " << exit_ms << " ms after kill(2); max step " << t.max_step_ratio << " x vmax*dt\n";
  wait_for(host, 10);
}

INSTANTIATE_TEST_SUITE_P(Clocks, SigtermRt,
                         ::testing::Values(Case{"real", 3000.0, SIGTERM}, Case{"real", 6000.0, SIGTERM},
                                           Case{"real", 3000.0, SIGINT}, Case{"virtual", 3000.0, SIGTERM}),
                         [](const auto& info) {
                           return info.param.clock + "_F" + std::to_string(static_cast<int>(info.param.feed)) + "_" +
                                  sigabbrev_np(info.param.sig);
                         });

// ---------------------------------------------------------------- a second signal

TEST(RtStop, SignalsTogetherAreOneRequestALaterSecondEndsTheRtAtOnce) {
  const std::string tag = "stop-twice";
  const std::string dir = make_temp_dir(tag);
  // A slow stop: X and Y accelerate at 10 mm/s² (a 200th of the default), so a stop from the
  // stroke's peak speed (about 15 mm/s) takes well over a second.
  const std::string config = write_test_config(dir, tag,
                                               {{"max_accel_mm_s2 = 2000.0", "max_accel_mm_s2 = 10.0"},
                                                {"max_accel_mm_s2 = 2000.0", "max_accel_mm_s2 = 10.0"}});
  BackgroundProcess rt = start_process({rt_exe(), "--config", config, "--clock", "real"}, dir + "/rt");
  BackgroundProcess host =
      start_process({host_exe(), "--config", config, "--run", strokes_program(dir, 20, 3000.0)}, dir + "/host");
  Reaped g1{rt}, g2{host};
  Status st{};
  ASSERT_TRUE(wait_rt(tag, [](const Status& s) { return s.state == MachineState::kRunning && s.line >= 3 && s.path_speed > 8.0; }, 60, st))
      << rt.err() << host.err();
  // Two signals at once (a terminal's Ctrl-C reaching the rt and forwarded by a launcher):
  // one request; the machine decelerates.
  kill(rt.pid, SIGINT);
  kill(rt.pid, SIGTERM);
  std::this_thread::sleep_for(400ms);
  ASSERT_EQ(wait_for(rt, 0.0), -1) << "still running, bringing the machine to rest\n" << rt.err();
  ASSERT_TRUE(read_rt_status(tag, st));
  EXPECT_EQ(st.state, MachineState::kStopping) << to_string(st.state);
  EXPECT_GT(st.path_speed, 0.0);
  // A second request, later: exit at once.
  const auto t_second = Clock::now();
  kill(rt.pid, SIGTERM);
  const int code = wait_for(rt, 5);
  const double exit_ms = std::chrono::duration<double, std::milli>(Clock::now() - t_second).count();
  EXPECT_EQ(code, 128 + SIGTERM) << rt.err();
  EXPECT_LT(exit_ms, 1000.0);
  EXPECT_NE(rt.err().find("second stop signal"), std::string::npos) << rt.err();
  wait_for(host, 10);
}

}  // namespace
}  // namespace pcnc::test
