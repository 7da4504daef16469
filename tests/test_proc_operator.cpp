// test_proc_operator.cpp — the machinist's side of the service with both processes running:
// touch-off (G10 L20's meaning, with and without G92) saved in the work-state file and still
// there after a restart of the service; MDI through the same pipeline as programs (it moves in
// work coordinates from where the machine stands, its errors come back with line:col before
// anything moves, its G10/G92 are kept), refusals while a program runs, the plan's progress
// in status, and `pcnc ctl mdi` / `pcnc ctl touch-off`.
#include <gtest/gtest.h>
#include <signal.h>

#include <algorithm>
#include <chrono>
#include <future>
#include <thread>

#include "config/config.hpp"
#include "config/work_state.hpp"
#include "service/rpc.hpp"
#include "service_procs.hpp"
#include "test_paths.hpp"

namespace pcnc::test {
namespace {

double axis_value(const json& v, int axis) { return v[std::string(1, "xyz"[axis])].get<double>(); }

// Runs `text` as MDI and waits for its end; returns the status after it.
json mdi(ServicePair& p, const std::string& text, int* code = nullptr) {
  // The record of the job before this one: the wait below is for a new one (an earlier MDI's
  // record would otherwise satisfy it before this job has even started).
  const json before = p.status().value("last_job", json());
  const json r = p.call("mdi", {{"text", text}});
  if (code) *code = error_code(r);
  if (!r.contains("result")) return r;
  EXPECT_TRUE(r["result"]["mdi"].get<bool>()) << r.dump();
  return p.wait_status(
      [&](const json& x) {
        return idle(x) && x["last_job"].is_object() && x["last_job"]["file"] == "MDI" && x["last_job"] != before;
      },
      60);
}

TEST(ServiceOperator, TouchOffSetsTheActiveOffsetAndSurvivesARestart) {
  ServicePair p("op-touch");
  ASSERT_TRUE(p.start("virtual")) << p.host_log();
  ASSERT_TRUE(p.call("jog", {{"axis", "Z"}, {"distance", -1.5}, {"feed", 300}}).contains("result"));
  json s = p.wait_status([](const json& x) { return x["state"] == "IDLE" && std::abs(axis_value(x["commanded"], 2) - 23.5) < 1e-9; }, 20);
  ASSERT_NEAR(axis_value(s["commanded"], 2), 23.5, 1e-9) << s.dump();

  const json r = p.call("touch_off", {{"axis", "z"}, {"value", 2.0}});
  ASSERT_TRUE(r.contains("result")) << r.dump();
  EXPECT_EQ(r["result"]["offset"], "G54");
  EXPECT_NEAR(r["result"]["z"].get<double>(), 21.5, 1e-9) << "offset = machine 23.5 - value 2";
  EXPECT_NEAR(axis_value(r["result"]["work_position"], 2), 2.0, 1e-9);
  s = p.status();
  EXPECT_NEAR(axis_value(s["work_offsets"]["G54"], 2), 21.5, 1e-9);
  EXPECT_NEAR(axis_value(s["work_offsets"]["G54"], 0), 12.5, 1e-9) << "the other axes keep their offset";
  EXPECT_NEAR(axis_value(s["work_position"]["commanded"], 2), 2.0, 1e-9) << s.dump();

  EXPECT_EQ(error_code(p.call("touch_off", {{"axis", "A"}, {"value", 0}})), rpc::kInvalidParams);
  EXPECT_EQ(error_code(p.call("touch_off", {{"axis", "X"}})), rpc::kInvalidParams);
  EXPECT_EQ(error_code(p.call("touch_off", {{"axis", "X"}, {"value", "0"}})), rpc::kInvalidParams);

  // Saved at once: a restarted service (killed, not shut down) reads it back.
  const WorkState saved = load_work_state(load_config(p.config()), p.dir() + "/state/work_state.json");
  EXPECT_NEAR(saved.g5x[0][2], 21.5, 1e-9);
  p.kill_host(SIGKILL);
  ASSERT_TRUE(p.start_host()) << p.host_log();
  s = p.wait_status([](const json& x) { return x["rt"]["state"] == "attached" && x["state"] == "IDLE"; }, 20);
  ASSERT_EQ(s["state"], "IDLE") << s.dump();
  EXPECT_NEAR(axis_value(s["work_offsets"]["G54"], 2), 21.5, 1e-9) << s.dump();
  EXPECT_NEAR(axis_value(s["work_position"]["commanded"], 2), 2.0, 1e-9) << s.dump();

  // A program run afterwards uses it: Z0 is 2 mm below where the touch-off was made.
  const std::string prog = write_program(p.dir(), "z0.ngc", "G21 G90\nG01 Z0 F300\nM30\n");
  ASSERT_TRUE(p.call("run", {{"file", prog}}).contains("result"));
  s = p.wait_status([](const json& x) { return idle(x) && x["last_job"].is_object(); }, 60);
  EXPECT_EQ(s["last_job"]["end"], "completed") << s.dump();
  EXPECT_NEAR(axis_value(s["commanded"], 2), 21.5, 1e-6);
}

TEST(ServiceOperator, MdiRunsThroughThePipelineAndKeepsItsOffsets) {
  ServicePair p("op-mdi");
  ASSERT_TRUE(p.start("virtual")) << p.host_log();
  // G54 is (12.5, 12.5, 25): X5 in work coordinates is machine 17.5.
  json s = mdi(p, "G1 X5 F300");
  EXPECT_EQ(s["last_job"]["end"], "completed") << s.dump();
  EXPECT_NEAR(axis_value(s["commanded"], 0), 17.5, 1e-6);
  EXPECT_NEAR(axis_value(s["work_position"]["commanded"], 0), 5.0, 1e-6);

  // Several lines, relative moves from where the machine stands.
  s = mdi(p, "G91\nG1 Y-2 F600\nG1 Z-0.5\n");
  EXPECT_EQ(s["last_job"]["end"], "completed") << s.dump();
  EXPECT_NEAR(axis_value(s["commanded"], 1), 10.5, 1e-6);
  EXPECT_NEAR(axis_value(s["commanded"], 2), 24.5, 1e-6);

  // Checked whole before anything moves: an error on line 2 is reported with line:col and the
  // good first line did not run.
  int code = 0;
  const json e = mdi(p, "G90 G1 X0 F300\nG1 X2 Q7\n", &code);
  EXPECT_EQ(code, rpc::kPreflightFailed) << e.dump();
  ASSERT_TRUE(e["error"]["data"]["errors"].is_array()) << e.dump();
  EXPECT_EQ(e["error"]["data"]["errors"][0].get<std::string>().rfind("mdi:2:", 0), 0u) << e.dump();
  EXPECT_NEAR(axis_value(p.status()["commanded"], 0), 17.5, 1e-6) << "nothing moved";
  // Outside the travel: refused too (the preflight's soft limits).
  EXPECT_EQ(error_code(p.call("mdi", {{"text", "G90 G1 X100 F300"}})), rpc::kPreflightFailed);
  EXPECT_EQ(error_code(p.call("mdi", {{"text", " \n"}})), rpc::kInvalidParams);
  EXPECT_EQ(error_code(p.call("mdi", {{"text", 5}})), rpc::kInvalidParams);

  // G10 and G92 made by MDI are kept: in status and in the file.
  s = mdi(p, "G10 L2 P2 X1 Y2 Z3");
  EXPECT_EQ(s["last_job"]["end"], "completed") << s.dump();
  EXPECT_NEAR(axis_value(s["work_offsets"]["G55"], 0), 1.0, 1e-9) << s.dump();
  EXPECT_NEAR(axis_value(s["work_offsets"]["G55"], 2), 3.0, 1e-9) << s.dump();
  s = mdi(p, "G92 X0");  // machine X 17.5 reads 0: G92 X = 5
  EXPECT_TRUE(s["work_state"]["G92_applied"].get<bool>()) << s.dump();
  EXPECT_NEAR(axis_value(s["work_state"]["G92"], 0), 5.0, 1e-9) << s.dump();
  EXPECT_NEAR(axis_value(s["work_position"]["commanded"], 0), 0.0, 1e-9) << s.dump();
  const WorkState saved = load_work_state(load_config(p.config()), p.dir() + "/state/work_state.json");
  EXPECT_EQ(saved.g5x[1], (Vec3{1.0, 2.0, 3.0}));
  EXPECT_TRUE(saved.g92_applied);

  // Touch-off with G92 applied: offset = machine - G92 - value = 17.5 - 5 - 1.
  const json t = p.call("touch_off", {{"axis", "X"}, {"value", 1.0}});
  ASSERT_TRUE(t.contains("result")) << t.dump();
  EXPECT_NEAR(t["result"]["x"].get<double>(), 11.5, 1e-9);
  EXPECT_NEAR(axis_value(p.status()["work_position"]["commanded"], 0), 1.0, 1e-9);
}

TEST(ServiceOperator, TheToolMdiLoadedIsInStatusAndTouchOffMeasuresItsTip) {
  ServicePair p("op-tool", {{"tool_table = \"\"", "tool_table = \"" + source_dir() + "/configs/desktop-mill.tbl\""}});
  ASSERT_TRUE(p.start("virtual")) << p.host_log();
  json s = p.status();
  EXPECT_EQ(s["work_state"]["tool"], 0) << "no tool at first";
  EXPECT_FALSE(s["work_state"]["tool_offset_applied"].get<bool>());
  // T2 (Z +4.25 in the table) with its length offset, by MDI: kept for what follows.
  s = mdi(p, "T2 M6 G43");
  ASSERT_EQ(s["last_job"]["end"], "completed") << s.dump();
  EXPECT_EQ(s["work_state"]["tool"], 2) << s.dump();
  EXPECT_TRUE(s["work_state"]["tool_offset_applied"].get<bool>());
  EXPECT_NEAR(axis_value(s["work_state"]["tool_offset"], 2), 4.25, 1e-9);
  const double machine_z = axis_value(s["commanded"], 2);
  EXPECT_NEAR(axis_value(s["work_position"]["commanded"], 2), machine_z - 25.0 - 4.25, 1e-9) << "the tip, not the spindle";
  // Touch-off Z 0 with T2 in: G54 Z = machine - 4.25, and Z0 then brings the same tip back there.
  const json t = p.call("touch_off", {{"axis", "Z"}, {"value", 0.0}});
  ASSERT_TRUE(t.contains("result")) << t.dump();
  EXPECT_NEAR(t["result"]["z"].get<double>(), machine_z - 4.25, 1e-9);
  EXPECT_NEAR(axis_value(t["result"]["work_position"], 2), 0.0, 1e-9);
  s = mdi(p, "G91 G1 Z-1 F300\nG90 G1 Z0\n");
  ASSERT_EQ(s["last_job"]["end"], "completed") << s.dump();
  EXPECT_NEAR(axis_value(s["commanded"], 2), machine_z, 1e-6) << "a program's Z0 is the touched-off tip";
  // G49 by MDI: the offset is off, the tool stays in the spindle.
  s = mdi(p, "G49");
  EXPECT_EQ(s["work_state"]["tool"], 2);
  EXPECT_FALSE(s["work_state"]["tool_offset_applied"].get<bool>());
  const WorkState saved = load_work_state(load_config(p.config()), p.dir() + "/state/work_state.json");
  EXPECT_EQ(saved.tool, 2);
  EXPECT_FALSE(saved.tool_offset_applied);
}

TEST(ServiceOperator, MdiAndTouchOffAreRefusedWhileAProgramRunsAndStatusHasThePlan) {
  ServicePair p("op-busy");
  ASSERT_TRUE(p.start("real")) << p.host_log();
  const std::string prog = zigzag_program(p.dir(), 6, 16.0, 600.0);  // ~20 s at F600
  const json r = p.call("run", {{"file", prog}});
  ASSERT_TRUE(r.contains("result")) << r.dump();
  const double planned = r["result"]["planned_time_s"].get<double>();
  EXPECT_GT(planned, 10.0) << r.dump();
  json s = p.wait_status([](const json& x) { return x["state"] == "RUNNING" && x["job"].value("planned_done_s", 0.0) > 0.0; }, 20);
  ASSERT_EQ(s["state"], "RUNNING") << s.dump();
  EXPECT_DOUBLE_EQ(s["job"]["planned_time_s"].get<double>(), planned);
  EXPECT_LT(s["job"]["planned_done_s"].get<double>(), planned);

  EXPECT_EQ(error_code(p.call("mdi", {{"text", "G1 X1 F300"}})), rpc::kRefused);
  EXPECT_EQ(error_code(p.call("touch_off", {{"axis", "Z"}, {"value", 0}})), rpc::kRefused);
  ASSERT_TRUE(p.call("pause").contains("result"));
  p.wait_status([](const json& x) { return x["state"] == "PAUSED"; }, 10);
  EXPECT_EQ(error_code(p.call("mdi", {{"text", "G1 X1 F300"}})), rpc::kRefused) << "not while paused either";
  ASSERT_TRUE(p.call("stop").contains("result"));
  s = p.wait_status([](const json& x) { return idle(x) && x["last_job"].is_object(); }, 20);
  EXPECT_EQ(s["state"], "IDLE");
}

// While the service checks a long program, status shows how far the check has got, and `stop`
// ends the check there: the run is refused with that reason and nothing moves.
TEST(ServiceOperator, StopDuringTheCheckOfALongProgramEndsItAndNothingMoves) {
  ServicePair p("op-check");
  ASSERT_TRUE(p.start("virtual")) << p.host_log();
  const json before = p.status();
  const std::string prog = loop_program(p.dir(), "long-check.ngc", 3000000);  // nine million lines run
  auto run = std::async(std::launch::async, [&] { return p.call("run", {{"file", prog}}, 120); });
  const json s = p.wait_status([](const json& x) { return x["job"].contains("check_line"); }, 60);
  ASSERT_TRUE(s["job"].contains("check_line")) << s.dump();
  EXPECT_EQ(s["job"]["phase"], "preflight");
  EXPECT_EQ(s["job"]["check_pass"], "check");
  EXPECT_GT(s["job"]["check_line"].get<int>(), 0);
  const double f = s["job"]["check_fraction"].get<double>();
  EXPECT_GT(f, 0.0);
  EXPECT_LE(f, 1.0);
  EXPECT_EQ(s["state"], "IDLE") << "nothing moves during the check";

  const json stop = p.call("stop");
  ASSERT_TRUE(stop.contains("result")) << stop.dump();
  const json reply = run.get();
  ASSERT_EQ(error_code(reply), rpc::kRefused) << reply.dump();
  EXPECT_NE(reply["error"]["message"].get<std::string>().find("stopped during the preflight check; nothing was moved"),
            std::string::npos)
      << reply.dump();
  const json after = p.wait_status([](const json& x) { return idle(x); }, 10);
  EXPECT_TRUE(idle(after)) << after.dump();
  EXPECT_EQ(after["last_job"], before["last_job"]) << "no job ran";
  for (int a = 0; a < 3; ++a) EXPECT_EQ(axis_value(after["commanded"], a), axis_value(before["commanded"], a));
  EXPECT_EQ(after["blocks_done"], before["blocks_done"]);
}

// A host lost during a long program, a new host asked to resume it, and `stop` while the resume
// still checks the program: the resume ends there (its reply says so), the program is abandoned
// (no journal left to resume), the machine leaves HOST_LOST for IDLE and does not move, then or later.
TEST(ServiceOperator, StopInHostLostEndsAResumeStillBeingChecked) {
  ServicePair p("op-resume-stop");
  ASSERT_TRUE(p.start("virtual")) << p.host_log();
  // its check lasts a second or two (under a sanitizer, which runs it several times slower, fewer lines)
  const std::string prog = loop_program(p.dir(), "long-resume.ngc", sanitizer_build() ? 100000 : 600000);
  auto run = std::async(std::launch::async, [&] { return p.call("run", {{"file", prog}}, 300); });
  json s = p.wait_status([](const json& x) { return x["state"] == "RUNNING" && x["blocks_done"].get<std::uint64_t>() > 50; }, 240);
  ASSERT_EQ(s["state"], "RUNNING") << s.dump() << p.host_log();
  p.kill_host(SIGKILL);
  run.wait();
  const Status lost = wait_rt_state(p.tag(), MachineState::kHostLost);
  ASSERT_EQ(lost.state, MachineState::kHostLost);
  ASSERT_TRUE(p.start_host()) << p.host_log();
  s = p.wait_status([](const json& x) { return x["rt"]["state"] == "attached"; }, 10);
  ASSERT_EQ(s["state"], "HOST_LOST") << s.dump();
  ASSERT_TRUE(s["resume"].is_object()) << "the journal names the program: " << s.dump();

  auto resume = std::async(std::launch::async, [&] { return p.call("resume", json::object(), 300); });
  s = p.wait_status([](const json& x) { return x["job"].contains("check_line"); }, 120);
  ASSERT_TRUE(s["job"].contains("check_line")) << s.dump();
  EXPECT_EQ(s["job"]["phase"], "preflight");
  EXPECT_EQ(s["state"], "HOST_LOST") << "nothing moves while the resume checks";
  const json stop = p.call("stop");
  ASSERT_TRUE(stop.contains("result")) << stop.dump();
  EXPECT_EQ(stop["result"]["state"], "IDLE") << stop.dump();
  const json reply = resume.get();
  ASSERT_EQ(error_code(reply), rpc::kRefused) << reply.dump();
  EXPECT_NE(reply["error"]["message"].get<std::string>().find("resume stopped during the preflight check; the program was abandoned"),
            std::string::npos)
      << reply.dump();

  const json after = p.wait_status([](const json& x) { return idle(x); }, 10);
  ASSERT_TRUE(idle(after)) << after.dump();
  EXPECT_TRUE(after["resume"].is_null()) << "nothing left to resume: " << after.dump();
  for (int a = 0; a < 3; ++a) EXPECT_EQ(axis_value(after["commanded"], a), lost.commanded[static_cast<std::size_t>(a)]);
  // and it stays there: the abandoned resume never starts the rest of the program
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  const json later = p.status();
  EXPECT_EQ(later["state"], "IDLE") << later.dump();
  EXPECT_EQ(later["commanded"], after["commanded"]);
  EXPECT_EQ(later["blocks_done"], after["blocks_done"]);
}

TEST(ServiceOperator, CtlMdiAndTouchOff) {
  ServicePair p("op-ctl");
  ASSERT_TRUE(p.start("virtual")) << p.host_log();
  auto ctl = [&](const std::vector<std::string>& args) { return p.ctl(args); };
  ProcessResult r = ctl({"mdi", "G1 X2 F300", "G1 Y3"});
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("MDI completed"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("X    2.0000  Y    3.0000"), std::string::npos) << "ends at work X2 Y3: " << r.out;

  r = ctl({"mdi", "G1 X2 Q7"});
  EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
  EXPECT_NE(r.err.find("mdi:1:"), std::string::npos) << r.err;

  r = ctl({"touch-off", "Y", "0"});
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("G54"), std::string::npos) << r.out;
  EXPECT_NEAR(axis_value(p.status()["work_offsets"]["G54"], 1), 15.5, 1e-9);
  EXPECT_NEAR(axis_value(p.status()["work_position"]["commanded"], 1), 0.0, 1e-9);

  r = ctl({"touch-off", "W", "0"});
  EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
}

// Piped (stdout is a file here), --watch prints plain lines, one per status push, with the
// work coordinates and the active offset; no terminal control sequences. Ctrl-C ends it with 0.
TEST(ServiceOperator, StatusWatchPipedPrintsPlainLines) {
  ServicePair p("op-watch");
  ASSERT_TRUE(p.start("virtual")) << p.host_log();
  ASSERT_TRUE(p.call("touch_off", {{"axis", "X"}, {"value", 3.0}}).contains("result"));
  BackgroundProcess w =
      start_process({pcnc_exe(), "ctl", "--config", p.config(), "status", "--watch", "--rate", "20"}, p.dir() + "/watch");
  Reaped reap{w};
  auto lines_seen = [&] {
    const std::string out = w.out();
    return std::count(out.begin(), out.end(), '\n');
  };
  for (int i = 0; i < 1000 && lines_seen() < 3; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  ASSERT_GE(lines_seen(), 3) << w.out() << w.err();
  ::kill(w.pid, SIGINT);
  EXPECT_EQ(wait_for(w, 10), 0) << w.err();
  const std::string out = w.out();
  EXPECT_EQ(out.find('\x1b'), std::string::npos) << "no escape sequences when piped: " << out;
  const std::string first = out.substr(0, out.find('\n'));
  EXPECT_EQ(first.rfind("IDLE", 0), 0u) << first;
  EXPECT_NE(first.find("X   12.5000"), std::string::npos) << "machine X: " << first;
  EXPECT_NE(first.find("work G54 X    3.0000"), std::string::npos) << "work X after the touch-off: " << first;
}

}  // namespace
}  // namespace pcnc::test
