// test_proc_cam_corpus.cpp — every real CAM program in ../shared/gcode/cam replayed end to end
// with `pcnc run --clock virtual` (both processes, --fit where the part is larger than the
// travel, contouring on as most CAM programs never say M21), each with its HTML report and
// JSON summary written, and the figures checked against bounds worked out from the program
// itself:
//   - the run completes (no fault), with no ring underrun;
//   - the tool ends on the program's last point after offset and scale (from its own blocks);
//   - every junction that turns by less than the contouring angle under M21 is passed without
//     stopping, and no other junction is: the rt's flow count equals the count from the blocks;
//   - the contour error stays under 10 µm at the programmed feed with the default config;
//   - the HTML page holds the tool path and the plots, and states the same figures.
// Programs the front end refuses are listed with the reason a user reads.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <regex>

#include "config/config.hpp"
#include "motion/path.hpp"
#include "gcode/program.hpp"
#include "report/run_outputs.hpp"
#include "report/run_summary.hpp"
#include "subprocess.hpp"
#include "test_paths.hpp"
#include "service_procs.hpp"

namespace pcnc::test {
namespace {

namespace fs = std::filesystem;

std::string cam_dir() { return shared_dir() + "/gcode/cam"; }

// Refused before anything moves, with this in the message (the same reasons test_corpus states).
const std::map<std::string, std::string> kRefused = {
    {"linuxcnc-tp/Cereal.ngc", "below the travel minimum"},  // G53 Z-10: outside this machine's Z travel
    {"linuxcnc-tp/Pasta.ngc", "below the travel minimum"},
};

// Long 2.5D programs (over 100 s of machine time: pockets, faces, outlines) are replayed in the
// normal build only. Under the sanitizers, which look for memory errors and undefined behaviour
// on the same code paths, the shorter 2.5D programs and every 3D program still replay: these
// repeat the same lines and arcs for minutes (about 50 s of the ASan suite's time).
const std::set<std::string> kLongUnderSanitizers = {
    "freecad/HeatSink_mill.tap",    "freecad/eccentric_slot_finish.nc", "fusion360/Key_Pockets.nc",
    "fusion360/cnc_Face_2.nc",      "ugs/Gates_combined_R12.nc",        "ugs/ShapeOko_Calibration_Pattern_01b.ngc",
    "ugs/electric_turtle.nc",
};

std::vector<std::string> cam_programs() {
  std::vector<std::string> out;
  for (const auto& e : fs::recursive_directory_iterator(cam_dir())) {
    if (e.is_regular_file()) out.push_back(fs::relative(e.path(), cam_dir()).string());
  }
  std::sort(out.begin(), out.end());
  return out;
}

// What the program's own blocks say. Junction angles are taken between the tangents of the
// curves the rt runs (prepare_block: an arc whose end radius differs within the G-code
// tolerance is run as a spiral, whose end tangents differ slightly from the circle's).
struct ProgramFacts {
  std::uint64_t blocks = 0;
  std::uint64_t motion_junctions = 0;  // consecutive motion blocks
  std::uint64_t flowable = 0;          // ... under M21 and turning less than the contouring angle
  Vec3 last_end{};                     // end of the last motion block (machine coordinates)
};

ProgramFacts program_facts(const std::string& path, const MachineConfig& c, const JobOptions& o, const Transform& t) {
  ProgramFacts f;
  BlockStream stream(path, c, o, t);
  const double cos_limit = std::cos(c.motion.contouring_angle_deg * M_PI / 180.0);
  Block b;
  PreparedBlock prev;
  bool have_prev = false;
  while (stream.next(b)) {
    ++f.blocks;
    const PreparedBlock p = prepare_block(b, c);
    if (p.motion) {
      if (have_prev && prev.motion) {
        ++f.motion_junctions;
        if (prev.contouring && dot(prev.dir_end, p.dir_start) > cos_limit) ++f.flowable;
      }
      f.last_end = b.end;
    }
    prev = p;
    have_prev = true;
  }
  return f;
}

std::string span(const std::string& html, const std::string& id) {
  const std::regex re("id=\"" + id + "\">([^<]*)<");
  std::smatch m;
  return std::regex_search(html, m, re) ? m[1].str() : std::string("(missing " + id + ")");
}

class CamCorpus : public ::testing::TestWithParam<std::string> {};

TEST(CamCorpusList, HasTheTwentyPrograms) {
  const auto all = cam_programs();
  EXPECT_EQ(all.size(), 20u);
  for (const auto& [rel, why] : kRefused) EXPECT_NE(std::find(all.begin(), all.end(), rel), all.end()) << rel;
  for (const auto& rel : kLongUnderSanitizers) EXPECT_NE(std::find(all.begin(), all.end(), rel), all.end()) << rel;
}

TEST_P(CamCorpus, ReplaysToTheEndWithinBounds) {
  const std::string rel = GetParam();
  if (sanitizer_build() && kLongUnderSanitizers.count(rel)) GTEST_SKIP() << rel << ": replayed in the normal build";
  const std::string path = cam_dir() + "/" + rel;
  std::string tag = "cam" + std::to_string(std::hash<std::string>{}(rel) % 100000);
  const std::string dir = make_temp_dir(tag);
  const std::string config_path = write_test_config(dir, tag);
  // the seed's contouring rule (the run below passes --tolerance 0): the figures are counted for it
  MachineConfig config = load_config(config_path);
  set_operator_tolerance(config.motion, 0.0);

  // --fit only where the part does not fit the travel as it is
  JobOptions options;
  options.contouring = true;
  // where the machine stands when the program starts (pcnc-host passes the rt's position)
  options.start_position = Vec3{config.axes[0].home_mm, config.axes[1].home_mm, config.axes[2].home_mm};
  const bool needs_fit = !check_program(path, config, options).ok;
  options.fit = needs_fit;

  const std::string html_path = dir + "/report.html", json_path = dir + "/summary.json";
  // --tolerance 0: the seed's contouring rule, which the junction counts below are checked against
  std::vector<std::string> argv = {pcnc_exe(), "run",    path,      "--clock",  "virtual", "--contouring", "on",
                                   "--config", config_path, "--report", html_path, "--summary", json_path,
                                   "--tolerance", "0"};
  if (needs_fit) argv.push_back("--fit");
  const ProcessResult r = run_process(argv, 600);

  if (kRefused.count(rel)) {
    EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
    EXPECT_NE(r.err.find(kRefused.at(rel)), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("nothing was moved"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(html_path)) << "no report for a program that did not run";
    fs::remove_all(dir);
    return;
  }
  ASSERT_EQ(r.exit_code, 0) << rel << "\n" << r.out << r.err;
  ASSERT_TRUE(fs::exists(json_path)) << r.out << r.err;
  const RunSummary s = read_run_summary(json_path);
  const Status& st = s.final_status;

  // ran to the end, cleanly
  EXPECT_EQ(s.end, "completed") << s.message;
  EXPECT_EQ(st.program_done, 1);
  EXPECT_EQ(st.fault, FaultCode::kNone);
  EXPECT_EQ(st.underruns, 0u) << "virtual clock: the rt waits for the host, never runs dry";
  EXPECT_EQ(s.blocks_sent, st.blocks_done);
  EXPECT_GT(st.program_time_s, 0.0);
  // one definition per figure: every line read, the time all attributed
  EXPECT_EQ(s.lines, s.lines_read) << "run to its end: every line the check read";
  double attributed = 0.0;
  for (const auto& [cause, sec] : s.time_by_cause) attributed += sec;
  EXPECT_NEAR(attributed, st.program_time_s, 1e-9) << "time_by_cause adds up to the program time";
  EXPECT_LE(st.timing.compute_p99_us, st.timing.compute_max_us);
  EXPECT_GE(st.program_time_s, s.feed_length_time_s * 0.999) << "no faster than the feed allows";
  EXPECT_GT(s.transform.scale, 0.0);
  EXPECT_LE(s.transform.scale, 1.0) << "--fit never scales up";
  if (!needs_fit) {
    EXPECT_EQ(s.transform.scale, 1.0);
  }

  // the program's own blocks, under the transform the run used
  const CheckResult check = check_program(path, config, options);
  ASSERT_TRUE(check.ok);
  EXPECT_EQ(check.transform.scale, s.transform.scale);
  for (std::size_t i = 0; i < 3; ++i) EXPECT_EQ(check.transform.offset[i], s.transform.offset[i]);
  const ProgramFacts facts = program_facts(path, config, options, check.transform);
  EXPECT_EQ(s.blocks_sent, facts.blocks);

  // final position: the last programmed point after offset and scale
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_NEAR(s.last_point[i], facts.last_end[i], 1e-9) << axis_name(static_cast<int>(i));
    EXPECT_NEAR(st.commanded[i], facts.last_end[i], 1e-6) << axis_name(static_cast<int>(i)) << " setpoint";
    EXPECT_NEAR(st.actual[i], facts.last_end[i], 0.005) << axis_name(static_cast<int>(i)) << " measured";
  }

  // contouring: exactly the junctions under the angle flow, all others stop
  EXPECT_EQ(st.junction_flows, facts.flowable) << "flows vs junctions turning less than the contouring angle";
  EXPECT_EQ(st.junction_stops + st.junction_flows, facts.motion_junctions);

  // accuracy at the programmed feed
  EXPECT_LT(st.max_contour_error, 0.010) << "mm; RMS " << rms_contour_error(st);
  for (int i = 0; i < kAxes; ++i) {
    EXPECT_LT(st.max_following_error[static_cast<std::size_t>(i)], config.axes[static_cast<std::size_t>(i)].following_error_limit_mm)
        << axis_name(i);
  }

  // the report: written, with pictures, stating the summary's figures
  ASSERT_TRUE(fs::exists(html_path));
  const std::string html = read_file(html_path);
  EXPECT_LT(html.size(), 2u * 1024 * 1024) << "decimated to the pixels: any corpus program's report under 2 MB";
  EXPECT_NE(html.find("<path class=\"feed\""), std::string::npos) << "the tool path is drawn";
  // rapids from the lines the run's check recorded (the report runs no front end of its own)
  EXPECT_EQ(s.rapid_lines.size(), check.rapid_lines.size());
  if (!s.rapid_lines.empty()) {
    EXPECT_NE(html.find("class=\"rapid\""), std::string::npos) << "rapids are drawn";
  }
  EXPECT_NE(html.find("id=\"final-tool\""), std::string::npos);
  EXPECT_NE(html.find("class=\"speed-plot\""), std::string::npos);
  EXPECT_NE(html.find("class=\"ferr-plot\""), std::string::npos);
  EXPECT_EQ(span(html, "machine-time"), fixed(st.program_time_s, 3));
  EXPECT_EQ(span(html, "junction-flows"), std::to_string(st.junction_flows));
  EXPECT_EQ(span(html, "junction-stops"), std::to_string(st.junction_stops));
  EXPECT_EQ(span(html, "contour-max"), fixed(st.max_contour_error * 1000.0, 2));
  EXPECT_EQ(span(html, "scale"), fixed(s.transform.scale, 6));
  EXPECT_EQ(html.find("http://"), html.find("http://www.w3.org/2000/svg")) << "nothing but the SVG namespace names a URL";
  EXPECT_EQ(html.find("https://"), std::string::npos);

  std::printf("[ figures  ] %-42s scale %.4f  machine %8.3f s  feed L/F %8.3f s  flows %6llu stops %5llu  "
              "(under the angle %llu)  ferr max %.2f/%.2f/%.2f um  contour max %.2f um\n",
              rel.c_str(), s.transform.scale, st.program_time_s, s.feed_length_time_s,
              static_cast<unsigned long long>(st.junction_flows), static_cast<unsigned long long>(st.junction_stops),
              static_cast<unsigned long long>(facts.flowable), st.max_following_error[0] * 1e3, st.max_following_error[1] * 1e3, st.max_following_error[2] * 1e3,
              st.max_contour_error * 1e3);
  if (!HasFailure()) fs::remove_all(dir);
}

std::string test_name(const ::testing::TestParamInfo<std::string>& info) {
  std::string n;
  for (char c : info.param) n += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
  return n;
}

INSTANTIATE_TEST_SUITE_P(Shared, CamCorpus, ::testing::ValuesIn(cam_programs()), test_name);

}  // namespace
}  // namespace pcnc::test
