// test_surface_correction.cpp — the surface-correction stage (issue 15, item 5): Z shifted by
// the surface minus the reference, long lines and arcs split so that the path stays within the
// tolerance of the corrected curve (checked densely, independently of the stage's own
// samples), end points exact, moves chained, machine-frame moves left alone; and the stage in
// the one pipeline (`check --surface`'s path).
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <numbers>
#include <vector>

#include "gcode/program.hpp"
#include "gcode/surface_correction.hpp"
#include "gcode_test_util.hpp"
#include "geometry/nurbs.hpp"
#include "geometry/surface_fit.hpp"
#include "move_stage.hpp"

namespace pcnc {
namespace {

double wave(double x, double y) { return 0.05 * std::sin(0.5 * x) * std::cos(0.4 * y) + 0.002 * x; }

std::shared_ptr<const BSplineSurface> wavy_surface(double (*z)(double, double) = wave) {
  PointGrid g;
  g.cols = g.rows = 9;
  for (int r = 0; r < 9; ++r)
    for (int c = 0; c < 9; ++c) g.points.push_back({c * 25.0 / 8, r * 25.0 / 8, z(c * 25.0 / 8, r * 25.0 / 8)});
  return std::make_shared<const BSplineSurface>(interpolate_grid(g, 3, 1.0).surface);
}

std::vector<Move> run_stage(SurfaceCorrection& stage, const std::vector<Move>& in) {
  return test::run_move_stage(stage, in);
}

Move surface_move(Vec3 a, Vec3 b, MoveKind k = MoveKind::kLine) {
  Move m;
  m.kind = k;
  m.start = a;
  m.end = b;
  m.feed_mm_s = k == MoveKind::kLine ? 10 : 0;
  m.line = 7;
  return m;
}

double distance_to_polyline(const Vec3& p, const std::vector<Move>& pieces) {
  double best = INFINITY;
  for (const Move& m : pieces) {
    const Vec3 ab = m.end - m.start;
    const double l2 = dot(ab, ab);
    const double t = l2 > 0 ? std::clamp(dot(p - m.start, ab) / l2, 0.0, 1.0) : 0.0;
    best = std::min(best, norm(p - (m.start + t * ab)));
  }
  return best;
}

TEST(SurfaceCorrection, ReferenceIsTheSurfaceAtTheWorkOrigin) {
  const auto s = wavy_surface();
  const double ref = SurfaceCorrection::reference_at(*s, {12.5, 12.5, 25});
  SurfaceCorrection stage(s, ref, 0.001, nullptr);
  EXPECT_NEAR(stage.offset_at(12.5, 12.5), 0.0, 1e-12);
  EXPECT_NEAR(stage.offset_at(5, 20), wave(5, 20) - wave(12.5, 12.5), 2e-3);  // the fit is close to the wave
}

TEST(SurfaceCorrection, ShiftsZAndSplitsLongLinesWithinTheTolerance) {
  const auto s = wavy_surface();
  const double tol = 0.001;
  SurfaceCorrection stage(s, SurfaceCorrection::reference_at(*s, {12.5, 12.5, 0}), tol, nullptr);
  const Vec3 a{1, 2, 5}, b{23, 21, 4};
  // a plunge at (1, 2) first: its end is lifted, the start (the machine's position) is not
  const std::vector<Move> out = run_stage(stage, {surface_move({1, 2, 8}, a, MoveKind::kRapid), surface_move(a, b)});
  ASSERT_GE(out.size(), 3u);
  EXPECT_EQ(out[0].start, (Vec3{1, 2, 8}));
  EXPECT_EQ(out[0].kind, MoveKind::kRapid);
  EXPECT_NEAR(out[0].end[2], 5 + stage.offset_at(1, 2), 1e-12);
  const std::vector<Move> pieces(out.begin() + 1, out.end());
  EXPECT_GT(pieces.size(), 4u) << "a 29 mm line over a 50 µm wave needs pieces for 1 µm";
  for (std::size_t i = 1; i < out.size(); ++i) EXPECT_EQ(out[i].start, out[i - 1].end) << i;
  // the corrected end point, exactly
  EXPECT_EQ(pieces.back().end, (Vec3{b[0], b[1], b[2] + stage.offset_at(b[0], b[1])}));
  for (std::size_t i = 0; i < pieces.size(); ++i)
    EXPECT_EQ(pieces[i].contouring, i + 1 < pieces.size()) << "joints inside the move flow; its end keeps M22";
  for (const Move& m : pieces) {
    EXPECT_EQ(m.kind, MoveKind::kLine);
    EXPECT_EQ(m.line, 7);
    EXPECT_EQ(m.feed_mm_s, 10);
    // every vertex lies on the corrected path: z = programmed z + offset
    const double t = (m.end[0] - a[0]) / (b[0] - a[0]);
    EXPECT_NEAR(m.end[2], a[2] + t * (b[2] - a[2]) + stage.offset_at(m.end[0], m.end[1]), 1e-12);
  }
  // every point of the corrected path lies within the tolerance of the pieces
  double worst = 0;
  for (int i = 0; i <= 20000; ++i) {
    const double t = i / 20000.0;
    Vec3 p = a + t * (b - a);
    p[2] += stage.offset_at(p[0], p[1]);
    worst = std::max(worst, distance_to_polyline(p, pieces));
  }
  EXPECT_LE(worst, tol * 1.0001);
  EXPECT_GT(worst, tol * 0.1) << "the split is far finer than asked: pieces are wasted";
}

TEST(SurfaceCorrection, APlaneNeedsNoSplit) {
  const auto s = wavy_surface([](double x, double y) { return 0.01 * x - 0.02 * y; });
  SurfaceCorrection stage(s, 0.0, 0.001, nullptr);
  // the first move starts at the machine's (uncorrected) position: the gap fades along it
  const std::vector<Move> out = run_stage(stage, {surface_move({1, 1, 3}, {24, 20, 3})});
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].start, (Vec3{1, 1, 3}));
  EXPECT_NEAR(out[0].end[2], 3 + 0.01 * 24 - 0.02 * 20, 1e-9);
}

TEST(SurfaceCorrection, ArcsBecomeLinesWithinTheTolerance) {
  const auto s = wavy_surface();
  const double tol = 0.002;
  SurfaceCorrection stage(s, 0.0, tol, nullptr);
  Move arc = surface_move({15, 10, 2}, {5, 10, 1});
  arc.kind = MoveKind::kArc;
  arc.center = {10, 10, 2};
  arc.radius = 5;
  arc.sweep = std::numbers::pi;  // counter-clockwise through (10, 15), descending 1 mm
  arc.normal_axis = 2;
  const std::vector<Move> out = run_stage(stage, {arc});
  ASSERT_GT(out.size(), 10u);
  for (const Move& m : out) EXPECT_EQ(m.kind, MoveKind::kLine);
  double worst = 0;
  for (int i = 0; i <= 5000; ++i) {
    const double t = i / 5000.0, a = std::numbers::pi * t;
    Vec3 p{10 + 5 * std::cos(a), 10 + 5 * std::sin(a), 2 - t};
    p[2] += stage.offset_at(p[0], p[1]);
    worst = std::max(worst, distance_to_polyline(p, out));
  }
  EXPECT_LE(worst, tol * 1.0001);
  EXPECT_NEAR(out.back().end[0], 5, 1e-12);
  EXPECT_NEAR(out.back().end[2], 1 + stage.offset_at(5, 10), 1e-12);
}

TEST(SurfaceCorrection, NurbsMovesBecomeLinesWithinTheTolerance) {
  const auto s = wavy_surface();
  const double tol = 0.001;
  SurfaceCorrection stage(s, 0.0, tol, nullptr);
  const auto curve = std::make_shared<const NurbsCurve>(
      make_nurbs({{2, 3, 4}, {8, 20, 4}, {15, 2, 3}, {22, 18, 3}}, {1, 2, 1, 1}, 4));
  Move m = surface_move(curve->points.front(), curve->points.back());
  m.kind = MoveKind::kNurbs;
  m.nurbs = curve;
  // a plunge to the curve's start first, so that the curve starts on the corrected path
  std::vector<Move> out = run_stage(stage, {surface_move({2, 3, 10}, {2, 3, 4}), m});
  out.erase(out.begin());
  ASSERT_GT(out.size(), 10u);
  double worst = 0;
  for (int i = 0; i <= 5000; ++i) {
    Vec3 p = nurbs_point(curve->view(), curve->u_min() + (curve->u_max() - curve->u_min()) * i / 5000.0);
    p[2] += stage.offset_at(p[0], p[1]);
    worst = std::max(worst, distance_to_polyline(p, out));
  }
  EXPECT_LE(worst, tol * 1.0001);
  for (const Move& piece : out) {
    EXPECT_EQ(piece.kind, MoveKind::kLine);
    EXPECT_EQ(piece.nurbs, nullptr);
  }
  EXPECT_NEAR(out.back().end[2], 3 + stage.offset_at(22, 18), 1e-12);
}

TEST(SurfaceCorrection, MachineFrameMovesAndDwellsAreNotLifted) {
  const auto s = wavy_surface();
  SurfaceCorrection stage(s, 0.0, 0.001, nullptr);
  Move up = surface_move({10, 10, 2}, {10, 10, 24}, MoveKind::kRapid);
  up.machine_frame = true;
  Move dwell;
  dwell.kind = MoveKind::kDwell;
  dwell.dwell_s = 1;
  const std::vector<Move> out = run_stage(stage, {surface_move({10, 10, 5}, {10, 10, 2}), up, dwell});
  ASSERT_EQ(out.size(), 3u);
  EXPECT_NEAR(out[0].end[2], 2 + stage.offset_at(10, 10), 1e-12);
  EXPECT_EQ(out[1].start, out[0].end);
  EXPECT_EQ(out[1].end, (Vec3{10, 10, 24}));
  EXPECT_EQ(out[2].kind, MoveKind::kDwell);
  EXPECT_EQ(out[2].start, out[1].end);
}

TEST(SurfaceCorrection, OutsideTheSurfaceWarnsOnce) {
  // a surface over 10..15 only
  PointGrid g;
  g.cols = g.rows = 4;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) g.points.push_back({10 + c * 5.0 / 3, 10 + r * 5.0 / 3, 0.01 * c});
  const auto s = std::make_shared<const BSplineSurface>(interpolate_grid(g, 3, 1.0).surface);
  DiagnosticSink sink("t.ngc");
  SurfaceCorrection stage(s, 0.0, 0.001, &sink);
  const std::vector<Move> out = run_stage(stage, {surface_move({12, 12, 5}, {20, 12, 5}), surface_move({20, 12, 5}, {22, 12, 5})});
  const auto d = sink.take();
  ASSERT_EQ(d.size(), 1u);
  EXPECT_NE(d[0].message.find("footprint"), std::string::npos);
  EXPECT_NEAR(out.back().end[2], 5 + 0.03, 1e-9);  // held at the x = 15 edge
}

TEST(SurfaceCorrection, RunsInThePipeline) {
  // a tilted plane: z = 0.01 (x - 12.5); the work origin is X12.5 Y12.5 (the config's G54)
  const auto s = wavy_surface([](double x, double) { return 0.01 * x; });
  JobOptions job;
  job.surface = s;
  std::vector<Move> moves;
  const MachineConfig cfg = test::mill_config();
  const std::string prog = "G21 G90\nG0 X0 Y0 Z-5\nG1 X10 Y0 F300\nG2 X0 Y0 I-5 J0\nM2\n";
  const MoveListing r = list_moves_text(prog, "t.ngc", cfg, job, [&](const Move& m) { moves.push_back(m); }, {});
  ASSERT_TRUE(r.ok);
  ASSERT_GE(moves.size(), 4u);
  // G0 X0 Y0 Z-5 goes to machine (12.5, 12.5, 20), the reference point: not lifted
  EXPECT_NEAR(moves[0].end[2], 20.0, 1e-12);
  for (const Move& m : moves) {
    if (m.kind == MoveKind::kEnd || m.kind == MoveKind::kPause) continue;
    EXPECT_EQ(m.kind == MoveKind::kArc, false) << "arcs become lines";
  }
  const Move& g1 = moves[1];
  EXPECT_NEAR(g1.end[0], 22.5, 1e-12);
  EXPECT_NEAR(g1.end[2], 20.0 + 0.01 * (22.5 - 12.5), 1e-9);
  const CheckResult c = check_program_text(prog, "t.ngc", cfg, job);
  EXPECT_TRUE(c.ok);
  // the arc (centre X17.5, through Y7.5) stays right of the work origin: it is lifted, never lowered
  EXPECT_NEAR(c.min_point[2], 20.0, 1e-9);
  EXPECT_NEAR(c.max_point[0], 22.5, 1e-9);
}

}  // namespace
}  // namespace pcnc
