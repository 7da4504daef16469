// test_proc_scope.cpp — the scope with both real processes on the real clock: a capture
// during a running program has every cycle (consecutive machine times, each row one whole
// sample) and the program runs on to its end; the trigger sits where its condition first
// holds after the pre-trigger is full; `pcnc ctl capture` writes the CSV (header, one row per
// cycle) beside the HTML page; unknown signals, bad triggers, too long a record, a trigger
// that never comes and an output path that cannot be written are refused with their reason;
// an rt that dies during a capture ends it with error 2.
#include <gtest/gtest.h>

#include <signal.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <thread>

#include "service/rpc.hpp"
#include "service_procs.hpp"

namespace pcnc::test {
namespace {

std::vector<std::vector<std::string>> read_csv(const std::string& path, std::string& header) {
  std::ifstream in(path);
  std::vector<std::vector<std::string>> rows;
  std::getline(in, header);
  for (std::string line; std::getline(in, line);) {
    std::vector<std::string> cells;
    std::stringstream ss(line);
    for (std::string c; std::getline(ss, c, ',');) cells.push_back(c);
    rows.push_back(cells);
  }
  return rows;
}

TEST(Scope, CapturesDuringARunningProgramWithTriggerAndWithoutGaps) {
  ServicePair p("scope-run");
  ASSERT_TRUE(p.start("real")) << p.host_log();
  const std::string prog = zigzag_program(p.dir(), 4, 16.0, 600.0);  // ~8 s

  // Armed before the program starts: the trigger is the first cycle the path speed passes 2 mm/s.
  json trig;
  std::thread waiter([&] {
    trig = p.call("capture",
                  {{"signals", {"speed", "line", "cmd_x"}}, {"seconds", 0.5}, {"trigger", "speed>2"}, {"pre_trigger_percent", 10}},
                  60);
  });
  std::this_thread::sleep_for(std::chrono::milliseconds(300));  // the pre-trigger (50 ms) fills
  const json run = p.call("run", {{"file", prog}});
  waiter.join();
  ASSERT_TRUE(run.contains("result")) << run.dump();
  ASSERT_TRUE(trig.contains("result")) << trig.dump() << p.host_log();
  const json& r = trig["result"];
  ASSERT_EQ(r["rows"], 1000);
  EXPECT_EQ(r["pre_rows"], 100);
  ASSERT_EQ(r["trigger_row"], 100);
  const auto t = r["columns"]["t"].get<std::vector<double>>();
  const auto speed = r["columns"]["speed"].get<std::vector<double>>();
  ASSERT_EQ(t.size(), 1000u);
  ASSERT_EQ(speed.size(), 1000u);
  for (std::size_t i = 1; i < t.size(); ++i) ASSERT_NEAR(t[i] - t[i - 1], 0.0005, 1e-7) << "row " << i << ": a gap";
  EXPECT_GT(speed[100], 2.0) << "the condition holds at the trigger";
  const double armed = r["t_armed_s"].get<double>();
  EXPECT_LE(armed, t[0]) << "armed before the program started, so the whole pre-trigger is armed time";
  for (std::size_t i = 0; i < 100; ++i) EXPECT_LE(speed[i], 2.0) << "row " << i << " held before the trigger";
  EXPECT_GT(speed.back(), speed[100]) << "the record runs on after the trigger (accelerating)";
  EXPECT_DOUBLE_EQ(r["t_trigger_s"].get<double>(), t[100]);

  // Without a trigger, through pcnc ctl, while the program runs: one row per cycle.
  ASSERT_EQ(p.status()["state"], "RUNNING");
  const std::string html = p.dir() + "/scope.html";
  const ProcessResult c = run_process({pcnc_exe(), "ctl", "--config", p.config(), "capture", "--signals",
                                       "cmd_x,act_x,ferr_x,ferr_y", "--seconds", "1", "-o", html},
                                      60);
  ASSERT_EQ(c.exit_code, 0) << c.err << c.out;
  EXPECT_NE(c.out.find("captured 2000 cycles"), std::string::npos) << c.out;
  EXPECT_NE(c.out.find("scope.csv"), std::string::npos) << c.out;
  std::string header;
  const auto rows = read_csv(p.dir() + "/scope.csv", header);
  EXPECT_EQ(header, "t,cmd_x,act_x,ferr_x,ferr_y");
  ASSERT_EQ(rows.size(), 2000u);
  double xmin = 1e9, xmax = -1e9;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    ASSERT_EQ(rows[i].size(), 5u) << i;
    const double cmd = std::stod(rows[i][1]), act = std::stod(rows[i][2]), ferr = std::stod(rows[i][3]);
    EXPECT_NEAR(ferr, cmd - act, 2.5e-7) << "row " << i << " is one whole sample";
    xmin = std::min(xmin, cmd);
    xmax = std::max(xmax, cmd);
    if (i > 0) {
      ASSERT_NEAR(std::stod(rows[i][0]) - std::stod(rows[i - 1][0]), 0.0005, 1e-7) << "row " << i << ": a gap";
    }
  }
  EXPECT_GT(xmax - xmin, 1.0) << "the machine moved during the capture";
  std::ifstream page(html);
  const std::string text((std::istreambuf_iterator<char>(page)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("data-name=\"ferr_y\""), std::string::npos);
  EXPECT_NE(text.find("2000 cycles"), std::string::npos);

  // The program is not disturbed: it runs to its end.
  const json s = p.wait_status([](const json& x) { return x["last_job"].is_object(); }, 60);
  ASSERT_TRUE(s["last_job"].is_object()) << s.dump();
  EXPECT_EQ(s["last_job"]["end"], "completed") << s.dump();
}

TEST(Scope, RefusesBadRequestsWithTheirReason) {
  ServicePair p("scope-bad");
  ASSERT_TRUE(p.start("real")) << p.host_log();
  auto ctl = [&](std::vector<std::string> args) {
    args.insert(args.begin(), "capture");
    return p.ctl(args, 60);
  };
  const std::string out = p.dir() + "/s.html";
  ProcessResult r = ctl({"--signals", "cmd_x,ferr_q", "--seconds", "1", "-o", out});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("unknown signal 'ferr_q'"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("ferr_x"), std::string::npos) << "lists the signals: " << r.err;
  r = ctl({"--signals", "ferr_x", "--seconds", "1", "--trigger", "ferr_x>>0.005", "-o", out});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("bad trigger 'ferr_x>>0.005'"), std::string::npos) << r.err;
  r = ctl({"--signals", "ferr_x", "--seconds", "1", "--trigger", "ferr_w>0.005", "-o", out});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("unknown signal 'ferr_w'"), std::string::npos) << r.err;
  r = ctl({"--signals", "ferr_x", "--seconds", "30", "-o", out});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("at most 10 s"), std::string::npos) << r.err;
  r = ctl({"--signals", "ferr_x", "--seconds", "1", "--pre-trigger", "20", "-o", out});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("need --trigger"), std::string::npos) << r.err;
  r = ctl({"--signals", "ferr_x", "--seconds", "1", "-o", "/nonexistent/dir/s.html"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("/nonexistent/dir"), std::string::npos) << r.err;
  EXPECT_FALSE(std::ifstream(p.dir() + "/s.csv").good()) << "nothing written for a refused capture";

  // A trigger that never holds ends with the range the signal was seen in.
  const json never = p.call("capture", {{"signals", {"ferr_x"}}, {"seconds", 0.1}, {"trigger", "abs(ferr_x)>1"}, {"trigger_timeout_s", 0.5}}, 30);
  ASSERT_TRUE(never.contains("error")) << never.dump();
  EXPECT_EQ(never["error"]["code"], rpc::kRefused);
  EXPECT_NE(never["error"]["message"].get<std::string>().find("did not hold within"), std::string::npos) << never.dump();
  EXPECT_NE(never["error"]["message"].get<std::string>().find("ranged over"), std::string::npos) << never.dump();
  EXPECT_EQ(p.status()["state"], "IDLE");

  // pcnc-rt dies during a capture: error 2, at once, not a record with a hole.
  json gone;
  std::thread waiter([&] { gone = p.call("capture", {{"signals", {"ferr_x"}}, {"seconds", 5}}, 30); });
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  p.kill_rt(SIGKILL);
  waiter.join();
  ASSERT_TRUE(gone.contains("error")) << gone.dump();
  EXPECT_EQ(gone["error"]["code"], rpc::kRtUnavailable) << gone.dump();
  // "pcnc-rt was lost during the capture: ..." (or, had the request come after the kill,
  // "pcnc-rt is not available"): either way no record
  EXPECT_NE(gone["error"]["message"].get<std::string>().find("pcnc-rt"), std::string::npos) << gone.dump();
}

}  // namespace
}  // namespace pcnc::test
