// test_proc_time_causes.cpp — `pcnc run --summary` end to end: the summary's time_by_cause
// adds up to the program time and names what a program was built to be limited by (junction
// stops, the programmed feed, an axis's velocity), and the summary's figures keep their
// invariants: check.lines = job.lines_read for a program run to its end, lines and blocks run
// <= read and sent, p50 <= p99 <= max for every latency.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "subprocess.hpp"
#include "test_paths.hpp"
#include "service_procs.hpp"

namespace pcnc::test {
namespace {

using nlohmann::json;


// Runs `program_text` (or the file `path` when text is empty) with --summary; returns the summary.
json run_summary(const std::string& tag, const std::string& program_text, std::string path = "") {
  const std::string dir = make_temp_dir(tag);
  const std::string config = write_test_config(dir, tag);
  if (path.empty()) {
    path = dir + "/p.ngc";
    std::ofstream(path) << program_text;
  }
  const std::string summary = dir + "/s.json";
  // --tolerance 0: the seed's rule, for which the demo's shares below were measured
  const ProcessResult r = run_process(
      {pcnc_exe(), "run", path, "--clock", "virtual", "--config", config, "--summary", summary, "--tolerance", "0"}, 300);
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  std::ifstream f(summary);
  if (!f) {
    ADD_FAILURE() << "no summary: " << r.err;
    return json::object();
  }
  return json::parse(f);
}

double share(const json& s, const std::string& cause) {
  const double total = s.at("status").at("program_time_s").get<double>();
  return s.at("time_by_cause").value(cause, 0.0) / total;
}

void expect_invariants(const json& s) {
  ASSERT_TRUE(s.contains("time_by_cause")) << s.dump().substr(0, 400);
  double sum = 0.0;
  for (const auto& [k, v] : s.at("time_by_cause").items()) {
    EXPECT_GE(v.get<double>(), 0.0) << k;
    sum += v.get<double>();
  }
  const json& st = s.at("status");
  const double program_time = st.at("program_time_s").get<double>();
  EXPECT_NEAR(sum, program_time, 1e-9) << "time_by_cause adds up to the program time";
  EXPECT_GT(program_time, 0.0);
  const json& c = s.at("check");
  const json& j = s.at("job");
  EXPECT_EQ(j.at("end"), "completed");
  EXPECT_EQ(c.at("lines").get<std::uint64_t>(), j.at("lines_read").get<std::uint64_t>()) << "run to its end: every line read";
  EXPECT_LE(st.at("blocks_done").get<std::uint64_t>(), j.at("blocks_sent").get<std::uint64_t>());
  EXPECT_LE(j.at("refill_p50_us").get<double>(), j.at("refill_p99_us").get<double>());
  EXPECT_LE(j.at("refill_p99_us").get<double>(), j.at("refill_max_us").get<double>());
  const json& t = st.at("timing");
  EXPECT_LE(t.at("compute_p99_us").get<double>(), t.at("compute_max_us").get<double>());
  EXPECT_LE(t.at("compute_min_us").get<double>(), t.at("compute_p99_us").get<double>());
  EXPECT_LE(t.at("wake_p99_us").get<double>(), t.at("wake_max_us").get<double>());
}

TEST(RunTimeCauses, DemoAddsUpAndKeepsItsInvariants) {
  const json s = run_summary("tc-demo", "", source_dir() + "/examples/demo.ngc");
  expect_invariants(s);
  EXPECT_GT(share(s, "feed"), 0.8) << s.at("time_by_cause").dump();
  EXPECT_NEAR(s.at("time_by_cause").value("dwell", 0.0), 0.2, 0.002) << "its G4 P0.2";
}

TEST(RunTimeCauses, AStaircaseOfShortMovesIsJunctionStops) {
  // 0.3 mm steps turning by 90° at F3000 (50 mm/s): 0.625 mm would be needed to reach F at
  // 2000 mm/s², so every step speeds up from a stop and slows to the next
  std::ostringstream p;
  p << "G21 G90 M22\nG0 X0 Y0 Z0\nG1 X0.3 F3000\n";
  for (int i = 0; i < 30; ++i) p << "G1 Y" << 0.3 * (i + 1) << "\nG1 X" << 0.3 * (i + 2) << "\n";
  p << "M30\n";
  const json s = run_summary("tc-stairs", p.str());
  expect_invariants(s);
  EXPECT_GT(share(s, "junction_stop"), 0.8) << s.at("time_by_cause").dump();
  EXPECT_LT(share(s, "feed"), 0.05) << s.at("time_by_cause").dump();
}

TEST(RunTimeCauses, SlowLongMoveIsTheFeed) {
  const json s = run_summary("tc-feed", "G21 G90\nG0 X-8 Y0 Z0\nG1 X8 F120\nM30\n");
  expect_invariants(s);
  EXPECT_GT(share(s, "feed"), 0.9) << s.at("time_by_cause").dump();
}

TEST(RunTimeCauses, FastZMoveIsZsVelocityLimit) {
  // F6000 = 100 mm/s on Z alone, whose limit is 50 mm/s
  const json s = run_summary("tc-zvel", "G21 G90\nG0 X0 Y0 Z0\nG1 Z-20 F6000\nM30\n");
  expect_invariants(s);
  EXPECT_GT(share(s, "axis_velocity_z"), 0.6) << s.at("time_by_cause").dump();
  EXPECT_GT(share(s, "start_end_stop"), 0.05) << "speeding up and stopping at the ends: " << s.at("time_by_cause").dump();
}

}  // namespace
}  // namespace pcnc::test
