// test_planned_time.cpp — the ETA's parts: each block's planned time (a rest-to-rest
// trapezoid or triangle at the block's own limits, a dwell's time, nothing for the end), the
// check's total as the sum over exactly the blocks that are sent, and the two views built on
// it: pcnc run's progress bar (progress lines with the plan) and `pcnc ctl status --watch`.
#include <gtest/gtest.h>

#include <cmath>

#include "config/config.hpp"
#include "ctl_watch.hpp"
#include "gcode/planned_time.hpp"
#include "gcode/program.hpp"
#include "progress.hpp"
#include "test_paths.hpp"

namespace pcnc {
namespace {

using json = nlohmann::json;

Block line(double length, double speed, double accel) {
  Block b{};
  b.kind = BlockKind::kLine;
  b.length = length;
  b.speed = speed;
  b.accel = accel;
  return b;
}

TEST(PlannedTime, TrapezoidTriangleDwellAndEnd) {
  // 10 mm at 5 mm/s, 100 mm/s²: 0.05 s to speed and back, 10/5 + 5/100 s.
  EXPECT_NEAR(planned_time_s(line(10.0, 5.0, 100.0)), 2.05, 1e-12);
  // 0.1 mm never reaches 20 mm/s at 100 mm/s² (needs 4 mm): 2 sqrt(L/a).
  EXPECT_NEAR(planned_time_s(line(0.1, 20.0, 100.0)), 2.0 * std::sqrt(0.001), 1e-12);
  Block d{};
  d.kind = BlockKind::kDwell;
  d.dwell_s = 0.75;
  EXPECT_DOUBLE_EQ(planned_time_s(d), 0.75);
  Block e{};
  e.kind = BlockKind::kEnd;
  EXPECT_DOUBLE_EQ(planned_time_s(e), 0.0);
  Block a{};
  a.kind = BlockKind::kArc;
  a.arc.sweep = -M_PI;
  a.arc.angular_speed = 1.0;
  a.arc.angular_accel = 1000.0;
  EXPECT_NEAR(planned_time_s(a), M_PI + 0.001, 1e-12) << "an arc by its angle, either direction";
}

TEST(PlannedTime, TheCheckSumsTheBlocksItAccepts) {
  const MachineConfig c = load_config(test::default_config());
  const std::string text = "G21 G90\nG0 X1 Y1\nG1 X5 F300\nG4 P0.5\nG2 X5 Y3 I0 J1\nM2\n";
  double sum = 0.0;
  std::size_t blocks = 0;
  const CheckResult r = check_program_text(text, "p.ngc", c, JobOptions{}, [&](const Block& b) {
    sum += planned_time_s(b);
    ++blocks;
  });
  ASSERT_TRUE(r.ok);
  EXPECT_EQ(blocks, r.blocks);
  EXPECT_DOUBLE_EQ(r.planned_time_s, sum);
  // at least the feed moves at their feed plus the dwell; the 4 mm line alone is 0.8 s at F300
  EXPECT_GT(r.planned_time_s, r.feed_length_time_s + 0.5);
}

TEST(PlannedTime, RunProgressBarTakesItsFractionAndEtaFromThePlan) {
  ProgressUpdate u{12, 500, 30.0, 20.0, 80.0};
  const auto back = parse_progress_update(format_progress_update(u));
  ASSERT_TRUE(back);
  EXPECT_DOUBLE_EQ(back->planned_done_s, 20.0);
  EXPECT_DOUBLE_EQ(back->planned_total_s, 80.0);
  EXPECT_TRUE(parse_progress_update("progress 1 2 3")) << "an update without the plan is still read";
  EXPECT_FALSE(parse_progress_update("progress 1 2 3 4 -5"));
  // a program pause under pcnc run --pauses ask: the same channel, a line of its own
  const auto pause = parse_pause_request(format_pause_request({417, true}));
  ASSERT_TRUE(pause);
  EXPECT_EQ(pause->line, 417u);
  EXPECT_TRUE(pause->optional);
  EXPECT_FALSE(parse_pause_request("pause 3 M2"));
  EXPECT_FALSE(parse_pause_request("pause 3 M0 x"));
  EXPECT_FALSE(parse_progress_update(format_pause_request({3, false}))) << "a pause is not a progress update";
  EXPECT_FALSE(parse_pause_request(format_progress_update(u))) << "nor an update a pause";

  // A quarter of the plan done in 10 s of wall time: the rest at that pace is 30 s, whatever the
  // line count says (line 12 of 500).
  const ProgressView v = make_progress_view(u, 10.0);
  EXPECT_DOUBLE_EQ(v.fraction, 0.25);
  ASSERT_TRUE(v.remaining_s);
  EXPECT_DOUBLE_EQ(*v.remaining_s, 30.0);
  EXPECT_FALSE(make_progress_view({1, 500, 0.1, 0.5, 80.0}, 1.0).remaining_s) << "no guess before 1 %";
}

json watched(double done, double total, double program_time) {
  return json{{"state", "RUNNING"},
              {"line", 7},
              {"commanded", {{"x", 17.5}, {"y", 12.5}, {"z", 24.0}}},
              {"actual", {{"x", 17.499}, {"y", 12.5}, {"z", 24.0}}},
              {"following_error", {{"x", 0.001}, {"y", 0.0}, {"z", 0.0}}},
              {"work_position", {{"commanded", {{"x", 5.0}, {"y", 0.0}, {"z", -1.0}}}, {"actual", {{"x", 4.999}, {"y", 0.0}, {"z", -1.0}}}}},
              {"work_state", {{"active", "G55"}, {"G92", {{"x", 0}, {"y", 0}, {"z", 0}}}, {"G92_applied", false}}},
              {"work_offsets", {{"G55", {{"x", 12.5}, {"y", 12.5}, {"z", 25.0}}}}},
              {"program_time_s", program_time},
              {"job", {{"active", true}, {"file", "/p/part.ngc"}, {"planned_time_s", total}, {"planned_done_s", done}}}};
}

TEST(StatusWatch, ShowsBothCoordinatesTheOffsetAndTheTimeLeft) {
  const json s = watched(30.0, 120.0, 40.0);
  const auto p = watch_progress(s);
  ASSERT_TRUE(p);
  EXPECT_DOUBLE_EQ(p->fraction, 0.25);
  ASSERT_TRUE(p->remaining_s);
  EXPECT_DOUBLE_EQ(*p->remaining_s, 90.0 * 40.0 / 30.0) << "the plan left, at the pace so far";

  const auto lines = format_watch(s);
  std::string all;
  for (const auto& l : lines) all += l + "\n";
  EXPECT_NE(all.find("RUNNING"), std::string::npos) << all;
  EXPECT_NE(all.find("/p/part.ngc"), std::string::npos) << all;
  EXPECT_NE(all.find("X   17.5000"), std::string::npos) << "machine: " << all;
  EXPECT_NE(all.find("X    5.0000"), std::string::npos) << "work: " << all;
  EXPECT_NE(all.find("work mm (G55)"), std::string::npos) << all;
  EXPECT_NE(all.find("X     1.00 um"), std::string::npos) << "following error: " << all;
  EXPECT_NE(all.find(" 25.0 %  left 2:00"), std::string::npos) << all;
  EXPECT_EQ(format_watch(watched(0.0, 0.0, 0.0)).size(), lines.size()) << "the redrawn block keeps its height";

  const std::string line = format_watch_line(s);
  EXPECT_EQ(line.find('\n'), std::string::npos);
  EXPECT_NE(line.find("work G55 X    5.0000"), std::string::npos) << line;
  EXPECT_NE(line.find("25.0 % left 2:00"), std::string::npos) << line;
  EXPECT_FALSE(watch_progress(watched(0.0, 0.0, 1.0))) << "no plan, no bar";
}

// While the service checks the program (phase preflight), the watch shows the check's progress
// in the bar's place, and the block keeps its height.
TEST(StatusWatch, ShowsTheChecksProgressBeforeTheProgramRuns) {
  json s = watched(0.0, 0.0, 0.0);
  s["state"] = "IDLE";
  s["job"] = json{{"active", true}, {"file", "/p/big.ngc"}, {"phase", "preflight"},
                  {"check_pass", "check"}, {"check_line", 270336}, {"check_fraction", 0.452}};
  EXPECT_EQ(watch_check(s), "checking  [#############.................]  45.2 %  line 270336");
  const auto lines = format_watch(s);
  EXPECT_EQ(lines.size(), format_watch(watched(30.0, 120.0, 40.0)).size());
  EXPECT_EQ(lines.back(), watch_check(s));
  EXPECT_NE(format_watch_line(s).find("  checking  [#"), std::string::npos) << format_watch_line(s);
  s["job"]["check_pass"] = "fit";
  EXPECT_EQ(watch_check(s).rfind("measuring for --fit  [", 0), 0u) << watch_check(s);
  s["job"]["check_pass"] = "locate";  // a resume runs the program again up to where it stopped
  EXPECT_EQ(watch_check(s), "locating the stop  [#############.................]  45.2 %  line 270336");
  s["job"].erase("check_fraction");
  EXPECT_EQ(watch_check(s), "") << "no check under way: nothing";
  EXPECT_EQ(format_watch(s).back(), "");
}

}  // namespace
}  // namespace pcnc
