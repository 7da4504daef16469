// test_proc_work_state.cpp — the work offsets set over the control socket outlive the service:
// pcnc-host --serve saves them in work_state.json in its private state directory (mode 0600)
// when set_offset changes them, reads them when it starts again (after a SIGKILL too) and runs
// programs with them; a corrupt file stops the start with a message naming it.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/stat.h>

#include <fstream>

#include "config/config.hpp"
#include "config/work_state.hpp"
#include "service_procs.hpp"
#include "test_paths.hpp"

namespace pcnc::test {
namespace {


mode_t mode_of(const std::string& path) {
  struct stat st {};
  return ::lstat(path.c_str(), &st) == 0 ? (st.st_mode & 07777) : 0;
}

TEST(ServiceWorkState, SetOffsetSurvivesARestartOfTheService) {
  ServicePair p("ws-restart");
  ASSERT_TRUE(p.start("virtual")) << p.host_log();
  const std::string state = p.dir() + "/state";
  const std::string file = state + "/work_state.json";
  EXPECT_EQ(p.status()["work_state"]["file"], file);

  ASSERT_TRUE(p.call("set_offset", {{"offset", "G55"}, {"x", 5.0}, {"y", 6.0}, {"z", 20.0}}).contains("result"));
  ASSERT_TRUE(p.call("set_offset", {{"offset", "G59.2"}, {"z", -3.0}}).contains("result"));
  EXPECT_EQ(mode_of(file), 0600u) << "the file is private";
  EXPECT_EQ(mode_of(state), 0700u) << "in the private state directory";
  const WorkState saved = load_work_state(load_config(p.config()), file);
  EXPECT_EQ(saved.g5x[1], (Vec3{5.0, 6.0, 20.0}));
  EXPECT_EQ(saved.g5x[7], (Vec3{0.0, 0.0, -3.0}));
  EXPECT_EQ(saved.g5x[0], load_config(p.config()).gcode.work_offsets[0]) << "the others keep the config's defaults";

  // Killed, not shut down: the offsets were saved when they were set.
  p.kill_host(SIGKILL);
  ASSERT_TRUE(p.start_host()) << p.host_log();
  json s = p.wait_status([](const json& x) { return x["rt"]["state"] == "attached" && x["state"] == "IDLE"; }, 20);
  ASSERT_EQ(s["state"], "IDLE") << s.dump();
  EXPECT_EQ(s["work_offsets"]["G55"]["x"], 5.0);
  EXPECT_EQ(s["work_offsets"]["G55"]["y"], 6.0);
  EXPECT_EQ(s["work_offsets"]["G55"]["z"], 20.0);
  EXPECT_EQ(s["work_offsets"]["G59.2"]["z"], -3.0);
  EXPECT_EQ(mode_of(file), 0600u);

  // A program run after the restart uses them: G55 X1 Y2 Z-1 ends at machine 5+1, 6+2, 20-1 ... X3.
  const std::string prog = write_program(p.dir(), "g55.ngc", "G21 G90\nG01 X1 Y2 Z-1 F600\nG01 X3\nM30\n");
  const json r = p.call("run", {{"file", prog}, {"work_offset", "G55"}});
  ASSERT_TRUE(r.contains("result")) << r.dump();
  s = p.wait_status([](const json& x) { return idle(x) && x["last_job"].is_object(); }, 60);
  EXPECT_EQ(s["last_job"]["end"], "completed") << s.dump();
  EXPECT_NEAR(pos(s, "commanded", 0), 8.0, 1e-6);
  EXPECT_NEAR(pos(s, "commanded", 1), 8.0, 1e-6);
  EXPECT_NEAR(pos(s, "commanded", 2), 19.0, 1e-6);
}

TEST(ServiceWorkState, ACorruptFileStopsTheStartNamingIt) {
  ServicePair p("ws-corrupt");
  const std::string state = p.dir() + "/state";
  ASSERT_EQ(::mkdir(state.c_str(), 0700), 0);
  const std::string file = state + "/work_state.json";
  std::ofstream(file) << "{\"version\": 1, \"G54\": {\"x\": 1";  // cut short
  const ProcessResult r = run_process({host_exe(), "--config", p.config(), "--serve"}, 30.0);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find(file), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("not valid JSON"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("the service does not start"), std::string::npos) << r.err;
  EXPECT_EQ(test::read_file(file), "{\"version\": 1, \"G54\": {\"x\": 1") << "the file is left for the operator to see";
}

}  // namespace
}  // namespace pcnc::test
