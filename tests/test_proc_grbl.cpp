// test_proc_grbl.cpp — `pcnc grbl` as a G-code sender sees it: the real processes, the
// pseudo-terminal opened raw, grbl 1.1's protocol (docs/grbl-protocol.md). Streaming by
// character counting runs the same moves as `pcnc run` of the same file; status reports
// during motion; hold and resume; overrides; jog and jog cancel; errors and check mode; a
// soft reset during motion stops under control; an e-stop is an alarm until $X; Ctrl-C ends
// the command with 0 and removes its link. Timeouts only guard against hangs.
#include <gtest/gtest.h>
#include <signal.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "ctl.hpp"
#include "ipc/segment.hpp"
#include "grbl_sender.hpp"
#include "service_procs.hpp"
#include "subprocess.hpp"
#include "test_paths.hpp"

namespace pcnc::test {
namespace {

using json = nlohmann::json;


// One `pcnc grbl` on its own test config, and a sender on its port that has read the banner.
struct GrblFixture {
  std::string tag, dir, config;
  std::unique_ptr<GrblProcess> grbl;
  std::unique_ptr<GrblSender> port;

  explicit GrblFixture(const std::string& t, const std::string& base_config = "") : tag(t), dir(make_temp_dir(t)) {
    config = base_config.empty() ? write_test_config(dir, tag) : base_config;
    grbl = start_grbl(config, dir);
    port = std::make_unique<GrblSender>(grbl->link);
  }
  bool banner() {
    auto lines = port->read_until([](const std::string& l) { return l.rfind("Grbl 1.1h", 0) == 0; }, 30.0);
    return lines.has_value();
  }
  json service_status() {
    CtlClient c(dir + "/pcnc.sock");
    return c.call("status")["result"];
  }
  ~GrblFixture() { remove_segment(test_shm_name(tag)); }
};

TEST(ProcGrbl, BannerStatusSettingsAndReports) {
  GrblFixture f("grbl-basic");
  ASSERT_TRUE(f.port->is_open()) << f.grbl->proc.err();
  ASSERT_TRUE(f.banner()) << f.grbl->proc.err();
  auto st = f.port->status();
  ASSERT_TRUE(st);
  EXPECT_EQ(st->state, "Idle") << st->raw;  // no homing lock: the simulated mill knows its position
  EXPECT_DOUBLE_EQ(st->mpos[0], 12.5);
  EXPECT_EQ(st->ov_feed, 100);
  EXPECT_TRUE(st->has_wco) << st->raw;

  auto info = f.port->command("$I");
  EXPECT_EQ(info.back(), "ok");
  EXPECT_NE(info.front().find("[VER:1.1h"), std::string::npos);
  auto settings = f.port->command("$$");
  EXPECT_EQ(settings.back(), "ok");
  EXPECT_NE(std::find(settings.begin(), settings.end(), "$110=6000.000"), settings.end()) << "X max rate from the config";
  EXPECT_NE(std::find(settings.begin(), settings.end(), "$130=25.000"), settings.end()) << "X travel from the config";
  EXPECT_EQ(f.port->command("$110=6000").back(), "ok") << "writing the value a setting has is accepted";
  EXPECT_EQ(f.port->command("$110=9000").back(), "error:5") << "settings are the config's: read-only";
  EXPECT_EQ(f.port->command("$999=1").back(), "error:3");
  auto params = f.port->command("$#");
  EXPECT_EQ(params.front(), "[G54:12.500,12.500,25.000]");
  auto gc = f.port->command("$G");
  EXPECT_EQ(gc.front().rfind("[GC:", 0), 0u);
  EXPECT_EQ(f.port->command("").back(), "ok");
}

TEST(ProcGrbl, StreamingByCharacterCountingRunsTheSameMovesAsPcncRun) {
  GrblFixture f("grbl-stream");
  ASSERT_TRUE(f.banner()) << f.grbl->proc.err();
  const std::string program = zigzag_program(f.dir, 9, 16.0, 1500.0);
  std::vector<GrblStatus> reports;
  const auto answers = f.port->stream(read_lines(program), &reports, 3);
  ASSERT_EQ(answers.size(), read_lines(program).size());
  for (const auto& a : answers) EXPECT_EQ(a, "ok");
  // status reports during the motion: running, between the start and the end
  bool saw_run = false;
  for (const auto& r : reports) saw_run |= r.state == "Run" && r.feed > 0.0;
  EXPECT_TRUE(saw_run) << reports.size() << " reports";
  auto idle = f.port->wait_status([](const GrblStatus& s) { return s.state == "Idle"; });
  ASSERT_TRUE(idle && idle->state == "Idle");
  // The program ended itself (M30): the stream's record is the last job.
  const json st = f.service_status();
  const json& last = st["last_job"];
  ASSERT_TRUE(last.is_object()) << st.dump();
  EXPECT_EQ(last["file"], "stream");
  EXPECT_EQ(last["end"], "completed") << last.dump();

  // pcnc run of the same file on the same machine: the same blocks, the same end point
  const std::string summary = f.dir + "/run.json";
  const std::string run_dir = make_temp_dir("grbl-stream-run");
  const std::string run_config = write_test_config(run_dir, "grbl-stream-run");
  auto r = run_process({pcnc_exe(), "run", program, "--config", run_config, "--clock", "virtual", "--summary", summary, "-q"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::ifstream in(summary);
  const json s = json::parse(in);
  EXPECT_EQ(last["blocks_sent"], s["job"]["blocks_sent"]);
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(last["final_position"][std::string(1, "xyz"[i])].get<double>(), s["status"]["commanded"][i].get<double>(), 1e-9);
  }
  remove_segment(test_shm_name("grbl-stream-run"));
}

TEST(ProcGrbl, SubroutineCalledOnceItsDefinitionArrivedAndErrors) {
  GrblFixture f("grbl-sub");
  ASSERT_TRUE(f.banner());
  const std::vector<std::string> lines = {"G21 G90", "o100 sub", "G91 G1 X1 F600", "o100 endsub", "o100 call", "o100 call", "G90"};
  for (const auto& a : f.port->stream(lines)) EXPECT_EQ(a, "ok");
  auto idle = f.port->wait_status([](const GrblStatus& s) { return s.state == "Idle"; });
  ASSERT_TRUE(idle);
  EXPECT_NEAR(idle->mpos[0], 14.5, 1e-3) << "two calls of a 1 mm move";
  // an error: error:N, then the message; the next line runs
  auto bad = f.port->command("G1 Q7");
  ASSERT_GE(bad.size(), 1u);
  EXPECT_EQ(bad.back(), "error:36");
  auto msg = f.port->read_line(5.0);
  ASSERT_TRUE(msg);
  EXPECT_EQ(msg->rfind("[MSG:", 0), 0u) << *msg;
  EXPECT_EQ(f.port->command("G1 X20 F600").back(), "error:33") << "outside the travel: refused before it moves";
  f.port->read_line(5.0);  // its message
  EXPECT_EQ(f.port->command("G1 X12 F600").back(), "ok") << "a new stream: G90 again";
  idle = f.port->wait_status([](const GrblStatus& s) { return s.state == "Idle"; });
  ASSERT_TRUE(idle);
  EXPECT_NEAR(idle->mpos[0], 12.0 + 12.5, 1e-3);
}

TEST(ProcGrbl, CheckModeChecksWithoutMotion) {
  GrblFixture f("grbl-check");
  ASSERT_TRUE(f.banner());
  auto on = f.port->command("$C");
  EXPECT_EQ(on.front(), "[MSG:Enabled]");
  EXPECT_EQ(on.back(), "ok");
  EXPECT_EQ(f.port->command("G1 X5 F600").back(), "ok");
  EXPECT_EQ(f.port->command("G1 X50").back(), "error:33");
  f.port->read_line(5.0);
  auto st = f.port->status();
  ASSERT_TRUE(st);
  EXPECT_EQ(st->state, "Check");
  EXPECT_DOUBLE_EQ(st->mpos[0], 12.5) << "check mode moves nothing";
  EXPECT_EQ(f.port->command("$H").back(), "error:8");
  auto off = f.port->command("$C");
  EXPECT_EQ(off.front(), "[MSG:Disabled]");
  EXPECT_TRUE(f.port->read_until([](const std::string& l) { return l.rfind("Grbl 1.1h", 0) == 0; }, 10.0));
}

TEST(ProcGrbl, HoldResumeAndOverrides) {
  GrblFixture f("grbl-hold");
  ASSERT_TRUE(f.banner());
  EXPECT_EQ(f.port->command("G21 G90").back(), "ok");
  EXPECT_EQ(f.port->command("G1 X-10 F300").back(), "ok");  // 10 mm at 5 mm/s
  auto run = f.port->wait_status([](const GrblStatus& s) { return s.state == "Run" && s.feed > 0.0; });
  ASSERT_TRUE(run && run->state == "Run") << (run ? run->raw : "");
  f.port->send_byte(0x91);  // feed +10 %
  auto ov = f.port->wait_status([](const GrblStatus& s) { return s.ov_feed == 110; });
  ASSERT_TRUE(ov && ov->ov_feed == 110);
  f.port->send_byte(0x92);
  f.port->send_byte(0x92);
  ov = f.port->wait_status([](const GrblStatus& s) { return s.ov_feed == 90; });
  ASSERT_TRUE(ov && ov->ov_feed == 90);
  f.port->send_byte('!');
  auto held = f.port->wait_status([](const GrblStatus& s) { return s.state == "Hold:0"; });
  ASSERT_TRUE(held && held->state == "Hold:0") << (held ? held->raw : "");
  const double at = held->mpos[0];
  EXPECT_GT(at, 2.5);
  EXPECT_LT(at, 12.5) << "held on the way";
  f.port->send_byte('~');
  auto idle = f.port->wait_status([](const GrblStatus& s) { return s.state == "Idle"; });
  ASSERT_TRUE(idle);
  EXPECT_NEAR(idle->mpos[0], 2.5, 1e-3) << "resumed to the end of the move";
  f.port->send_byte(0x90);
  ov = f.port->wait_status([](const GrblStatus& s) { return s.ov_feed == 100; });
  EXPECT_TRUE(ov && ov->ov_feed == 100);
}

TEST(ProcGrbl, JogAndJogCancel) {
  GrblFixture f("grbl-jog");
  ASSERT_TRUE(f.banner());
  EXPECT_EQ(f.port->command("$J=G91 X1").back(), "error:16") << "a jog needs F";
  EXPECT_EQ(f.port->command("$J=G91 X100 F600").back(), "error:15") << "beyond the travel";
  f.port->read_line(5.0);
  EXPECT_EQ(f.port->command("$J=G91 X1 F600").back(), "ok");
  auto idle = f.port->wait_status([](const GrblStatus& s) { return s.state == "Idle"; });
  ASSERT_TRUE(idle);
  EXPECT_NEAR(idle->mpos[0], 13.5, 1e-3);
  EXPECT_EQ(f.port->command("$J=G91 Y-10 F120").back(), "ok");  // 5 s
  auto jog = f.port->wait_status([](const GrblStatus& s) { return s.state == "Jog" && s.mpos[1] < 12.4; });
  ASSERT_TRUE(jog && jog->state == "Jog") << (jog ? jog->raw : "");
  f.port->send_byte(0x85);
  idle = f.port->wait_status([](const GrblStatus& s) { return s.state == "Idle"; });
  ASSERT_TRUE(idle && idle->state == "Idle");
  EXPECT_GT(idle->mpos[1], 2.5) << "cancelled before its end";
  const json st = f.service_status();
  EXPECT_EQ(st["state"], "IDLE");
  EXPECT_EQ(st["fault"], "none");
}

TEST(ProcGrbl, SoftResetDuringMotionStopsUnderControl) {
  GrblFixture f("grbl-reset");
  ASSERT_TRUE(f.banner());
  EXPECT_EQ(f.port->command("G21 G90").back(), "ok");
  EXPECT_EQ(f.port->command("G1 X10 F600").back(), "ok");
  EXPECT_EQ(f.port->command("G1 X-10").back(), "ok");
  auto run = f.port->wait_status([](const GrblStatus& s) { return s.state == "Run" && s.feed > 0.0; });
  ASSERT_TRUE(run && run->state == "Run");
  f.port->send_byte(0x18);
  EXPECT_TRUE(f.port->read_until([](const std::string& l) { return l.rfind("Grbl 1.1h", 0) == 0; }, 20.0));
  auto st = f.port->status();
  ASSERT_TRUE(st);
  EXPECT_EQ(st->state, "Idle") << st->raw;
  const json s = f.service_status();
  EXPECT_EQ(s["state"], "IDLE") << "stopped along the path, no fault";
  EXPECT_EQ(s["fault"], "none");
  EXPECT_NE(s["last_job"]["end"], "completed") << s["last_job"].dump();
  EXPECT_EQ(f.port->command("G1 X0").back(), "error:22") << "a new stream after the reset: no feed rate yet";
  f.port->read_line(5.0);
}

TEST(ProcGrbl, EstopIsAnAlarmUntilUnlock) {
  GrblFixture f("grbl-alarm");
  ASSERT_TRUE(f.banner());
  {
    CtlClient c(f.dir + "/pcnc.sock");
    ASSERT_TRUE(c.call("estop").contains("result"));
  }
  auto alarm = f.port->read_until([](const std::string& l) { return l.rfind("ALARM:", 0) == 0; }, 10.0);
  ASSERT_TRUE(alarm);
  EXPECT_EQ(alarm->back(), "ALARM:3");
  auto st = f.port->status();
  ASSERT_TRUE(st);
  EXPECT_EQ(st->state, "Alarm");
  EXPECT_EQ(f.port->command("G1 X1 F100").back(), "error:9") << "G-code is locked out during an alarm";
  auto unlock = f.port->command("$X");
  EXPECT_EQ(unlock.back(), "ok");
  st = f.port->wait_status([](const GrblStatus& s) { return s.state == "Idle"; }, 10.0);
  ASSERT_TRUE(st && st->state == "Idle");
}

TEST(ProcGrbl, CtrlCEndsWithZeroAndRemovesTheLink) {
  GrblFixture f("grbl-exit");
  ASSERT_TRUE(f.banner());
  ASSERT_TRUE(std::filesystem::is_symlink(f.grbl->link));
  f.port.reset();
  kill(f.grbl->proc.pid, SIGINT);
  EXPECT_EQ(f.grbl->proc.wait(20.0), 0) << f.grbl->proc.err();
  f.grbl->proc.pid = -1;
  EXPECT_FALSE(std::filesystem::exists(std::filesystem::symlink_status(f.grbl->link)));
}

}  // namespace
}  // namespace pcnc::test
