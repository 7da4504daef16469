// test_segment_merge.cpp — the naive-CAM detector (host/segment_merge.hpp): runs of collinear
// G1 moves under M21 become one line within the tolerance, nothing else is touched, and the
// block stream of a tiny-segment program carries far fewer, longer blocks to the same end.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include "gcode/program.hpp"
#include "gcode/segment_merge.hpp"
#include "gcode_test_util.hpp"

namespace pcnc {
namespace {

using test::line_move;

std::vector<Move> merge_all(const std::vector<Move>& in, double tol) {
  SegmentMerger merger;
  std::size_t next = 0;
  auto pull = [&](Move& m) {
    if (next >= in.size()) return false;
    m = in[next++];
    m.path_tolerance_mm = tol;  // what the interpreter gives each move (G64 P, --tolerance, config)
    return true;
  };
  std::vector<Move> out;
  Move m;
  while (merger.next(pull, m)) out.push_back(m);
  return out;
}

double distance_to_segment(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double t = std::clamp(dot(p - a, ab) / dot(ab, ab), 0.0, 1.0);
  return norm(a + t * ab - p);
}

// 0.031 mm chords of an R20 circle with a Z ripple, as CAM output (tiny.ngc's shape).
std::vector<Move> tiny_circle(int n, bool contouring = true) {
  std::vector<Move> v;
  auto at = [](int i) {
    const double a = 2.0 * std::numbers::pi * i / 4000.0;
    return Vec3{20.0 * std::cos(a), 20.0 * std::sin(a), -0.5 + 0.5 * std::cos(8.0 * a)};
  };
  for (int i = 1; i <= n; ++i) v.push_back(line_move(at(i - 1), at(i), i, 16.7, contouring));
  return v;
}

TEST(SegmentMerge, FitsIsTheDistanceOfEveryPointToTheChord) {
  const std::vector<Vec3> pts{{0, 0, 0}, {1, 0.004, 0}, {2, -0.004, 0}};
  EXPECT_TRUE(SegmentMerger::fits(pts, {3, 0, 0}, 0.005));
  EXPECT_FALSE(SegmentMerger::fits(pts, {3, 0, 0}, 0.003));
  EXPECT_FALSE(SegmentMerger::fits({{0, 0, 0}, {1, 0, 0}}, {1, 1, 0}, 0.01)) << "a corner";
  EXPECT_FALSE(SegmentMerger::fits({{0, 0, 0}, {1, 0, 0}}, {0, 0, 0}, 0.01)) << "back to the start";
}

TEST(SegmentMerge, TinyCircleSegmentsMergeWithinTheTolerance) {
  const std::vector<Move> in = tiny_circle(4000);
  const double tol = 0.01;
  const std::vector<Move> out = merge_all(in, tol);
  ASSERT_FALSE(out.empty());
  EXPECT_LT(out.size() * 10, in.size()) << "at least ten segments per merged line";
  // a continuous chain from the first start to the last end, lines rising, feed kept
  EXPECT_EQ(out.front().start, in.front().start);
  EXPECT_EQ(out.back().end, in.back().end);
  EXPECT_EQ(out.back().line, in.back().line);
  for (std::size_t k = 1; k < out.size(); ++k) {
    EXPECT_EQ(out[k].start, out[k - 1].end);
    EXPECT_GT(out[k].line, out[k - 1].line);
    EXPECT_EQ(out[k].feed_mm_s, 16.7);
  }
  // every programmed point lies within the tolerance of the merged line that replaced it
  std::size_t j = 0;
  for (const Move& m : out) {
    for (; j < in.size() && in[j].line <= m.line; ++j) {
      EXPECT_LE(distance_to_segment(in[j].end, m.start, m.end), tol) << "line " << in[j].line;
    }
  }
  EXPECT_EQ(j, in.size());
}

TEST(SegmentMerge, OnlyFeedMovesUnderM21WithTheSameFeedMerge) {
  std::vector<Move> in;
  for (int i = 0; i < 10; ++i) in.push_back(line_move({i * 0.1, 0, 0}, {(i + 1) * 0.1, 0, 0}, i + 1));
  EXPECT_EQ(merge_all(in, 0.01).size(), 1u);
  EXPECT_EQ(merge_all(in, 0.0).size(), 10u) << "tolerance 0: off";
  std::vector<Move> m22 = in;
  for (Move& m : m22) m.contouring = false;
  EXPECT_EQ(merge_all(m22, 0.01).size(), 10u) << "M22: every point is an exact stop";
  std::vector<Move> feeds = in;
  for (int i = 5; i < 10; ++i) feeds[static_cast<std::size_t>(i)].feed_mm_s = 20.0;
  EXPECT_EQ(merge_all(feeds, 0.01).size(), 2u) << "a feed change ends the run";
  std::vector<Move> rapid = in;
  rapid[4].kind = MoveKind::kRapid;
  const std::vector<Move> r = merge_all(rapid, 0.01);
  ASSERT_EQ(r.size(), 3u) << "a rapid is never merged and ends the run";
  EXPECT_EQ(r[1].kind, MoveKind::kRapid);
  // a 90° corner stays a corner
  const std::vector<Move> corner{line_move({0, 0, 0}, {1, 0, 0}, 1), line_move({1, 0, 0}, {1, 1, 0}, 2)};
  EXPECT_EQ(merge_all(corner, 0.01).size(), 2u);
}

TEST(SegmentMerge, LongStraightRunsAreCutAtTheRunLimit) {
  std::vector<Move> in;
  for (int i = 0; i < 1000; ++i) in.push_back(line_move({i * 0.01, 0, 0}, {(i + 1) * 0.01, 0, 0}, i + 1));
  const std::vector<Move> out = merge_all(in, 0.01);
  ASSERT_EQ(out.size(), 4u);  // 256 + 256 + 256 + 232 moves
  EXPECT_EQ(out[0].line, 256);
  EXPECT_EQ(out[3].end, in.back().end);
}

// Through the block stream: the path tolerance in the config turns smoothing (and merging) on.
TEST(SegmentMerge, BlockStreamCarriesFewerLongerBlocksToTheSameEnd) {
  std::string text = "G21 G90 G17 M21\nG0 X20 Y0 Z-1\nG1 F1000\n";
  for (int i = 1; i <= 2000; ++i) {
    const double a = 2.0 * std::numbers::pi * i / 4000.0;
    char buf[96];
    std::snprintf(buf, sizeof buf, "G1 X%.4f Y%.4f\n", 20.0 * std::cos(a), 20.0 * std::sin(a));
    text += buf;
  }
  text += "M30\n";
  MachineConfig c = load_config(test::source_dir() + "/configs/bench-peers.toml");
  JobOptions o;
  auto count = [&](double tol, Vec3* last) {
    c.motion.path_tolerance_mm = tol;
    const CheckResult chk = check_program_text(text, "tiny.ngc", c, o);
    EXPECT_TRUE(chk.ok);
    BlockStream s(BlockStream::FromText{}, text, "tiny.ngc", c, o, chk.transform);
    Block b{};
    std::size_t n = 0;
    while (s.next(b)) {
      ++n;
      if (b.kind == BlockKind::kLine || b.kind == BlockKind::kNurbs) *last = b.end;
    }
    return n;
  };
  Vec3 end_merged{}, end_plain{};
  const std::size_t merged = count(0.01, &end_merged), plain = count(0.0, &end_plain);
  EXPECT_EQ(plain, 2002u);  // the rapid, 2000 lines (the F line moves nothing), the end
  EXPECT_LT(merged * 10, plain);
  EXPECT_EQ(end_merged, end_plain);
}

}  // namespace
}  // namespace pcnc
