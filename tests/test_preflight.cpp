// test_preflight.cpp — soft limits (end points and arc extremes), --fit, figures, streaming.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>

#include "gcode_test_util.hpp"
#include "gcode/preflight.hpp"

namespace pcnc {
namespace {

using test::mill_config;
using test::run_program;

JobOptions at_zero() {
  JobOptions o;
  o.offset = Vec3{0, 0, 0};
  o.start_position = Vec3{0, 0, 0};
  return o;
}

TEST(Preflight, EndPointOutsideTravelIsAnErrorWithItsLine) {
  const auto r = run_program("G0 X1 Y1 Z1\nG0 X30\nM2\n", mill_config(), at_zero());
  EXPECT_FALSE(r.check.ok);
  const Diagnostic* d = r.first_error();
  ASSERT_NE(d, nullptr);
  EXPECT_EQ(d->line, 2);
  EXPECT_NE(d->message.find("X 30.0000 mm (machine) is above the travel maximum 25.0000"), std::string::npos)
      << d->message;
}

TEST(Preflight, ArcBulgeOutsideTravelIsCaughtAtItsExtremePoint) {
  // End points inside (y = 1), but the half circle bulges to y = -4: below the travel.
  const auto r = run_program("G0 X5 Y1 Z1\nG3 X15 Y1 I5 J0 F100\nM2\n", mill_config(), at_zero());
  EXPECT_FALSE(r.check.ok);
  EXPECT_TRUE(r.has_error("arc extreme point"));
  EXPECT_TRUE(r.has_error("Y -4.0000"));
  // The same arc the other way round bulges up to y = 6: inside.
  EXPECT_TRUE(run_program("G0 X5 Y1 Z1\nG2 X15 Y1 I5 J0 F100\nM2\n", mill_config(), at_zero()).check.ok);
}

TEST(Preflight, ExtremePointsOfAFullCircle) {
  Move m;
  m.kind = MoveKind::kArc;
  m.start = {10, 5, 0};
  m.end = m.start;
  m.center = {5, 5, 0};
  m.radius = 5;
  m.sweep = 2 * 3.14159265358979323846;
  m.normal_axis = 2;
  Box box;
  for_each_extreme(m, [&](const Vec3& p) { box.add(p); });
  EXPECT_NEAR(box.min[0], 0, 1e-12);
  EXPECT_NEAR(box.max[0], 10, 1e-12);
  EXPECT_NEAR(box.min[1], 0, 1e-12);
  EXPECT_NEAR(box.max[1], 10, 1e-12);
}

TEST(Preflight, ManyViolationsAreCountedNotListed) {
  std::string program = "G0 Z1\n";
  for (int i = 0; i < 1000; ++i) program += "G0 X" + std::to_string(30 + i % 5) + "\nG0 X1\n";
  program += "M2\n";
  const auto r = run_program(program, mill_config(), at_zero());
  EXPECT_FALSE(r.check.ok);
  EXPECT_LT(r.check.diagnostics.size(), 5u);
  EXPECT_TRUE(r.has_error("1000 points leave the travel above the maximum of axis X"));
}

// A NURBS move whose control polygon lies inside what the extents already hold skips the search
// for its extreme points (Preflight::within_seen): it must still count as outside the travel
// when it is, change no extents when it is inside them, and a curve that reaches past them must
// move them to its true extreme (the convex hull's corner is farther than the curve).
TEST(Preflight, ACurveInsideTheSeenExtentsChangesNothingButIsStillCheckedAgainstTheTravel) {
  const MachineConfig config = mill_config();
  DiagnosticSink sink("t.ngc");
  Preflight pf(config, sink, true);
  auto line = [](Vec3 a, Vec3 b) {
    Move m;
    m.kind = MoveKind::kLine;
    m.start = a;
    m.end = b;
    m.feed_mm_s = 10.0;
    m.line = 1;
    return m;
  };
  // a quadratic Bezier from (2,2,5) to (10,2,5), its middle control point at y = 8: the curve
  // peaks at y = 5 (the polygon's corner is at 8)
  auto curve = [](double y_mid, double z) {
    auto c = std::make_shared<NurbsCurve>();
    c->degree = 2;
    c->points = {{2, 2, z}, {6, y_mid, z}, {10, 2, z}};
    c->weights = {1, 1, 1};
    c->knots = {0, 0, 0, 1, 1, 1};
    Move m;
    m.kind = MoveKind::kNurbs;
    m.start = c->points.front();
    m.end = c->points.back();
    m.nurbs = c;
    m.feed_mm_s = 10.0;
    m.line = 2;
    return m;
  };
  pf.add(line({0, 0, 5}, {1, 1, 5}));  // the preflight sees end points: (1,1,5) and (12,9,5)
  pf.add(line({1, 1, 5}, {12, 9, 5}));
  const Box seen = pf.extents();
  pf.add(curve(8.0, 5.0));  // inside the box the line made: nothing changes
  EXPECT_EQ(pf.extents().min, seen.min);
  EXPECT_EQ(pf.extents().max, seen.max);
  pf.add(curve(16.0, 5.0));  // its polygon passes y = 9: the box grows to the curve's peak, y = 9
  EXPECT_NEAR(pf.extents().max[1], 9.0, 1e-9) << "the curve's own extreme, not its polygon's";
  EXPECT_FALSE(sink.has_errors());
  // outside the travel (z below 0) and inside the extents it has seen: still counted
  pf.add(line({12, 9, 5}, {1, 1, -2}));
  pf.add(line({1, 1, -2}, {12, 9, -2}));
  pf.finish();
  const std::vector<Diagnostic> lines_only = sink.take();
  DiagnosticSink sink2("t.ngc");
  Preflight pf2(config, sink2, true);
  pf2.add(line({0, 0, 5}, {1, 1, 5}));
  pf2.add(line({1, 1, 5}, {12, 9, 5}));
  pf2.add(line({12, 9, 5}, {1, 1, -2}));
  pf2.add(line({1, 1, -2}, {12, 9, -2}));
  pf2.add(curve(8.0, -1.0));
  pf2.finish();
  auto below_z = [](const std::vector<Diagnostic>& ds) {
    for (const Diagnostic& d : ds) {
      const std::size_t at = d.message.find(" points leave the travel below the minimum of axis Z");
      if (at != std::string::npos) return std::stoi(d.message.substr(0, at));
    }
    return 1;  // one point: reported on its own, without a count
  };
  EXPECT_GT(below_z(sink2.take()), below_z(lines_only)) << "the curve's points below Z 0 are counted too";
}

TEST(Preflight, FitScalesDownAndCentres) {
  // A 100 x 50 mm rectangle at depth -1..5: scale 25/100, centred in the 25 mm travel.
  JobOptions o;
  o.fit = true;
  o.start_position = Vec3{12.5, 12.5, 25};
  const auto r = run_program("G0 Z5\nG0 X0 Y0\nG1 Z-1 F100\nX100\nY50\nX0\nY0\nG0 Z5\nM2\n", mill_config(), o);
  ASSERT_TRUE(r.check.ok) << (r.first_error() ? r.first_error()->message : "");
  EXPECT_NEAR(r.check.transform.scale, 0.25, 1e-12);
  EXPECT_NEAR(r.check.min_point[0], 0, 1e-9);
  EXPECT_NEAR(r.check.max_point[0], 25, 1e-9);
  EXPECT_NEAR(r.check.min_point[1], 12.5 - 6.25, 1e-9);
  EXPECT_NEAR(r.check.max_point[1], 12.5 + 6.25, 1e-9);
  EXPECT_NEAR(0.5 * (r.check.min_point[2] + r.check.max_point[2]), 12.5, 1e-9);
  // machine = scale * program + offset holds for every point
  const Block corner = r.motion().at(3);  // X100 at Z-1
  EXPECT_NEAR(corner.end[0], 0.25 * 100 + r.check.transform.offset[0], 1e-9);
  EXPECT_NEAR(corner.end[2], 0.25 * -1 + r.check.transform.offset[2], 1e-9);
}

TEST(Preflight, FitNeverScalesUp) {
  JobOptions o;
  o.fit = true;
  const auto r = run_program("G0 X0 Y0 Z0\nG1 X1 Y1 F100\nM2\n", mill_config(), o);
  ASSERT_TRUE(r.check.ok);
  EXPECT_DOUBLE_EQ(r.check.transform.scale, 1.0);
}

TEST(Preflight, FeedTimeAndFigures) {
  const auto r = run_program("G0 X1 Y1 Z1\nG1 X11 F600\nG4 P2\nG0 X1\nM2\n", mill_config(), at_zero());
  ASSERT_TRUE(r.check.ok);
  EXPECT_NEAR(r.check.feed_length_time_s, 1.0, 1e-12);  // 10 mm at 10 mm/s; rapids and dwells not counted
  EXPECT_EQ(r.check.moves, 3u);
  EXPECT_EQ(r.check.lines, 5u);
  EXPECT_NEAR(r.check.last_point[0], 1, 1e-12);
  EXPECT_NEAR(r.check.max_point[0], 11, 1e-12);
}

TEST(Preflight, FitToTravelFunction) {
  const MachineConfig c = mill_config();
  Box box;
  box.add({-50, -10, 0});
  box.add({50, 10, 5});
  const FitResult f = fit_to_travel(box, {0, 0, 0}, c);
  EXPECT_DOUBLE_EQ(f.scale, 0.25);
  EXPECT_DOUBLE_EQ(f.offset[0], 12.5);
  EXPECT_DOUBLE_EQ(f.offset[2], 12.5 - 0.25 * 2.5);
}

// Streaming: a file is read in chunks; lines across chunk borders and a missing final newline
// come out right, and an over-long line is an error, not a crash.
TEST(Preflight, StreamsFilesAcrossChunkBorders) {
  const std::string path = (std::filesystem::temp_directory_path() / "pcnc_test_preflight.ngc").string();
  {
    std::ofstream f(path);
    f << "G21 G90\nG0 Z1\n";
    for (int i = 0; i < 30000; ++i) f << "G1 X" << (i % 20) << ".5 Y" << (i % 7) << " F600 (padding to cross chunks)\n";
    f << "M2";  // no final newline
  }
  JobOptions o = at_zero();
  const CheckResult r = check_program(path, mill_config(), o);
  ASSERT_TRUE(r.ok);
  EXPECT_EQ(r.lines, 30003u);
  BlockStream s(path, mill_config(), o, r.transform);
  Block b;
  std::uint64_t n = 0;
  Block last;
  while (s.next(b)) {
    ++n;
    last = b;
  }
  EXPECT_EQ(last.kind, BlockKind::kEnd);
  EXPECT_EQ(last.line, 30003u);
  EXPECT_EQ(s.bytes_read(), s.total_bytes());
  std::remove(path.c_str());
}

TEST(Preflight, OverlongLineIsAnError) {
  std::string program = "G0 X1\n(" + std::string(70000, 'a') + ")\nM2\n";
  const auto r = run_program(program, mill_config(), at_zero());
  EXPECT_FALSE(r.check.ok);
  EXPECT_TRUE(r.has_error("line too long"));
}

TEST(Preflight, MissingFileIsAnErrorNotACrash) {
  const CheckResult r = check_program("/nonexistent/x.ngc", mill_config(), JobOptions{});
  EXPECT_FALSE(r.ok);
  ASSERT_FALSE(r.diagnostics.empty());
  EXPECT_NE(r.diagnostics[0].message.find("cannot open"), std::string::npos);
}

}  // namespace
}  // namespace pcnc
