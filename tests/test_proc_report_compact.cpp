// test_proc_report_compact.cpp — the run report from the compact trace (pcnc-rt
// --trace-digest) on real two-process runs: one run writes both the full CSV and the compact
// trace, and the report made from each carries the same figures (time by cause, slowest
// stretches, every plot bucket, the figures table); `pcnc run --report` without --trace
// writes its report from the compact trace also when the run faults or is stopped mid-way.
// On a 5-axis machine the compact trace keeps the joints: the same run's compact trace and
// CSV give the same joint following-error plot (exact) and tool-axis marks within the rt's
// decimation, and `pcnc run --report` alone draws the tool-axis view and the joint plot.
#include <gtest/gtest.h>
#include <signal.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <fstream>
#include <regex>
#include <thread>

#include <nlohmann/json.hpp>

#include "report/run_outputs.hpp"
#include "report/trace_compact_reader.hpp"
#include "five_axis_trace.hpp"
#include "subprocess.hpp"
#include "test_paths.hpp"
#include "service_procs.hpp"

namespace pcnc::test {
namespace {

using nlohmann::json;


// The page's part from `open` up to the next `close` ("" when absent).
std::string section(const std::string& html, const std::string& open, const std::string& close) {
  const auto a = html.find(open);
  if (a == std::string::npos) return "";
  const auto b = html.find(close, a);
  return html.substr(a, b == std::string::npos ? std::string::npos : b - a);
}

void expect_time_by_cause_adds_up(const json& s) {
  ASSERT_TRUE(s.contains("time_by_cause")) << s.dump().substr(0, 300);
  double sum = 0.0;
  for (const auto& [k, v] : s.at("time_by_cause").items()) sum += v.get<double>();
  EXPECT_NEAR(sum, s.at("status").at("program_time_s").get<double>(), 1e-9);
}

// One real run (a short corpus program, --fit), the rt writing the CSV and the compact trace
// from the same rows; the two reports side by side.
TEST(ReportCompact, SameFiguresAsTheFullTraceOnARealRun) {
  const std::string dir = make_temp_dir("rcompact");
  const std::string config = write_test_config(dir, "rcompact");
  const std::string csv = dir + "/t.csv", compact = dir + "/t.pcct", summary = dir + "/s.json";
  const std::string program = shared_dir() + "/gcode/cam/linuxcnc-tp/test_12mmflat.ngc";
  BackgroundProcess rt = start_process({bin_dir() + "/rt/pcnc-rt", "--config", config, "--clock", "virtual", "--trace", csv,
                                        "--trace-digest", compact, "--log-level", "warn"},
                                       dir + "/rt");
  Reaped rt_guard{rt};
  const ProcessResult host = run_process({bin_dir() + "/host/pcnc-host", "--config", config, "--run", program, "--fit",
                                          "--summary", summary, "--log-level", "warn", "--quiet"},
                                         300);
  ASSERT_EQ(host.exit_code, 0) << host.out << host.err;
  kill(rt.pid, SIGTERM);
  ASSERT_EQ(wait_for(rt, 30), 0) << rt.err();
  ASSERT_TRUE(is_compact_trace_file(compact));
  ASSERT_FALSE(is_compact_trace_file(csv));

  const ReportPage full = load_report_page(summary, csv);
  const ReportPage small = load_report_page(summary, compact);
  ASSERT_TRUE(full.has_trace && small.has_trace);
  ASSERT_GT(full.trace.program_rows, 8000u);
  // exact: counts, the time per cause, the slowest lines
  EXPECT_EQ(small.trace.rows, full.trace.rows);
  EXPECT_EQ(small.trace.program_rows, full.trace.program_rows);
  EXPECT_EQ(small.trace.cause_rows, full.trace.cause_rows);
  EXPECT_EQ(small.summary.time_by_cause, full.summary.time_by_cause);
  ASSERT_FALSE(full.summary.time_by_cause.empty());
  ASSERT_EQ(small.slowest.size(), full.slowest.size());
  for (std::size_t i = 0; i < full.slowest.size(); ++i) {
    EXPECT_EQ(small.slowest[i].line, full.slowest[i].line);
    EXPECT_EQ(small.slowest[i].lost_s, full.slowest[i].lost_s);
    EXPECT_EQ(small.slowest[i].cause, full.slowest[i].cause);
  }
  ASSERT_EQ(small.trace.buckets.size(), full.trace.buckets.size());
  for (std::size_t i = 0; i < full.trace.buckets.size(); ++i) {
    const TraceBucket &a = small.trace.buckets[i], &b = full.trace.buckets[i];
    EXPECT_EQ(a.t0, b.t0) << i;
    EXPECT_EQ(a.rows, b.rows) << i;
    EXPECT_EQ(a.feed_speed_max, b.feed_speed_max) << i;
    EXPECT_EQ(a.planned_max, b.planned_max) << i;
    EXPECT_EQ(a.ferr_max[0], b.ferr_max[0]) << i;
    EXPECT_EQ(a.ferr_min[2], b.ferr_min[2]) << i;
    EXPECT_EQ(a.cause_rows, b.cause_rows) << i;
  }
  // the path: decimated twice, so its points may differ; its ends may not
  ASSERT_FALSE(small.trace.path.empty());
  EXPECT_NEAR(small.trace.path.front().p[0], full.trace.path.front().p[0], 1e-5);  // kept in single precision
  EXPECT_EQ(small.trace.path.back().p[1], full.trace.path.back().p[1]);

  // the page: the plots, the figures and the time table are the same text
  const std::string a = render_report_html(small), b = render_report_html(full);
  for (const auto& [open, close] : std::vector<std::pair<std::string, std::string>>{
           {"<svg class=\"speed-plot\"", "</svg>"},
           {"<svg class=\"ferr-plot\"", "</svg>"},
           {"<h2>Figures</h2>", "</section>"},
           {"<h2>Where the time went", "</section>"},
           {"Slowest stretches</h2>", "</table>"}}) {
    const std::string x = section(a, open, close), y = section(b, open, close);
    EXPECT_FALSE(x.empty()) << open;
    EXPECT_TRUE(x == y) << open << " differs";
  }
}

// `pcnc run --report --summary` without --trace: the rt writes no CSV, only the compact trace.
json run_with_report(const std::string& dir, const std::vector<std::string>& extra, int expect_exit, double stop_after_s = 0) {
  const std::string report = dir + "/r.html", summary = dir + "/s.json";
  std::vector<std::string> argv = {pcnc_exe(), "run", source_dir() + "/examples/demo.ngc", "--report", report, "--summary", summary, "-q"};
  argv.insert(argv.end(), extra.begin(), extra.end());
  BackgroundProcess p = start_process(argv, dir + "/pcnc");
  Reaped guard{p};
  if (stop_after_s > 0) {
    std::this_thread::sleep_for(std::chrono::duration<double>(stop_after_s));
    kill(p.pid, SIGTERM);
  }
  const int status = wait_for(p, 300);
  EXPECT_EQ(status, expect_exit) << p.out() << p.err();
  const std::string html = read_file(report);
  EXPECT_NE(html.find("<svg class=\"speed-plot\""), std::string::npos) << p.err();
  EXPECT_NE(html.find("trace rows"), std::string::npos) << "the page was drawn from a trace";
  EXPECT_EQ(p.err().find("HTML report was not written"), std::string::npos) << p.err();
  std::ifstream f(summary);
  if (!f) {
    ADD_FAILURE() << "no summary: " << p.err();
    return json::object();
  }
  return json::parse(f);
}

TEST(ReportCompact, FaultedRunGetsItsReport) {
  const std::string dir = make_temp_dir("rcfault");
  // X may lag 1 µm: the demo's first move faults
  const std::string config = write_test_config(dir, "rcfault", {{"following_error_limit_mm = 0.2", "following_error_limit_mm = 0.001"}});
  const json s = run_with_report(dir, {"--clock", "virtual", "--config", config}, 1);
  expect_time_by_cause_adds_up(s);
  EXPECT_GT(s.at("status").at("program_time_s").get<double>(), 0.0);
  const std::string html = read_file(dir + "/r.html");
  EXPECT_NE(html.find("FAULT"), std::string::npos);
}

TEST(ReportCompact, StoppedRunGetsItsReport) {
  const std::string dir = make_temp_dir("rcstop");
  const std::string config = write_test_config(dir, "rcstop");
  // real clock: demo.ngc takes 14 s; SIGTERM after 2 s stops it along the path
  const json s = run_with_report(dir, {"--clock", "real", "--config", config}, 128 + SIGTERM, 2.0);
  expect_time_by_cause_adds_up(s);
  const double t = s.at("status").at("program_time_s").get<double>();
  EXPECT_GT(t, 0.2);
  EXPECT_LT(t, 10.0);
}

// The impeller blade (examples/5axis) on desktop-5axis.toml, the rt writing the CSV with the
// joints' columns and the compact trace from the same rows.
TEST(ReportCompact, FiveAxisJointsAsTheFullTraceGivesThem) {
  const std::string dir = make_temp_dir("rc5axis");
  const std::string config = write_five_axis_config(dir, "rc5axis");
  const std::string csv = dir + "/t.csv", compact = dir + "/t.pcct", summary = dir + "/s.json";
  BackgroundProcess rt = start_process({bin_dir() + "/rt/pcnc-rt", "--config", config, "--clock", "virtual", "--trace", csv,
                                        "--trace-digest", compact, "--log-level", "warn"},
                                       dir + "/rt");
  Reaped rt_guard{rt};
  const ProcessResult host =
      run_process({bin_dir() + "/host/pcnc-host", "--config", config, "--run", source_dir() + "/examples/5axis/impeller-blade.ngc",
                   "--summary", summary, "--log-level", "warn", "--quiet"},
                  300);
  ASSERT_EQ(host.exit_code, 0) << host.out << host.err;
  kill(rt.pid, SIGTERM);
  ASSERT_EQ(wait_for(rt, 30), 0) << rt.err();

  const ReportPage full = load_report_page(summary, csv);
  const ReportPage small = load_report_page(summary, compact);
  const JointDigest &a = small.trace.joints, &b = full.trace.joints;
  ASSERT_EQ(b.letters, (std::vector<char>{'A', 'C'}));
  EXPECT_EQ(a.letters, b.letters);
  // the joints' following error: exact, every bucket and the maxima
  EXPECT_GT(b.ferr_abs_max[0], 0.0);
  EXPECT_GT(b.ferr_abs_max[1], 0.0);
  EXPECT_EQ(a.ferr_abs_max, b.ferr_abs_max);
  ASSERT_GT(b.buckets.size(), 100u);
  ASSERT_EQ(a.buckets.size(), b.buckets.size());
  for (std::size_t i = 0; i < b.buckets.size(); ++i) {
    EXPECT_EQ(a.buckets[i].t0, b.buckets[i].t0) << i;
    EXPECT_EQ(a.buckets[i].t1, b.buckets[i].t1) << i;
    EXPECT_EQ(a.buckets[i].rows, b.buckets[i].rows) << i;
    EXPECT_EQ(a.buckets[i].ferr_min, b.buckets[i].ferr_min) << i;
    EXPECT_EQ(a.buckets[i].ferr_max, b.buckets[i].ferr_max) << i;
  }
  // the tool axis: from the rt's kept points (1 µm or 0.001° apart, more past its budget), so
  // the tip path may be shorter by the chords it skipped and a mark may land a kept point later
  ASSERT_TRUE(a.tool_axis && b.tool_axis);
  EXPECT_EQ(a.axis_every_mm, b.axis_every_mm);
  EXPECT_NEAR(a.tip_path_mm, b.tip_path_mm, 1e-3 * b.tip_path_mm);
  ASSERT_GT(b.marks.size(), 20u);
  EXPECT_LE(std::abs(static_cast<long>(a.marks.size()) - static_cast<long>(b.marks.size())), 1L);
  double worst_tip = 0.0, worst_axis = 0.0;  // mm, and 1 - cos of the angle
  for (const ToolAxisMark& m : a.marks) {
    double best = 1e9, axis = 0.0;
    for (const ToolAxisMark& n : b.marks) {
      if (norm(m.tip - n.tip) < best) {
        best = norm(m.tip - n.tip);
        axis = 1.0 - dot(m.axis, n.axis);
      }
    }
    worst_tip = std::max(worst_tip, best);
    worst_axis = std::max(worst_axis, axis);
  }
  std::printf("tool-axis marks: compact %zu, CSV %zu; worst tip %.6f mm, worst axis 1-cos %.3g; tip path %.6f vs %.6f mm\n",
              a.marks.size(), b.marks.size(), worst_tip, worst_axis, a.tip_path_mm, b.tip_path_mm);
  // a mark lands at most a kept point (one cycle's travel on a rapid: 24 µm on this program) off
  EXPECT_LT(worst_tip, 0.1 * b.axis_every_mm);
  EXPECT_LT(worst_axis, 1.0 - std::cos(0.1 * std::numbers::pi / 180.0));  // within 0.1°

  // the page: both 5-axis sections, the joint plot the same text
  const std::string x = render_report_html(small), y = render_report_html(full);
  EXPECT_NE(x.find("id=\"tool-axis-view\""), std::string::npos);
  const std::string px = section(x, "id=\"joint-ferr\"", "</section>"), py = section(y, "id=\"joint-ferr\"", "</section>");
  EXPECT_NE(px.find("joint-ferr-plot"), std::string::npos);
  EXPECT_TRUE(px == py) << "the joint plot differs";
}

// `pcnc run --report` alone on a 5-axis machine: the page has the tool-axis view and the joint plot.
TEST(ReportCompact, FiveAxisRunWithReportOnlyDrawsTheToolAxisAndTheJoints) {
  const std::string dir = make_temp_dir("rc5only");
  const std::string config = write_five_axis_config(dir, "rc5only");
  const std::string report = dir + "/r.html";
  const ProcessResult r = run_process({pcnc_exe(), "run", source_dir() + "/examples/5axis/singularity.ngc", "--config", config,
                                       "--clock", "virtual", "--report", report, "-q"},
                                      300);
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  const std::string html = read_file(report);
  EXPECT_NE(html.find("id=\"tool-axis-view\""), std::string::npos);
  const std::string view = section(html, "<svg class=\"tool-axis-view\"", "</svg>");
  EXPECT_NE(view.find("<polyline class=\"tip-path\""), std::string::npos);
  EXPECT_NE(view.find("<line class=\"tool-axis\""), std::string::npos);
  EXPECT_NE(section(html, "id=\"joint-ferr\"", "</section>").find("joint-ferr-plot"), std::string::npos);
}

}  // namespace
}  // namespace pcnc::test
