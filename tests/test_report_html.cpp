// test_report_html.cpp — the HTML run report and what it is made from: trace rows parsed and
// digested (min/max buckets keep every peak, the path thins but keeps its ends), the run
// summary's JSON round trip, the page's figures equal to the summary's, SVGs present and
// non-empty, nothing fetched from the network; and the page rendered by headless Chromium
// into a screenshot that is neither missing nor blank.
#include <algorithm>
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <regex>
#include <thread>

#include "progress.hpp"
#include "report/report_html.hpp"
#include "report/run_report.hpp"
#include "report/run_summary.hpp"
#include "report/time_causes.hpp"
#include "headless_chromium.hpp"
#include "subprocess.hpp"
#include "report/trace_reader.hpp"
#include "loop/trace_writer.hpp"

namespace pcnc {
namespace {

namespace fs = std::filesystem;

// A summary with distinct, recognisable values in every figure the page shows.
RunSummary sample_summary() {
  RunSummary s;
  s.program = "/tmp/some dir/part <1>.ngc";
  s.machine = "desktop-mill";
  s.config_path = "configs/desktop-mill.toml";
  s.clock = "virtual";
  s.contouring_at_start = true;
  s.contouring_angle_deg = 10.0;
  s.cycle_hz = 2000.0;
  s.travel_max = {25, 25, 25};
  s.lines = 1234;
  s.moves = 1200;
  s.warnings = 2;
  s.transform.scale = 0.25;
  s.transform.offset = {12.5, 12.5, 20.0};
  s.min_point = {10.0, 11.0, 19.0};
  s.max_point = {15.0, 14.0, 20.5};
  s.last_point = {12.5, 12.5, 20.5};
  s.feed_length_time_s = 41.2346;
  s.end = "completed";
  s.blocks_sent = 1201;
  s.lines_read = 1234;
  s.wall_time_s = 0.5;
  s.refill_count = 1197;
  s.refill_p50_us = 12.25;
  s.refill_p99_us = 87.5;
  s.refill_max_us = 301.0;
  s.pauses = 2;
  s.pauses_mode = "continue";
  s.pause_lines = {17, 402};
  s.smoothing_min_tolerance_mm = 0.005;
  s.smoothing_max_tolerance_mm = 0.01;
  s.packed_arcs = 603;
  s.packed_curves = 1;
  s.packed_blocks = 41;
  s.packed_max_deviation_mm = 2.5e-10;
  Status& st = s.final_status;
  st.state = MachineState::kIdle;
  st.program_done = 1;
  st.clock_virtual = 1;
  st.program_time_s = 47.8915;
  st.blocks_done = 1201;
  st.junction_flows = 876;
  st.junction_stops = 324;
  st.underruns = 3;
  st.actual = {12.5001, 12.4999, 20.5002};
  st.commanded = {12.5, 12.5, 20.5};
  st.max_following_error = {0.00412, 0.00377, 0.00151};
  st.program_cycles = 95783;
  st.following_error_sq_sum = {95783 * 1e-6, 95783 * 4e-6, 95783 * 0.25e-6};  // RMS 1, 2, 0.5 µm
  st.max_contour_error = 0.00734;
  st.contour_error_sq_sum = 95783 * 9e-6;  // RMS 3 µm
  st.timing.compute_p99_us = 3.25;
  st.timing.compute_max_us = 17.5;
  st.timing.wake_p99_us = 0.0;
  st.timing.overruns = 0;
  return s;
}

TraceSample row(double t, std::uint32_t line, MachineState state, Vec3 act, Vec3 ferr, double speed) {
  TraceSample r;
  r.t = t;
  r.line = line;
  r.state = state;
  r.actual = act;
  r.commanded = act + ferr;
  r.following_error = ferr;
  r.speed = speed;
  return r;
}

// A square traced at 2 kHz: rapid on line 1, feed on lines 2..5, with a following-error
// spike of 9 µm on Y in a single cycle.
TraceDigest square_digest(std::size_t max_buckets = 100, std::size_t max_points = 100000) {
  DigestOptions o;
  o.max_buckets = max_buckets;
  o.path_tolerance_mm = 0.01;
  o.max_path_points = max_points;
  o.is_rapid_line = [](std::uint32_t line) { return line == 1; };
  TraceDigester d(o);
  double t = 0.0;
  for (int i = 0; i < 20; ++i) d.add(row(t += 0.0005, 0, MachineState::kIdle, {10, 11, 20}, {}, 0.0));
  Vec3 p{10, 11, 20};
  for (int i = 0; i < 200; ++i) {  // rapid: 1 mm in +X at 10 mm/s... then the square
    p[0] += 0.005;
    d.add(row(t += 0.0005, 1, MachineState::kRunning, p, {0.001, 0, 0}, 10.0));
  }
  const Vec3 dirs[4] = {{0, 1, 0}, {1, 0, 0}, {0, -1, 0}, {-1, 0, 0}};
  int n = 0;
  for (std::uint32_t side = 0; side < 4; ++side) {
    for (int i = 0; i < 400; ++i, ++n) {
      p = p + 0.005 * dirs[side];
      const Vec3 ferr = n == 777 ? Vec3{0, 0.009, 0} : Vec3{0, 0.001, -0.0005};
      d.add(row(t += 0.0005, 2 + side, MachineState::kRunning, p, ferr, 10.0));
    }
  }
  for (int i = 0; i < 50; ++i) d.add(row(t += 0.0005, 6, MachineState::kIdle, p, {}, 0.0));
  return d.finish();
}

TEST(TraceReader, ParsesTheWritersRows) {
  TraceSample s;
  s.t = 1.2345;
  s.line = 17;
  s.state = MachineState::kPaused;
  s.commanded = {1.5, -2.25, 3.0};
  s.actual = {1.4999, -2.2501, 2.9999};
  s.following_error = {0.0001, 0.0001, 0.0001};
  s.speed = 12.5;
  TraceSample r;
  ASSERT_TRUE(parse_trace_row(trace_csv_row(s), r)) << trace_csv_row(s);
  EXPECT_DOUBLE_EQ(r.t, 1.2345);
  EXPECT_EQ(r.line, 17u);
  EXPECT_EQ(r.state, MachineState::kPaused);
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_NEAR(r.commanded[i], s.commanded[i], 1e-7);
    EXPECT_NEAR(r.actual[i], s.actual[i], 1e-7);
    EXPECT_NEAR(r.following_error[i], s.following_error[i], 1e-7);
  }
  EXPECT_DOUBLE_EQ(r.speed, 12.5);
  EXPECT_FALSE(parse_trace_row("1.0,2,RUNNING,1,2,3,4,5,6,7,8,9", r)) << "a field short";
  EXPECT_FALSE(parse_trace_row("1.0,2,RUNNING,1,2,3,4,5,6,7,8,9,10,11", r)) << "a field too many";
  EXPECT_FALSE(parse_trace_row("1.0,2,WALKING,1,2,3,4,5,6,7,8,9,10", r)) << "unknown state";
  EXPECT_FALSE(parse_trace_row("1.0,x,RUNNING,1,2,3,4,5,6,7,8,9,10", r));
}

TEST(TraceReader, StreamsAFileAndRefusesOtherFiles) {
  const std::string dir = test::make_temp_dir("trace_reader");
  const std::string path = dir + "/t.csv";
  {
    std::ofstream f(path);
    f << trace_csv_header() << "\n";
    for (int i = 0; i < 1000; ++i) {
      TraceSample s;
      s.t = i * 0.0005;
      s.line = static_cast<std::uint32_t>(i / 100);
      s.state = MachineState::kRunning;
      s.speed = i;
      f << trace_csv_row(s) << "\n";
    }
  }
  TraceReader reader(path);
  TraceSample r;
  double sum = 0.0;
  while (reader.next(r)) sum += r.speed;
  EXPECT_EQ(reader.rows(), 1000u);
  EXPECT_DOUBLE_EQ(sum, 999.0 * 1000.0 / 2.0);

  const std::string other = dir + "/other.csv";
  std::ofstream(other) << "a,b,c\n1,2,3\n";
  EXPECT_THROW(TraceReader{other}, std::runtime_error);
  EXPECT_THROW(TraceReader{dir + "/missing.csv"}, std::runtime_error);
  const std::string bad = dir + "/bad.csv";
  std::ofstream(bad) << trace_csv_header() << "\nnot,a,row\n";
  TraceReader bad_reader(bad);
  EXPECT_THROW(bad_reader.next(r), std::runtime_error);
  fs::remove_all(dir);
}

TEST(TraceDigest, KeepsPeaksWindowAndPathEnds) {
  const TraceDigest d = square_digest(100);
  EXPECT_EQ(d.rows, 20u + 200u + 1600u + 50u);
  EXPECT_EQ(d.program_rows, 1800u) << "from the first RUNNING row to the last busy one";
  EXPECT_NEAR(d.duration_s, 1799 * 0.0005, 1e-9);
  EXPECT_LE(d.buckets.size(), 100u);
  EXPECT_GE(d.buckets.size(), 50u) << "merging halves the count, never more";
  double ymax = 0.0, zmin = 0.0;
  std::uint64_t rows = 0;
  for (const TraceBucket& b : d.buckets) {
    ymax = std::max(ymax, b.ferr_max[1]);
    zmin = std::min(zmin, b.ferr_min[2]);
    rows += b.rows;
    EXPECT_LE(b.t0, b.t1);
  }
  EXPECT_DOUBLE_EQ(ymax, 0.009) << "a one-cycle spike survives decimation";
  EXPECT_DOUBLE_EQ(zmin, -0.0005);
  EXPECT_EQ(rows, d.program_rows);
  EXPECT_DOUBLE_EQ(d.ferr_abs_max[1], 0.009);
  EXPECT_DOUBLE_EQ(d.speed_max, 10.0);

  // path: the rapid is marked, the corners are kept, the last point is the final position
  ASSERT_GE(d.path.size(), 5u);
  EXPECT_TRUE(d.path[1].rapid);
  EXPECT_FALSE(d.path.back().rapid);
  const Vec3 end{11.0, 11.0, 20.0};
  EXPECT_NEAR(norm(d.path.back().p - end), 0.0, 1e-9);
  for (const Vec3 corner : {Vec3{11, 13, 20}, Vec3{13, 13, 20}, Vec3{13, 11, 20}}) {
    double best = 1e9;
    for (const ToolPathPoint& q : d.path) best = std::min(best, norm(q.p - corner));
    EXPECT_LT(best, 0.0101) << "corner " << corner[0] << "," << corner[1];
  }
}

TEST(TraceDigest, ThinsAPathThatOutgrowsItsBudget) {
  const TraceDigest wide = square_digest(100, 100000);
  const TraceDigest thin = square_digest(100, 100);
  EXPECT_LE(thin.path.size(), 101u);
  EXPECT_LT(thin.path.size(), wide.path.size());
  EXPECT_GT(thin.path_tolerance_mm, wide.path_tolerance_mm);
  EXPECT_NEAR(norm(thin.path.back().p - wide.path.back().p), 0.0, 1e-12) << "the end point is kept";
}

TEST(RunReport, TerminalReportNamesACornerTolerance) {
  RunReport r;
  r.program = "part.nc";
  r.job.final_status.junction_flows = 12;
  r.job.final_status.junction_stops = 3;
  const std::string plain = format_run_report(r);
  EXPECT_NE(plain.find("12 passed without stopping, 3 stops\n"), std::string::npos) << plain;
  EXPECT_EQ(plain.find("path tolerance"), std::string::npos);
  r.path_tolerance_mm = 0.01;
  const std::string merged = format_run_report(r);
  EXPECT_NE(merged.find("3 stops (path tolerance 10.0 um"), std::string::npos) << merged;
}

TEST(RunReport, TerminalReportStatesThePausesAndTheToleranceTheCurvesWereFittedTo) {
  RunReport r;
  r.program = "part.nc";
  r.path_tolerance_mm = 0.005;
  const std::string none = format_run_report(r);
  EXPECT_EQ(none.find("pauses"), std::string::npos) << "no line without pauses";
  EXPECT_NE(none.find("smoothing         tolerance 5.0 um: 0 G1 moves"), std::string::npos) << none;
  r.job.pauses = 3;
  r.job.pauses_mode = "continue";
  r.job.pause_lines = {12, 40, 77};
  r.check.smoothed_curves = 4;
  r.check.smoothed_moves = 90;
  r.check.smoothing_min_tolerance_mm = 0.01;  // G64 P0.01 in the program
  r.check.smoothing_max_tolerance_mm = 0.01;
  const std::string text = format_run_report(r);
  EXPECT_NE(text.find("  pauses            3 (M0/M1 on lines 12, 40, 77): the machine came to rest there and went on "
                      "(--pauses continue)\n"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("smoothing         tolerance 10.0 um (G64 P): 90 G1 moves"), std::string::npos) << text;
  EXPECT_EQ(text.find("arc packing"), std::string::npos) << "no line without packed arcs";
  r.check.packed_arcs = 603;
  r.check.packed_curves = 1;
  r.check.packed_blocks = 41;
  const std::string packed = format_run_report(r);
  EXPECT_NE(packed.find("  arc packing       603 arcs packed into 41 blocks (1 curve, exact: max 0.000 um from the arcs)\n"),
            std::string::npos)
      << packed;
  r.check.smoothing_min_tolerance_mm = 0.002;
  r.job.pauses = 40;  // more than the lines kept
  r.job.pauses_mode = "ask";
  const std::string range = format_run_report(r);
  EXPECT_NE(range.find("tolerance 2.0-10.0 um (G64 P)"), std::string::npos) << range;
  EXPECT_NE(range.find("40 (M0/M1 on lines 12, 40, 77, ...): the machine waited at rest for the operator"), std::string::npos)
      << range;
}

TEST(RunSummary, JsonRoundTrip) {
  const RunSummary a = sample_summary();
  const RunSummary b = run_summary_from_json(nlohmann::json::parse(to_json(a).dump()));
  EXPECT_EQ(to_json(a), to_json(b));
  EXPECT_EQ(b.program, a.program);
  EXPECT_EQ(b.final_status.junction_flows, 876u);
  EXPECT_DOUBLE_EQ(b.final_status.program_time_s, 47.8915);
  EXPECT_DOUBLE_EQ(b.transform.scale, 0.25);
  EXPECT_EQ(b.pauses, 2u);
  EXPECT_EQ(b.pauses_mode, "continue");
  EXPECT_EQ(b.pause_lines, (std::vector<std::uint32_t>{17, 402}));
  EXPECT_DOUBLE_EQ(b.smoothing_max_tolerance_mm, 0.01);
  EXPECT_DOUBLE_EQ(b.smoothing_min_tolerance_mm, 0.005);
  EXPECT_EQ(b.packed_arcs, 603u);
  EXPECT_EQ(b.packed_curves, 1u);
  EXPECT_EQ(b.packed_blocks, 41u);
  EXPECT_DOUBLE_EQ(b.packed_max_deviation_mm, 2.5e-10);
  nlohmann::json broken = to_json(a);
  nlohmann::json older = to_json(a);  // a summary written before path_tolerance_mm existed
  older.erase("path_tolerance_mm");
  older["job"].erase("pauses");  // nor pauses, nor the smoothing's tolerances
  older["check"].erase("smoothing_tolerance_mm");
  for (const char* k : {"packed_arcs", "packed_curves", "packed_blocks", "packed_max_deviation_mm"}) older["check"].erase(k);
  const RunSummary old_one = run_summary_from_json(older);
  EXPECT_EQ(old_one.packed_arcs, 0u);
  EXPECT_EQ(old_one.path_tolerance_mm, 0.0);
  EXPECT_EQ(old_one.pauses, 0u);
  EXPECT_EQ(old_one.smoothing_max_tolerance_mm, 0.0);
  broken["status"].erase("underruns");
  EXPECT_THROW(run_summary_from_json(broken), nlohmann::json::exception);
  const Vec3 rms = rms_following_error(a.final_status);
  EXPECT_NEAR(rms[0], 0.001, 1e-12);
  EXPECT_NEAR(rms[1], 0.002, 1e-12);
  EXPECT_NEAR(rms[2], 0.0005, 1e-12);
  EXPECT_NEAR(rms_contour_error(a.final_status), 0.003, 1e-12);
}

std::string span(const std::string& html, const std::string& id) {
  const std::regex re("id=\"" + id + "\">([^<]*)<");
  std::smatch m;
  return std::regex_search(html, m, re) ? m[1].str() : std::string("(missing " + id + ")");
}

ReportPage sample_page() {
  ReportPage page;
  page.summary = sample_summary();
  page.trace = square_digest();
  page.has_trace = true;
  return page;
}

TEST(ReportHtml, FiguresEqualTheSummary) {
  const std::string html = render_report_html(sample_page());
  EXPECT_EQ(span(html, "machine-time"), "47.892");
  EXPECT_EQ(span(html, "feed-time"), "41.235");
  EXPECT_EQ(span(html, "time-ratio"), "1.161");
  EXPECT_EQ(span(html, "replay-speed"), "96");
  EXPECT_EQ(span(html, "lines"), "1234");
  EXPECT_EQ(span(html, "blocks-sent"), "1201");
  EXPECT_EQ(span(html, "junction-flows"), "876");
  EXPECT_EQ(span(html, "junction-stops"), "324");
  EXPECT_EQ(span(html, "packed-arcs"), "603");
  EXPECT_EQ(span(html, "packed-blocks"), "41");
  EXPECT_EQ(span(html, "packed-curves"), "1");
  EXPECT_EQ(span(html, "packed-deviation"), "0.000");
  EXPECT_EQ(span(html, "ferr-max-x"), "4.12");
  EXPECT_EQ(span(html, "ferr-max-y"), "3.77");
  EXPECT_EQ(span(html, "ferr-max-z"), "1.51");
  EXPECT_EQ(span(html, "ferr-rms-x"), "1.00");
  EXPECT_EQ(span(html, "ferr-rms-y"), "2.00");
  EXPECT_EQ(span(html, "ferr-rms-z"), "0.50");
  EXPECT_EQ(span(html, "contour-max"), "7.34");
  EXPECT_EQ(span(html, "contour-rms"), "3.00");
  EXPECT_EQ(span(html, "underruns"), "3");
  EXPECT_EQ(span(html, "rt-compute-p99"), "3.25");
  EXPECT_EQ(span(html, "refill-p99"), "87.5");
  EXPECT_EQ(span(html, "scale"), "0.250000");
  EXPECT_EQ(span(html, "offset-z"), "20.0000");
  // no corner tolerance in the sample: the page says nothing of one
  EXPECT_EQ(html.find("id=\"path-tolerance\""), std::string::npos);
  ReportPage merging = sample_page();
  merging.summary.path_tolerance_mm = 0.01;
  EXPECT_EQ(span(render_report_html(merging), "path-tolerance"), "10.0");
  EXPECT_EQ(span(html, "pauses"), "2");  // M0/M1 gone on from (pcnc run --pauses)
  EXPECT_NE(html.find("M0/M1 on lines 17, 402"), std::string::npos);
  EXPECT_EQ(span(html, "final-x"), "12.5001");
  EXPECT_EQ(span(html, "last-point-z"), "20.5000");
  EXPECT_EQ(span(html, "result"), "completed");
  // the program name is escaped, not markup
  EXPECT_NE(html.find("part &lt;1&gt;.ngc"), std::string::npos);
  EXPECT_EQ(html.find("part <1>"), std::string::npos);
}

// Every <svg ...>...</svg> element of the page.
std::vector<std::string> svgs(const std::string& html) {
  std::vector<std::string> out;
  std::size_t at = 0;
  while ((at = html.find("<svg", at)) != std::string::npos) {
    const std::size_t end = html.find("</svg>", at);
    if (end == std::string::npos) break;
    out.push_back(html.substr(at, end + 6 - at));
    at = end;
  }
  return out;
}

TEST(ReportHtml, PicturesArePresentAndSelfContained) {
  const ReportPage page = sample_page();
  const std::string html = render_report_html(page);
  const auto all = svgs(html);
  ASSERT_EQ(all.size(), 4u) << "isometric, top view, speed, following error";
  EXPECT_NE(all[0].find("class=\"toolpath\""), std::string::npos);
  EXPECT_NE(all[1].find("class=\"topview\""), std::string::npos);
  EXPECT_NE(all[2].find("class=\"speed-plot\""), std::string::npos);
  EXPECT_NE(all[3].find("class=\"ferr-plot\""), std::string::npos);
  for (const std::string& svg : all) EXPECT_TRUE(svg.find("<polyline") != std::string::npos || svg.find("<path") != std::string::npos) << svg.substr(0, 80);
  // tool path: rapids and feeds, the red dot at the final position
  EXPECT_NE(all[0].find("class=\"rapid\""), std::string::npos);
  EXPECT_NE(all[0].find("class=\"feed\""), std::string::npos);
  EXPECT_NE(all[0].find("id=\"final-tool\""), std::string::npos);
  EXPECT_NE(all[0].find("fill=\"#ff2d2d\""), std::string::npos);
  // three following-error series
  std::size_t series = 0;
  for (std::size_t at = 0; (at = all[3].find("class=\"series\"", at)) != std::string::npos; ++at) ++series;
  EXPECT_EQ(series, 3u);
  // nothing loaded from elsewhere: the 3D view's scripts are inline
  EXPECT_EQ(html.find("<script src"), std::string::npos);
  EXPECT_EQ(html.find(" src="), std::string::npos);
  EXPECT_EQ(html.find("https://"), std::string::npos);
  EXPECT_EQ(html.find("<link"), std::string::npos);
  EXPECT_EQ(html.find("@import"), std::string::npos);
  EXPECT_EQ(html.find("url(http"), std::string::npos);
}

TEST(ReportHtml, WithoutATraceSaysSo) {
  ReportPage page;
  page.summary = sample_summary();
  page.trace_note = "the run was made without a trace";
  const std::string html = render_report_html(page);
  EXPECT_NE(html.find("no trace"), std::string::npos);
  EXPECT_EQ(span(html, "machine-time"), "47.892") << "the figures are there all the same";
}

TEST(Progress, LineFormatRoundTripAndView) {
  const ProgressUpdate u{1234, 5000, 61.5};
  const auto back = parse_progress_update(format_progress_update(u));
  ASSERT_TRUE(back);
  EXPECT_EQ(back->line, 1234u);
  EXPECT_EQ(back->total_lines, 5000u);
  EXPECT_DOUBLE_EQ(back->machine_time_s, 61.5);
  EXPECT_FALSE(parse_progress_update("progress 1 2"));
  EXPECT_FALSE(parse_progress_update("done"));
  EXPECT_FALSE(parse_progress_update("progress 1 2 3 4"));

  const ProgressView v = make_progress_view(u, 10.0);
  EXPECT_NEAR(v.fraction, 0.2468, 1e-12);
  ASSERT_TRUE(v.remaining_s);
  EXPECT_NEAR(*v.remaining_s, 10.0 * (1 - 0.2468) / 0.2468, 1e-9);
  EXPECT_FALSE(make_progress_view({10, 5000, 1.0}, 3.0).remaining_s) << "no guess before 1 %";
  const std::string bar = format_progress_bar(v, u, 20);
  EXPECT_EQ(bar.substr(0, 22), "[####................]");
  EXPECT_NE(bar.find("24.7 %"), std::string::npos) << bar;
  EXPECT_NE(bar.find("line 1234/5000"), std::string::npos) << bar;
  EXPECT_NE(bar.find("elapsed 0:10"), std::string::npos) << bar;
  EXPECT_NE(bar.find("left 0:31"), std::string::npos) << bar;
  EXPECT_EQ(format_duration(3725), "1:02:05");
  EXPECT_EQ(format_duration(75), "1:15");
}

// What a display wrote to the temporary file `f`; closes it.
std::string read_back_and_close(std::FILE* f) {
  std::rewind(f);
  char buf[512];
  std::string text;
  while (std::fgets(buf, sizeof buf, f)) text += buf;
  std::fclose(f);
  return text;
}

TEST(Progress, PlainLinesWhenNotATerminal) {
  std::FILE* f = std::tmpfile();
  ASSERT_NE(f, nullptr);
  EXPECT_FALSE(ProgressDisplay::is_terminal(f));
  ProgressDisplay d(f, false, 0.0);  // every update logs
  d.update({100, 1000, 5.0});
  d.update({200, 1000, 10.0});
  d.finish();
  const std::string text = read_back_and_close(f);
  EXPECT_NE(text.find("pcnc: line 100/1000 (10.0 %)"), std::string::npos) << text;
  EXPECT_NE(text.find("pcnc: line 200/1000 (20.0 %)"), std::string::npos) << text;
  EXPECT_EQ(text.find('\r'), std::string::npos) << "no terminal control in a log";
  EXPECT_EQ(text.find("\x1b["), std::string::npos);
}

// The check's progress: the line the host writes (pcnc run), and the bar and log line that show it.
TEST(Progress, TheChecksProgressLineBarAndLog) {
  CheckProgress c;
  c.pass = CheckPass::kCheck;
  c.line = 12345;
  c.bytes_read = 452;
  c.total_bytes = 1000;
  c.blocks = 777;
  const std::string line = format_check_progress(c);
  EXPECT_EQ(line, "checking check 12345 452 1000 777\n");
  const auto back = parse_check_progress(line);
  ASSERT_TRUE(back);
  EXPECT_EQ(back->pass, CheckPass::kCheck);
  EXPECT_EQ(back->line, 12345u);
  EXPECT_EQ(back->bytes_read, 452u);
  EXPECT_EQ(back->total_bytes, 1000u);
  EXPECT_EQ(back->blocks, 777u);
  EXPECT_EQ(parse_check_progress("checking fit 1 2 3 0")->pass, CheckPass::kFit);
  EXPECT_FALSE(parse_check_progress("checking run 1 2 3 4"));
  EXPECT_FALSE(parse_check_progress("checking check 1 2 3"));
  EXPECT_FALSE(parse_check_progress("checking check 1 2 3 4 5"));
  EXPECT_FALSE(parse_check_progress("progress 1 2 3"));
  EXPECT_FALSE(parse_progress_update(line)) << "the run's display does not take it for a run update";

  EXPECT_DOUBLE_EQ(c.fraction(), 0.452);
  EXPECT_DOUBLE_EQ(CheckProgress{}.fraction(), 0.0) << "no size: no fraction";
  const std::string bar = format_check_bar(c, 12.0, 15.0, 10);
  EXPECT_EQ(bar, "checking  [####......]  45.2 %  line 12345  elapsed 0:12  left 0:15");
  c.pass = CheckPass::kFit;
  EXPECT_EQ(format_check_bar(c, 3.0, std::nullopt, 0), "measuring for --fit   45.2 %  line 12345  elapsed 0:03  left ?");
  EXPECT_EQ(format_check_log(c, 3.0, std::nullopt),
            "pcnc: measuring for --fit line 12345 (45.2 % of the file), elapsed 0:03, unknown time left");

  // the display: plain lines (not a terminal), the time left from the pace of the pass
  std::FILE* f = std::tmpfile();
  ASSERT_NE(f, nullptr);
  {
    ProgressDisplay d(f, false, 0.0);  // every update logs
    CheckProgress p;
    p.total_bytes = 1000;
    p.bytes_read = 100;
    p.line = 10;
    d.checking(p);  // first sight of the pass: no pace yet
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    p.bytes_read = 300;
    p.line = 30;
    d.checking(p);  // 20 % in at least 50 ms: 70 % left at that pace
    d.finish();
  }
  const std::string text = read_back_and_close(f);
  EXPECT_NE(text.find("pcnc: checking line 10 (10.0 % of the file)"), std::string::npos) << text;
  EXPECT_NE(text.find("unknown time left\npcnc: checking line 30 (30.0 % of the file)"), std::string::npos) << text;
  EXPECT_TRUE(std::regex_search(text, std::regex("pcnc: checking line 30 .*, about [0-9]+:[0-9]{2} left")))
      << "a guess once the pass has gone on: " << text;
  EXPECT_EQ(text.find('\r'), std::string::npos) << "no terminal control in a log";
}

// ---- headless Chromium: the page renders and is not blank ----

// PNG: signature, IHDR width and height (big-endian at bytes 16..23).
bool png_size(const std::string& data, std::uint32_t& w, std::uint32_t& h) {
  if (data.size() < 24 || data.compare(0, 8, "\x89PNG\r\n\x1a\n") != 0) return false;
  auto be = [&](std::size_t at) {
    return (static_cast<std::uint32_t>(static_cast<unsigned char>(data[at])) << 24) |
           (static_cast<std::uint32_t>(static_cast<unsigned char>(data[at + 1])) << 16) |
           (static_cast<std::uint32_t>(static_cast<unsigned char>(data[at + 2])) << 8) |
           static_cast<std::uint32_t>(static_cast<unsigned char>(data[at + 3]));
  };
  w = be(16);
  h = be(20);
  return true;
}

TEST(ReportChromium, RendersAScreenshotThatIsNotBlank) {
  const std::string chromium = test::find_chromium();
  if (chromium.empty()) GTEST_SKIP() << "chromium is not installed (tools/install-deps.sh installs it): the headless rendering test did not run";
  const std::string dir = test::make_temp_dir("chromium");
  const std::string html = dir + "/report.html";
  std::ofstream(html) << render_report_html(sample_page());
  const std::string png = dir + "/report.png";
  const std::string blank_html = dir + "/blank.html", blank_png = dir + "/blank.png";
  std::ofstream(blank_html) << "<!DOCTYPE html><html><body style=\"background:#f3f4f7\"></body></html>";
  auto shoot = [&](const std::string& page, const std::string& out) {
    return test::chromium_screenshot(chromium, "file://" + page, out, out + ".profile");
  };
  const test::ProcessResult r = shoot(html, png);
  ASSERT_TRUE(fs::exists(png)) << "exit " << r.exit_code << "\n" << r.err;
  const test::ProcessResult rb = shoot(blank_html, blank_png);
  ASSERT_TRUE(fs::exists(blank_png)) << rb.err;

  const std::string data = test::read_file(png), blank = test::read_file(blank_png);
  std::uint32_t w = 0, h = 0;
  ASSERT_TRUE(png_size(data, w, h)) << "not a PNG";
  EXPECT_EQ(w, 1200u);
  EXPECT_EQ(h, 1600u);
  // A blank page of the same size compresses to almost nothing; the report's lines, text and
  // colours do not. (Sizes seen: blank about 10 kB, the report over 100 kB.)
  EXPECT_GT(data.size(), 60000u) << "the screenshot is suspiciously small";
  EXPECT_GT(data.size(), 5 * blank.size()) << "report " << data.size() << " bytes vs blank " << blank.size();
  fs::remove_all(dir);
}

// The report draws rapids from the lines the run's check recorded (no front end of its own).
// The check's plan in the summary: each entry written as text ("%.9g" speeds, "%.4g" angles)
// and read back field by field (std::from_chars) to the values written, every junction kind
// and cause key; an entry with a field missing, one too many, or a word for a number is refused.
TEST(RunSummary, PlanEntriesRoundTripAndMalformedOnesAreRefused) {
  RunSummary a = sample_summary();
  a.plan.clear();
  for (int k = 0; k < kTimeCauseCount; ++k) {
    LinePlan p;
    p.first = 10u * static_cast<std::uint32_t>(k) + 1u;
    p.last = p.first + static_cast<std::uint32_t>(k % 3);
    p.cruise = static_cast<TimeCause>(k);
    p.accel = static_cast<TimeCause>((k + 3) % kTimeCauseCount);
    p.speed = 12.345678912 * (k + 1);
    p.before = static_cast<JunctionKind>(k % 6);
    p.after = static_cast<JunctionKind>((k + 1) % 6);
    p.angle_before_deg = k == 0 ? -1.0 : 0.125 * k;
    p.angle_after_deg = 179.5 - k;
    a.plan.push_back(p);
  }
  const nlohmann::json j = to_json(a);
  const RunSummary b = run_summary_from_json(nlohmann::json::parse(j.dump()));
  ASSERT_EQ(b.plan.size(), a.plan.size());
  for (std::size_t i = 0; i < a.plan.size(); ++i) {
    const LinePlan &x = a.plan[i], &y = b.plan[i];
    EXPECT_EQ(y.first, x.first);
    EXPECT_EQ(y.last, x.last);
    EXPECT_EQ(y.cruise, x.cruise);
    EXPECT_EQ(y.accel, x.accel);
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.9g", x.speed);
    EXPECT_EQ(y.speed, std::strtod(buf, nullptr)) << i;  // what sscanf's %lf read before
    EXPECT_EQ(y.before, x.before);
    EXPECT_EQ(y.after, x.after);
    std::snprintf(buf, sizeof buf, "%.4g", x.angle_before_deg);
    EXPECT_EQ(y.angle_before_deg, std::strtod(buf, nullptr)) << i;
    std::snprintf(buf, sizeof buf, "%.4g", x.angle_after_deg);
    EXPECT_EQ(y.angle_after_deg, std::strtod(buf, nullptr)) << i;
  }
  // the plan is one string, its entries separated by ';'
  const std::string text = j["check"]["plan"].get<std::string>();
  const std::string good = text.substr(0, text.find(';'));
  const std::string rest = text.substr(good.size());
  EXPECT_EQ(std::count(text.begin(), text.end(), ';'), static_cast<long>(a.plan.size()) - 1);
  for (const std::string& bad : {good.substr(0, good.rfind(',')), good + ",1", "x" + good, std::string("1,2,feed,nokey,3,0,0,0,0"),
                                std::string("1,2,feed,feed,3,0,9,0,0"), std::string("1,2,feed,feed,fast,0,0,0,0"), std::string()}) {
    nlohmann::json broken = j;
    broken["check"]["plan"] = bad + rest;
    EXPECT_THROW(run_summary_from_json(broken), std::runtime_error) << bad;
  }
  // a summary written before: the plan as an array of entries, read the same
  nlohmann::json older = j;
  older["check"]["plan"] = nlohmann::json::array();
  for (std::size_t at = 0; at <= text.size();) {
    const std::size_t end = std::min(text.find(';', at), text.size());
    older["check"]["plan"].push_back(text.substr(at, end - at));
    at = end + 1;
  }
  const RunSummary c = run_summary_from_json(older);
  ASSERT_EQ(c.plan.size(), a.plan.size());
  for (std::size_t i = 0; i < a.plan.size(); ++i) {
    EXPECT_EQ(c.plan[i].first, b.plan[i].first);
    EXPECT_EQ(c.plan[i].speed, b.plan[i].speed);
    EXPECT_EQ(c.plan[i].angle_after_deg, b.plan[i].angle_after_deg);
  }
}

// write_run_summary writes the plan's text around nlohmann's writer, and read_run_summary takes
// it out before the parse (the plan is nearly all of a summary's bytes): the file is exactly what
// nlohmann writes for the whole summary, and reads back to the same summary, even when another
// string holds the text of the plan's key; a summary without the pretty-printer's spacing
// (edited by hand, or by a tool) reads the same through the parser alone.
TEST(RunSummary, TheFileIsNlohmannsTextAndReadsBackTheSame) {
  RunSummary a = sample_summary();
  a.program = "odd \"plan\": \"name\".ngc";
  a.message = R"("plan": "x;y")";
  a.plan.clear();
  for (std::uint32_t k = 1; k <= 300; ++k) {
    LinePlan p;
    p.first = k;
    p.last = k + 2;
    p.speed = 1.0 / k;
    p.angle_after_deg = 3.0 * k;
    a.plan.push_back(p);
  }
  const std::string dir = test::make_temp_dir("summary_text");
  const std::string path = dir + "/s.json";
  write_run_summary(a, path);
  std::ifstream f(path);
  const std::string text{std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
  EXPECT_EQ(text, to_json(a).dump(2) + "\n");
  const RunSummary b = read_run_summary(path);
  EXPECT_EQ(b.program, a.program);
  EXPECT_EQ(b.message, a.message);
  ASSERT_EQ(b.plan.size(), a.plan.size());
  for (std::size_t i = 0; i < a.plan.size(); ++i) {
    EXPECT_EQ(b.plan[i].last, a.plan[i].last) << i;
    EXPECT_NEAR(b.plan[i].speed, a.plan[i].speed, 1e-8 * a.plan[i].speed) << i;  // nine digits
  }
  {
    std::ofstream compact(path);
    compact << to_json(a).dump() << "\n";
  }
  const RunSummary c = read_run_summary(path);
  ASSERT_EQ(c.plan.size(), a.plan.size());
  EXPECT_EQ(c.plan.back().first, a.plan.back().first);
  std::filesystem::remove_all(dir);
}

TEST(RunSummary, RapidLinesRoundTripAndOlderSummariesHaveNone) {
  RunSummary a = sample_summary();
  a.rapid_lines = {{1, 1}, {7, 9}};
  const RunSummary b = run_summary_from_json(nlohmann::json::parse(to_json(a).dump()));
  ASSERT_EQ(b.rapid_lines.size(), 2u);
  EXPECT_EQ(b.rapid_lines[1].first, 7u);
  EXPECT_EQ(b.rapid_lines[1].last, 9u);
  nlohmann::json older = to_json(a);
  older["check"].erase("rapid_lines");
  EXPECT_TRUE(run_summary_from_json(older).rapid_lines.empty());
  RunReport r;
  r.check.rapid_lines = {{3, 4}};
  EXPECT_EQ(make_run_summary(r, MachineConfig{}, "c.toml", false).rapid_lines.size(), 1u);
}

}  // namespace
}  // namespace pcnc

namespace pcnc {
namespace {

// A rapid at 100 mm/s, then four feed sides at 10 mm/s that each start and end at rest: the
// speed plot keeps the feed's own scale, marks the rapid, draws the planned speed, the cause
// band and the line axis; the time table adds up to the machine time.
TEST(ReportHtml, SpeedPlotAndWhereTheTimeWent) {
  std::vector<LinePlan> plan;
  LinePlan r;
  r.first = r.last = 1;
  r.cruise = TimeCause::kRapid;
  r.speed = 100.0;
  plan.push_back(r);
  for (std::uint32_t l = 2; l <= 5; ++l) {
    LinePlan f;
    f.first = f.last = l;
    f.speed = 10.0;
    f.before = f.after = JunctionKind::kAngleStop;
    f.angle_before_deg = f.angle_after_deg = 90.0;
    plan.push_back(f);
  }
  const CauseClassifier k(plan);
  DigestOptions o;
  o.max_buckets = 400;
  o.is_rapid_line = [](std::uint32_t line) { return line == 1; };
  o.cause_of = [&k](const TraceSample& row, double prev) { return k.classify(row, prev); };
  TraceDigester d(o);
  double t = 0.0;
  for (int i = 0; i < 200; ++i) d.add(row(t += 0.0005, 1, MachineState::kRunning, {}, {}, i < 100 ? i : 200 - i));
  for (std::uint32_t side = 0; side < 4; ++side) {
    for (int i = 0; i < 400; ++i) {
      const double v = std::min({10.0, 0.5 * i, 0.5 * (399 - i)});  // up, cruise, down to rest
      d.add(row(t += 0.0005, 2 + side, MachineState::kRunning, {}, {}, v));
    }
  }
  ReportPage page;
  page.summary = sample_summary();
  page.summary.plan = plan;
  page.trace = d.finish();
  page.has_trace = true;
  const double program_time = page.summary.final_status.program_time_s;
  page.summary.time_by_cause = time_by_cause(page.trace.cause_rows, program_time);
  page.slowest = slowest_stretches(page.trace, k, program_time / static_cast<double>(page.trace.program_rows), 12);
  const std::string html = render_report_html(page);

  const auto all = svgs(html);
  ASSERT_EQ(all.size(), 4u);
  const std::string& speed = all[2];
  EXPECT_NE(speed.find("class=\"marked\""), std::string::npos) << "the rapid's slices are shaded";
  EXPECT_NE(speed.find("class=\"reference\""), std::string::npos) << "the planned speed";
  EXPECT_NE(speed.find("class=\"cause-band\""), std::string::npos);
  EXPECT_NE(speed.find("class=\"line-tick\""), std::string::npos);
  EXPECT_NE(speed.find(">10</text>"), std::string::npos) << "the feed's scale tops at 10 mm/s";
  EXPECT_EQ(speed.find(">100</text>"), std::string::npos) << "the rapid's 100 mm/s does not squash it";

  double sum = 0.0;
  for (const auto& [key, sec] : page.summary.time_by_cause) sum += std::stod(span(html, "cause-" + key));
  EXPECT_NEAR(sum, program_time, 0.0005 * static_cast<double>(page.summary.time_by_cause.size()));
  EXPECT_GT(page.trace.cause_rows[static_cast<std::size_t>(TimeCause::kJunctionStop)], 4u * 30u);
  ASSERT_EQ(page.slowest.size(), 5u) << "every line lost time";
  EXPECT_EQ(page.slowest[0].line, 1u) << "the rapid never cruises: it starts and ends the program at rest";
  EXPECT_EQ(page.slowest[0].cause, TimeCause::kStartEndStop);
  for (std::size_t i = 1; i < 5; ++i) {
    EXPECT_EQ(page.slowest[i].cause, TimeCause::kJunctionStop) << page.slowest[i].line;
    EXPECT_NEAR(page.slowest[i].angle_deg, 90.0, 1e-9);
    EXPECT_LE(page.slowest[i].lost_s, page.slowest[i - 1].lost_s) << "most lost first";
  }
  EXPECT_NE(html.find("turn 90.0°"), std::string::npos);
}

// Cutter compensation: the top view draws the programmed contour over the tool path, the
// figures name the tool diameter, and the summary JSON keeps both.
TEST(ReportHtml, CutterCompensationContourAndToolDiameter) {
  ReportPage page = sample_page();
  page.summary.comp_entries = 1;
  page.summary.comp_moves_in = 4;
  page.summary.comp_moves_out = 6;
  page.summary.comp_tool_diameter_mm = 3.0;
  page.summary.comp_biarcs = 9;
  page.summary.comp_moves_replaced = 40;
  page.summary.comp_contour = {{{5, 5, 24}, {20, 5, 24}, {20, 20, 24}, {5, 20, 24}, {5, 5, 24}}};
  const std::string html = render_report_html(page);
  const auto all = svgs(html);
  ASSERT_GE(all.size(), 2u);
  const std::string& top = all[1];
  const std::size_t g = top.find("class=\"comp-contour\"");
  ASSERT_NE(g, std::string::npos);
  const std::size_t pl = top.find("<polyline points=\"", g);
  ASSERT_NE(pl, std::string::npos);
  const std::string pts = top.substr(pl, top.find("\"/>", pl) - pl);
  EXPECT_EQ(std::count(pts.begin(), pts.end(), ','), 5) << pts;  // the five contour points
  EXPECT_NE(top.find("tool diameter 3.000 mm"), std::string::npos);
  EXPECT_EQ(span(html, "comp-tool-diameter"), "3.0000");
  const RunSummary back = run_summary_from_json(to_json(page.summary));
  EXPECT_EQ(back.comp_entries, 1u);
  EXPECT_EQ(back.comp_moves_out, 6u);
  EXPECT_EQ(back.comp_biarcs, 9u);
  EXPECT_EQ(back.comp_moves_replaced, 40u);
  EXPECT_NE(html.find("9 biarcs replaced 40 programmed moves"), std::string::npos);
  EXPECT_DOUBLE_EQ(back.comp_tool_diameter_mm, 3.0);
  ASSERT_EQ(back.comp_contour.size(), 1u);
  EXPECT_EQ(back.comp_contour[0].size(), 5u);
  // Without compensation the top view has no contour and the JSON no cutter_comp.
  const std::string plain = render_report_html(sample_page());
  EXPECT_EQ(plain.find("comp-contour"), std::string::npos);
  EXPECT_FALSE(to_json(sample_summary())["check"].contains("cutter_comp"));
}

}  // namespace
}  // namespace pcnc
