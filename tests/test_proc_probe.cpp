// test_proc_probe.cpp — probing on the two real processes (pcnc run: pcnc-rt + pcnc-host) on the
// default machine's flat workpiece (configs/desktop-mill.toml: its top at machine Z 15, program
// Z -10; a 1 mm ball): G38.2 stops on it, #5063 read back by the following lines moves the
// machine, the probe log holds the point; a G38.2 that misses ends the run with file:line:col.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <regex>
#include <string>

#include <unistd.h>

#include <thread>

#include "config/config.hpp"
#include "service_procs.hpp"
#include "subprocess.hpp"
#include "test_paths.hpp"

namespace pcnc::test {
namespace {


TEST(ProcProbe, G38_2OnTheFlatWorkpieceAndReadingTheResultBack) {
  const std::string dir = make_temp_dir("probe");
  const std::string config = write_test_config(dir, "probe");
  const MachineConfig c = load_config(config);
  const std::string prog = dir + "/probe.ngc";
  std::ofstream(prog) << "(PROBEOPEN probe-log.txt)\n"
                         "G21 G90 G54 F50\n"
                         "G0 X2 Y3 Z-5\n"
                         "G38.2 Z-15\n"
                         "(PRINT,probed z=#5063 ok=#5070)\n"
                         "G0 Z[#5063 + 3]\n"
                         "(PROBECLOSE)\n"
                         "M2\n";
  const ProcessResult check = run_process({pcnc_exe(), "check", prog, "--config", config});
  ASSERT_EQ(check.exit_code, 0) << check.err;
  EXPECT_NE(check.out.find("probing: 1 probing move (first at line 4): the rest checked assuming contact"), std::string::npos)
      << check.out;

  const ProcessResult r = run_process({pcnc_exe(), "run", prog, "--clock", "virtual", "--config", config}, 120);
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  // where the ball centre triggers: R minus the axial pre-travel above the top, program Z
  const double top = c.table.z_mm - c.gcode.work_offsets[0][2];
  const double expected = top + c.probe.model.ball_radius_mm - c.probe.model.pretravel_axial_mm;
  std::smatch m;
  const std::regex printed(R"(probed z=(-?[0-9.]+) ok=([0-9.]+))");
  // the check before the run prints the value it assumed (the commanded end); the run the real one
  double z = 0.0, ok = 0.0;
  int prints = 0;
  for (auto it = std::sregex_iterator(r.err.begin(), r.err.end(), printed); it != std::sregex_iterator(); ++it, ++prints) {
    z = std::stod((*it)[1]);
    ok = std::stod((*it)[2]);
  }
  ASSERT_EQ(prints, 2) << r.err;
  EXPECT_NEAR(z, expected, 6 * c.probe.model.repeatability_mm + 0.001) << r.err;
  EXPECT_NE(z, -15.0) << "not the commanded end";
  EXPECT_EQ(ok, 1.0);
  // the line after the probe moved to #5063 + 3
  const std::regex final_pos(R"(program X(-?[0-9.]+) Y(-?[0-9.]+) Z(-?[0-9.]+))");
  ASSERT_TRUE(std::regex_search(r.out, m, final_pos)) << r.out;
  EXPECT_NEAR(std::stod(m[1]), 2.0, 1e-3);
  EXPECT_NEAR(std::stod(m[3]), z + 3.0, 2e-3) << r.out;
  // the probe log: LinuxCNC's nine numbers, the probed point in work coordinates
  const std::string log = read_file(dir + "/probe-log.txt");
  double v[9];
  ASSERT_EQ(std::sscanf(log.c_str(), "%lf %lf %lf %lf %lf %lf %lf %lf %lf", &v[0], &v[1], &v[2], &v[3], &v[4], &v[5], &v[6],
                        &v[7], &v[8]),
            9)
      << log;
  EXPECT_NEAR(v[0], 2.0, 1e-6);
  EXPECT_NEAR(v[1], 3.0, 1e-6);
  EXPECT_NEAR(v[2], z, 1e-4) << "the log and #5063 agree";
  EXPECT_EQ(std::count(log.begin(), log.end(), '\n'), 1);
}

TEST(ProcProbe, AG38_2ThatMissesStopsTheRunAtItsLine) {
  const std::string dir = make_temp_dir("probemiss");
  const std::string config = write_test_config(dir, "probemiss");
  const std::string prog = dir + "/miss.ngc";
  std::ofstream(prog) << "G21 G90 G54 F50\nG0 X2 Y3 Z-5\nG38.2 Z-6\nG0 Z0\nM2\n";
  const ProcessResult r = run_process({pcnc_exe(), "run", prog, "--clock", "virtual", "--config", config}, 120);
  EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
  EXPECT_NE((r.out + r.err).find("miss.ngc:3:1: error: G38.2 reached its end without the probe triggering"),
            std::string::npos)
      << r.out << r.err;
}

// `pcnc ctl probe` over the control socket of `pcnc-host --serve` (an MDI G38.x).
TEST(ProcProbe, CtlProbeDownTouchesTheWorkpieceAndUpReleasesIt) {
  ServicePair pair("ctlprobe");
  ASSERT_TRUE(pair.start("virtual")) << pair.host_log() << pair.rt_log();
  const MachineConfig c = load_config(pair.config());
  const double z_trigger = c.table.z_mm + c.probe.model.ball_radius_mm - c.probe.model.pretravel_axial_mm;
  const double noise = 6 * c.probe.model.repeatability_mm;

  const ProcessResult down = pair.ctl({"probe", "Z-", "--feed", "50"});
  ASSERT_EQ(down.exit_code, 0) << down.out << down.err << pair.host_log();
  EXPECT_NE(down.out.find("probe G38.2: contact; latched at machine"), std::string::npos) << down.out;
  json st = pair.status();
  EXPECT_EQ(st["probe"]["outcome"], "contact") << st.dump();
  EXPECT_NEAR(st["probe"]["latched"]["z"].get<double>(), z_trigger, noise + 0.001) << st.dump();
  EXPECT_NEAR(st["probe"]["latched"]["x"].get<double>(), 12.5, 1e-9);
  EXPECT_LT(st["probe"]["stop"]["z"].get<double>(), st["probe"]["latched"]["z"].get<double>());
  EXPECT_TRUE(st["probe"]["input"].get<bool>()) << "the stylus stays deflected where it stopped";
  EXPECT_EQ(st["state"], "IDLE");

  const ProcessResult up = pair.ctl({"probe", "Z+", "--code", "G38.4", "--feed", "20", "--distance", "2"});
  ASSERT_EQ(up.exit_code, 0) << up.out << up.err << pair.host_log();
  st = pair.status();
  EXPECT_EQ(st["probe"]["outcome"], "contact");
  EXPECT_FALSE(st["probe"]["input"].get<bool>());
  EXPECT_NEAR(st["probe"]["latched"]["z"].get<double>(), z_trigger, noise + 0.001);

  // an MDI of several lines syncs at its probe: the line after it reads #5063 (program Z)
  const ProcessResult mdi = pair.ctl({"mdi", "G21 G90 G54 F50", "G38.2 Z-12", "G0 Z[#5063 + 1.5]"});
  ASSERT_EQ(mdi.exit_code, 0) << mdi.out << mdi.err << pair.host_log();
  st = pair.status();
  EXPECT_EQ(st["probe"]["outcome"], "contact");
  EXPECT_NEAR(st["commanded"]["z"].get<double>(), st["probe"]["latched"]["z"].get<double>() + 1.5, 1e-6) << st.dump();

  // nothing along +X within 2 mm: G38.2 without contact is an error at its line, ctl exits 1
  const ProcessResult miss = pair.ctl({"probe", "X+", "--distance", "2"});
  EXPECT_EQ(miss.exit_code, 1) << miss.out << miss.err;
  EXPECT_NE(miss.err.find("mdi:1:9: error: G38.2 reached its end without the probe triggering"), std::string::npos)
      << miss.out << "\n" << miss.err;
  EXPECT_EQ(pair.status()["probe"]["outcome"], "no contact");
  // G38.3 may miss: no error, the outcome printed
  const ProcessResult miss3 = pair.ctl({"probe", "X+", "--distance", "2", "--code", "G38.3"});
  EXPECT_EQ(miss3.exit_code, 0) << miss3.out << miss3.err;
  EXPECT_NE(miss3.out.find("probe G38.3: no contact"), std::string::npos) << miss3.out;
  EXPECT_EQ(pair.ctl({"probe", "Q+"}).exit_code, 2);
}

// The journal records each probe result: a program killed with its host after probing is
// resumed and interprets the lines after the probe with the real result (docs/probe.md).
TEST(ProcProbe, AResumedProgramReadsTheJournalsProbeResult) {
  ServicePair pair("proberesume");
  ASSERT_TRUE(pair.start("real")) << pair.host_log() << pair.rt_log();
  const std::string prog = pair.dir() + "/probe-then-cut.ngc";
  std::ofstream(prog) << "G21 G90 G54 F50\nG0 X0 Y0 Z-8.5\nG38.2 Z-11\nG1 X6 F60\nG0 Z[#5063 + 2]\nM2\n";
  ASSERT_TRUE(pair.call("run", {{"file", prog}}).contains("result"));
  const json cutting = pair.wait_status([](const json& s) { return s["state"] == "RUNNING" && s["line"] == 4; }, 30);
  ASSERT_EQ(cutting["line"], 4) << cutting.dump();
  ASSERT_EQ(cutting["probe"]["outcome"], "contact");
  const double latched_z = cutting["probe"]["latched"]["z"].get<double>();
  pair.kill_host(SIGKILL);
  ASSERT_EQ(wait_rt_state(pair.tag(), MachineState::kHostLost).state, MachineState::kHostLost);
  ASSERT_TRUE(pair.start_host()) << pair.host_log();
  pair.wait_status([](const json& x) { return x["rt"]["state"] == "attached"; }, 10);
  const json r = pair.call("resume", json::object(), 60);
  ASSERT_TRUE(r.contains("result")) << r.dump() << pair.host_log();
  const json s = pair.wait_status(
      [](const json& x) { return x["state"] == "IDLE" && !x["job"]["active"].get<bool>() && x["last_job"].is_object(); }, 60);
  EXPECT_EQ(s["last_job"]["end"], "completed") << s.dump();
  // #5063 + 2 in G54 is the latched machine Z + 2 (an assumed contact at Z-11 would give 16)
  EXPECT_NEAR(s["commanded"]["z"].get<double>(), latched_z + 2.0, 1e-6) << s.dump();
  EXPECT_NEAR(s["commanded"]["x"].get<double>(), 12.5 + 6.0, 1e-6);
}

// The host lost at the sync point itself: the rt finished the probing move while the host was
// stopped (so the journal never got the result), then the host was killed. The resume takes
// the result from the rt's status, writes it to the journal and the probe log, and the lines
// after the probe read it (docs/probe.md, docs/reliability.md).
TEST(ProcProbe, AHostLostAtTheSyncPointResumesWithTheRtsResult) {
  // the rt waits 6 s for a silent host before HOST_LOST: time for the probe to finish
  ServicePair pair("probesync", {{"host_timeout_s = 0.1", "host_timeout_s = 6.0"}});
  ASSERT_TRUE(pair.start("real")) << pair.host_log() << pair.rt_log();
  const std::string prog = pair.dir() + "/probe-sync.ngc";
  std::ofstream(prog) << "(PROBEOPEN sync-log.txt)\nG21 G90 G54 F50\nG0 X0 Y0 Z-8\nG38.2 Z-11 F20\nG1 X6 F60\n"
                         "G0 Z[#5063 + 2]\n(PROBECLOSE)\nM2\n";
  // the reply to run may come only at the first sync point: ask from another thread
  json run_reply;
  std::thread runner([&] {
    try {
      run_reply = pair.call("run", {{"file", prog}}, 60);
    } catch (const std::exception& e) {  // the host was killed before it answered
      run_reply = json{{"lost", e.what()}};
    }
  });
  // in the probing move (machine Z 17 down to the contact near 16, 3 s at 20 mm/min)
  auto in_probe = [](const json& s) {
    return s["state"] == "RUNNING" && s["probe"]["count"] == 0 && s["commanded"]["z"].get<double>() < 16.98 &&
           s["commanded"]["z"].get<double>() > 16.2;
  };
  const json probing = pair.wait_status(in_probe, 30);
  const bool caught = in_probe(probing);
  const int stopped = caught ? ::kill(pair.host_pid(), SIGSTOP) : -1;
  if (!caught || stopped != 0) {
    runner.join();
    FAIL() << "not caught in the probing move: " << probing.dump() << run_reply.dump();
  }
  Status st{};
  for (int i = 0; i < 500 && !(read_rt_status(pair.tag(), st) && st.probe_count >= 1); ++i) usleep(10000);
  pair.kill_host(SIGKILL);
  runner.join();  // its connection closed with the host (or the reply came first)
  ASSERT_EQ(st.probe_count, 1u) << "the probe did not finish while the host was stopped";
  ASSERT_EQ(st.probe_outcome, ProbeOutcome::kContact);
  const double latched_z = st.probe_latched[2];
  ASSERT_EQ(wait_rt_state(pair.tag(), MachineState::kHostLost, 15.0).state, MachineState::kHostLost);
  ASSERT_TRUE(pair.start_host()) << pair.host_log();
  pair.wait_status([](const json& x) { return x["rt"]["state"] == "attached"; }, 10);
  const json r = pair.call("resume", json::object(), 60);
  ASSERT_TRUE(r.contains("result")) << r.dump() << pair.host_log();
  const json s = pair.wait_status(
      [](const json& x) { return x["state"] == "IDLE" && !x["job"]["active"].get<bool>() && x["last_job"].is_object(); }, 60);
  EXPECT_EQ(s["last_job"]["end"], "completed") << s.dump() << pair.host_log();
  EXPECT_NEAR(s["commanded"]["z"].get<double>(), latched_z + 2.0, 1e-6) << s.dump();
  EXPECT_NEAR(s["commanded"]["x"].get<double>(), 12.5 + 6.0, 1e-6);
  EXPECT_NE(pair.host_log().find("its result is pcnc-rt's"), std::string::npos) << pair.host_log();
  // the probe log holds the one result, in program Z (G54 Z 25)
  const std::string log = read_file(pair.dir() + "/sync-log.txt");
  EXPECT_EQ(std::count(log.begin(), log.end(), '\n'), 1) << log;
  double x = 0, y = 0, z = 0;
  ASSERT_EQ(std::sscanf(log.c_str(), "%lf %lf %lf", &x, &y, &z), 3) << log;
  EXPECT_NEAR(z, latched_z - 25.0, 1e-5) << log;
}

}  // namespace
}  // namespace pcnc::test
