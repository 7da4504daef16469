// test_nurbs_gcode.cpp — the G-code front end's NURBS support (G5.2/G5.3, G6.2): the curves
// the interpreter builds (control points, weights, knots, planes, units, offsets), every
// validation rule with its file:line:col message and nothing streamed, soft limits and --fit
// extents on the curve itself, the control polygon refined into the travel, and the ring
// blocks BlockStream streams (pieces, joins, contouring flags).
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "gcode_test_util.hpp"
#include "geometry/nurbs.hpp"
#include "ipc/block_nurbs.hpp"
#include "gcode/nurbs_move.hpp"

namespace pcnc {
namespace {

using test::mill_config;
using test::run_program;
using test::wide_config;

std::vector<Block> nurbs_blocks(const std::vector<Block>& blocks) {
  std::vector<Block> out;
  for (const Block& b : blocks) {
    if (b.kind == BlockKind::kNurbs) out.push_back(b);
  }
  return out;
}

std::vector<double> knots_of(const Block& b) { return {b.nurbs.knots, b.nurbs.knots + b.nurbs.knot_count}; }

// LinuxCNC's documentation example (nurbs-xy.ngc), at F100 from (0,0,0).
const char* kNurbsXy =
    "G17 G0 X0 Y0 Z0\n"
    "F100\n"
    "G5.2 P1 L3\n"
    "  X0 Y1 P1\n"
    "  X2 Y2 P1\n"
    "  X2 Y0 P1\n"
    "  X0 Y0 P2\n"
    "G5.3\n"
    "G0 X0 Y1\n"
    "M2\n";

TEST(NurbsGcode, G52CurveHasTheCurrentPointFirstAndLinuxCncKnots) {
  const auto r = run_program(kNurbsXy, wide_config());
  ASSERT_TRUE(r.check.ok) << (r.first_error() ? r.first_error()->message : "");
  const auto nb = nurbs_blocks(r.blocks);
  ASSERT_EQ(nb.size(), 1u);
  const Block& b = nb[0];
  EXPECT_EQ(b.line, 3u);
  EXPECT_EQ(b.nurbs.degree, 2);
  ASSERT_EQ(b.nurbs.point_count, 5);
  const Vec3 want[5] = {{0, 0, 0}, {0, 1, 0}, {2, 2, 0}, {2, 0, 0}, {0, 0, 0}};
  const double w[5] = {1, 1, 1, 1, 2};
  for (int i = 0; i < 5; ++i) {
    EXPECT_EQ(b.nurbs.points[i], want[i]) << i;
    EXPECT_EQ(b.nurbs.weights[i], w[i]) << i;
  }
  EXPECT_EQ(knots_of(b), (std::vector<double>{0, 0, 0, 1, 2, 3, 3, 3}));
  EXPECT_EQ(b.start, (Vec3{0, 0, 0}));
  EXPECT_EQ(b.end, (Vec3{0, 0, 0}));
  EXPECT_NEAR(b.speed, 100.0 / 60.0, 1e-12);
  // the program goes on from the curve's end: the next rapid starts at its last point
  bool after = false;
  for (const Block& x : r.blocks) {
    if (x.line == 9) {
      after = true;
      EXPECT_EQ(x.start, (Vec3{0, 0, 0}));
      EXPECT_EQ(x.end, (Vec3{0, 1, 0}));
    }
  }
  EXPECT_TRUE(after);
  // the feed time counts the curve's arc length at F
  const NurbsCurve c = make_nurbs({want, want + 5}, {w, w + 5}, 3);
  EXPECT_NEAR(r.check.feed_length_time_s, nurbs_arc_length(c.view(), c.u_min(), c.u_max()) / (100.0 / 60.0), 1e-9);
}

TEST(NurbsGcode, G52LineWithCoordinatesIsTheSecondPoint) {
  const auto r = run_program("G0 X1 Y1 Z0\nG1 F60\nG5.2 X2 Y3 P0.5 L3\nX4 Y1 P1\nG5.3\nM2\n", wide_config());
  ASSERT_TRUE(r.check.ok) << (r.first_error() ? r.first_error()->message : "");
  const auto nb = nurbs_blocks(r.blocks);
  ASSERT_EQ(nb.size(), 1u);
  ASSERT_EQ(nb[0].nurbs.point_count, 3);
  EXPECT_EQ(nb[0].nurbs.points[0], (Vec3{1, 1, 0}));
  EXPECT_EQ(nb[0].nurbs.weights[0], 1.0);
  EXPECT_EQ(nb[0].nurbs.points[1], (Vec3{2, 3, 0}));
  EXPECT_EQ(nb[0].nurbs.weights[1], 0.5);
  EXPECT_EQ(nb[0].nurbs.points[2], (Vec3{4, 1, 0}));
}

// G18 and G19 read the plane's two named axes; the third stays where it is.
TEST(NurbsGcode, PlanesG18AndG19MapTheNamedAxes) {
  const std::string body = "F100\nG5.2 P1 L3\n A0 B1 P1\n A2 B2 P1\n A2 B0 P1\n A0 B0 P2\nG5.3\nM2\n";
  auto program = [&](const char* plane, char a, char b) {
    std::string s = std::string(plane) + " G0 X0 Y0 Z0\nG0 X0.5 Y0.5 Z0.5\nG0 X0 Y0 Z0\n" + body;
    for (char& c : s) {
      if (c == 'A') c = a;
      if (c == 'B') c = b;
    }
    return s;
  };
  const auto xy = nurbs_blocks(run_program(program("G17", 'X', 'Y'), wide_config()).blocks);
  const auto zx = nurbs_blocks(run_program(program("G18", 'Z', 'X'), wide_config()).blocks);
  const auto yz = nurbs_blocks(run_program(program("G19", 'Y', 'Z'), wide_config()).blocks);
  ASSERT_EQ(xy.size(), 1u);
  ASSERT_EQ(zx.size(), 1u);
  ASSERT_EQ(yz.size(), 1u);
  ASSERT_EQ(zx[0].nurbs.point_count, 5);
  for (int i = 0; i < 5; ++i) {
    const Vec3 p = xy[0].nurbs.points[i];
    EXPECT_EQ(zx[0].nurbs.points[i], (Vec3{p[1], 0.0, p[0]})) << i;  // first named axis Z, second X
    EXPECT_EQ(yz[0].nurbs.points[i], (Vec3{0.0, p[0], p[1]})) << i;  // Y, Z
  }
  EXPECT_EQ(knots_of(zx[0]), knots_of(xy[0]));
  // the corpus's own files say the same (they also trace the control polygon with G0)
  const auto corpus = run_program(
      "G18 G0 Z0 X0 Y3\nF100\nG5.2 P1 L3\n Z0 X1 P1\n Z2 X2 P1\n Z2 X0 P1\n Z0 X0 P2\nG5.3\nM2\n", wide_config());
  const auto c = nurbs_blocks(corpus.blocks);
  ASSERT_EQ(c.size(), 1u);
  EXPECT_EQ(c[0].nurbs.points[2], (Vec3{2, 3, 2}));
}

TEST(NurbsGcode, ChordLengthKnotsWhenTheConfigAsks) {
  MachineConfig cfg = wide_config();
  cfg.gcode.nurbs_knots = 1;
  const auto r = run_program(kNurbsXy, cfg);
  ASSERT_TRUE(r.check.ok);
  const auto nb = nurbs_blocks(r.blocks);
  ASSERT_EQ(nb.size(), 1u);
  const std::vector<Vec3> pts = {{0, 0, 0}, {0, 1, 0}, {2, 2, 0}, {2, 0, 0}, {0, 0, 0}};
  const std::vector<double> want = chord_length_knots(pts, 2);
  EXPECT_EQ(knots_of(nb[0]), want);
  EXPECT_NE(want, (std::vector<double>{0, 0, 0, 1, 2, 3, 3, 3}));  // really a different vector
}

TEST(NurbsGcode, UnitsOffsetsAndIncrementalPoints) {
  MachineConfig cfg = wide_config();
  cfg.gcode.work_offsets[1] = Vec3{100, 200, 300};
  const auto r = run_program("G20 G55 G0 X0 Y0 Z0\nF10\nG91 G5.2 P1 L3\nX1 Y0 P1\nX0 Y1 P1\nG5.3\nM2\n", cfg);
  ASSERT_TRUE(r.check.ok) << (r.first_error() ? r.first_error()->message : "");
  const auto nb = nurbs_blocks(r.blocks);
  ASSERT_EQ(nb.size(), 1u);
  ASSERT_EQ(nb[0].nurbs.point_count, 3);
  EXPECT_EQ(nb[0].nurbs.points[0], (Vec3{100, 200, 300}));
  EXPECT_LT(norm(nb[0].nurbs.points[1] - Vec3{125.4, 200, 300}), 1e-12);
  EXPECT_LT(norm(nb[0].nurbs.points[2] - Vec3{125.4, 225.4, 300}), 1e-12);
  EXPECT_NEAR(nb[0].speed, 10 * 25.4 / 60.0, 1e-12);
}

// The same rational quadratic quarter circle, LinuxCNC style and Fanuc style.
const char* kQuarterG52 =
    "G0 X10 Y0 Z0\nG1 F600\nG5.2 P1 L3\nX10 Y10 P[SQRT[2]/2]\nX0 Y10 P1\nG5.3\nM2\n";
const char* kQuarterG62 =
    "G0 X10 Y0 Z0\nG6.2 P3 K0 X10 Y0 Z0 R1 F600\nK0 X10 Y10 R[SQRT[2]/2]\nK0 X0 Y10 R1\nK1\nK1\nK1\nM2\n";

TEST(NurbsGcode, FanucAndLinuxCncDescriptionsGiveTheSameBlock) {
  const auto a = run_program(kQuarterG52, wide_config());
  const auto b = run_program(kQuarterG62, wide_config());
  ASSERT_TRUE(a.check.ok) << (a.first_error() ? a.first_error()->message : "");
  ASSERT_TRUE(b.check.ok) << (b.first_error() ? b.first_error()->message : "");
  const auto na = nurbs_blocks(a.blocks), nb = nurbs_blocks(b.blocks);
  ASSERT_EQ(na.size(), 1u);
  ASSERT_EQ(nb.size(), 1u);
  const Block& x = na[0];
  const Block& y = nb[0];
  EXPECT_EQ(format_block(x).substr(3), format_block(y).substr(3));  // all but the line number
  ASSERT_EQ(x.nurbs.point_count, y.nurbs.point_count);
  ASSERT_EQ(x.nurbs.schedule_count, y.nurbs.schedule_count);
  for (int i = 0; i < x.nurbs.point_count; ++i) {
    EXPECT_EQ(x.nurbs.points[i], y.nurbs.points[i]);
    EXPECT_EQ(x.nurbs.weights[i], y.nurbs.weights[i]);
  }
  for (int i = 0; i < x.nurbs.schedule_count; ++i) {
    EXPECT_EQ(x.nurbs.schedule_u[i], y.nurbs.schedule_u[i]);
    EXPECT_EQ(x.nurbs.schedule_speed[i], y.nurbs.schedule_speed[i]);
  }
  EXPECT_EQ(knots_of(x), knots_of(y));
  EXPECT_EQ(knots_of(y), (std::vector<double>{0, 0, 0, 1, 1, 1}));
}

TEST(NurbsGcode, FanucFullCircleWithDoubledKnotsAndOmittedCoordinates) {
  // 9 points, knots 0 0 0 1 1 2 2 3 3 4 4 4; the G6.2 line has no coordinates (the current
  // position is the first point) and later points omit Z (it keeps its value).
  const double s = std::sqrt(0.5);
  char buf[1024];
  std::snprintf(buf, sizeof buf,
                "G0 X5 Y0 Z1\nG6.2 P3 K0 R1 F600\nK0 X5 Y5 R%.17g\nK0 X0 Y5 R1\nK1 X-5 Y5 R%.17g\nK1 X-5 Y0 R1\n"
                "K2 X-5 Y-5 R%.17g\nK2 X0 Y-5 R1\nK3 X5 Y-5 R%.17g\nK3 X5 Y0 R1\nK4\nK4\nK4\nG1 X6\nM2\n",
                s, s, s, s);
  const auto r = run_program(buf, wide_config());
  ASSERT_TRUE(r.check.ok) << (r.first_error() ? r.first_error()->message : "");
  const auto nb = nurbs_blocks(r.blocks);
  ASSERT_EQ(nb.size(), 1u);  // no corner: the doubled knots keep the circle smooth
  EXPECT_EQ(nb[0].nurbs.point_count, 9);
  const NurbsView v = view_of(nb[0].nurbs);
  for (int k = 0; k <= 400; ++k) {
    const Vec3 p = nurbs_point(v, 4.0 * k / 400);
    EXPECT_NEAR(std::hypot(p[0], p[1]), 5.0, 1e-12);
    EXPECT_NEAR(p[2], 1.0, 1e-14);
  }
  // the extents are the circle's, not its control polygon's
  EXPECT_NEAR(r.check.min_point[1], -5.0, 1e-9);
  EXPECT_NEAR(r.check.max_point[0], 6.0, 1e-9);
  EXPECT_NEAR(r.check.min_point[0], -5.0, 1e-9);
}

// ---- every validation rule: rejected with line:col, nothing streamed ----------------------
struct Bad {
  const char* program;
  const char* error;
  int line;
  int col;
};
class NurbsRejected : public ::testing::TestWithParam<Bad> {};

TEST_P(NurbsRejected, BeforeAnyMotionWithLineColumnAndReason) {
  const Bad& c = GetParam();
  const auto r = run_program(std::string("G0 X0 Y0 Z0\nF100\n") + c.program + "\nM2\n", wide_config());
  EXPECT_FALSE(r.check.ok) << c.program;
  const Diagnostic* d = r.first_error();
  ASSERT_NE(d, nullptr) << c.program;
  EXPECT_NE(d->message.find(c.error), std::string::npos) << c.program << " -> " << d->message;
  EXPECT_NE(d->message.find("expected"), std::string::npos) << d->message;
  EXPECT_EQ(d->line, c.line) << c.program << " -> " << d->message;
  EXPECT_EQ(d->column, c.col) << c.program << " -> " << d->message;
  EXPECT_TRUE(r.blocks.empty()) << "rejected before motion";
  const std::string shown = format_diagnostic(*d);
  EXPECT_EQ(shown.rfind("test.ngc:" + std::to_string(c.line) + ":" + std::to_string(c.col) + ": error: ", 0), 0u)
      << shown;
}

INSTANTIATE_TEST_SUITE_P(
    Rules, NurbsRejected,
    ::testing::Values(
        // order 2..6
        Bad{"G5.2 P1 L7\nX1 Y1 P1\nG5.3", "order must be a whole number from 2 to 6", 3, 9},
        Bad{"G5.2 P1 L1\nX1 Y1 P1\nG5.3", "order must be a whole number from 2 to 6", 3, 9},
        Bad{"G5.2 P1 L2.5\nX1 Y1 P1\nG5.3", "order must be a whole number", 3, 9},
        Bad{"G6.2 P7 K0 F10\nK0 X1 Y1\nK1\nK1", "order must be a whole number", 3, 6},
        // enough control points for the order
        Bad{"G5.2 P1 L4\nX1 Y1 P1\nX2 Y0 P1\nG5.3", "order 4 needs at least 4 control points, got 3", 3, 1},
        // weights > 0
        Bad{"G5.2 P1 L3\nX1 Y1 P0\nX2 Y0 P1\nG5.3", "weight P0 is not positive", 4, 7},
        Bad{"G5.2 P-1 L3\nX1 Y1 P1\nX2 Y0 P1\nG5.3", "weight P-1 is not positive", 3, 6},
        Bad{"G6.2 P2 K0 F10\nK0 X1 Y1 R-2\nK1\nK1", "weight R-2 is not positive", 4, 10},
        // knots: non-decreasing, the right count, clamped
        Bad{"G6.2 P2 K0\nK1 X1 Y1\nK0.5 X2 Y0\nK2\nK2", "knot K0.5 is smaller than the knot before it", 5, 1},
        Bad{"G6.2 P3 K0\nK0 X1 Y1\nK0 X2 Y0\nK1\nK1\nG1 X3", "closing knot-only K lines first (2 given)", 8, 1},
        Bad{"G6.2 P3 K0\nK0 X1 Y1\nK0 X2 Y0\nK1\nK1",
            "M2 inside the G6.2 NURBS curve opened on line 3; expected its 3 closing knot-only K lines first (2 given)",
            8, 1},
        Bad{"G6.2 P2 K0\nK0.5 X1 Y1\nK1 X2 Y0\nK2\nK2", "its first 2 and its last 2 knots must be equal", 3, 1},
        Bad{"G6.2 P2 K0\nK0 X1 Y1\nK0 X2 Y0\nK2\nK2", "its first 2 and its last 2 knots must be equal", 3, 1},
        Bad{"G6.2 P2 K0\nK0 X1 Y1\nK1\nK1 X2 Y0", "control point after the closing knot-only lines", 6, 4},
        Bad{"G6.2 P2 K0\nX1 Y1\nK1\nK1", "without its knot K", 4, 1},
        Bad{"G6.2 P2 K0 X1 Y0\nK0 X1 Y1\nK1\nK1", "mm away from the current position", 3, 12},
        // no other motion word (or any G/M word) inside a group; G5.3 closes only G5.2
        Bad{"G5.2 P1 L3\nX1 Y1 P1\nG1 X2 Y0\nG5.3", "G1 inside the G5.2 NURBS curve opened on line 3", 5, 1},
        Bad{"G5.2 P1 L3\nX1 Y1 P1\nG2 X2 Y0 I1\nG5.3", "G2 inside the G5.2", 5, 1},
        Bad{"G5.2 P1 L3\nX1 Y1 P1\nG5.2 P1 L3\nG5.3", "G5.2 inside the G5.2", 5, 1},
        Bad{"G5.2 P1 L3\nX1 Y1 P1\nM3\nX2 Y0 P1\nG5.3", "M3 inside the G5.2", 5, 1},
        Bad{"G5.2 P1 L3\nX1 Y1 P1 I1\nX2 Y0 P1\nG5.3", "I word inside the G5.2", 4, 10},
        Bad{"G5.2 P1 L3\nX1 Y1 P1 F20\nX2 Y0 P1\nG5.3", "F word inside the G5.2", 4, 10},
        Bad{"G6.2 P2 K0\nK0 X1 Y1\nG0 X5\nK1\nK1", "G0 inside the G6.2 NURBS curve", 5, 1},
        Bad{"G5.3", "G5.3 without an open G5.2", 3, 1},
        Bad{"G5.2 P1 L3\nX1 Y1 P1\nX2 Y0 P1", "M2 inside the G5.2 NURBS curve opened on line 3; expected G5.3", 6, 1},
        // control points in the plane, both axes, with weight
        Bad{"G5.2 P1 L3\nX1 Y1 Z1 P1\nX2 Y0 P1\nG5.3", "Z word in a G17 NURBS curve", 4, 7},
        Bad{"G5.2 P1 L3\nX1 P1\nX2 Y0 P1\nG5.3", "NURBS control point without Y", 4, 1},
        Bad{"G5.2 P1 L3\nX1 Y1\nX2 Y0 P1\nG5.3", "without its weight P", 4, 1},
        Bad{"G18 G5.2 P1 L3\nX1 Y1 P1\nX2 Z0 P1\nG5.3", "Y word in a G18 NURBS curve", 4, 4},
        Bad{"G5.2 P1 L3\nX1 Y1 P1\nX2 Y0 P1\nG5.3 X1", "G5.3 with a control point", 6, 6},
        // words on the opening line
        Bad{"G5.2 P1 L3 M2\nX1 Y1 P1\nG5.3", "on a line that opens a G5.2 NURBS curve", 3, 12},
        Bad{"G6.2 P3 L3 K0\nK0 X1 Y1\nK1\nK1", "L word with no G code", 3, 9},
        // a curve with no length
        Bad{"G5.2 P1 L2\nX0 Y0 P1\nG5.3", "all its control points coincide", 3, 1},
        // G5 and G5.1 splines: LinuxCNC's rules
        Bad{"G5 X10 Y0 I3 J5", "G5 without both P and Q", 3, 1},
        Bad{"G5 X10 Y0 I3 P1 Q1", "G5 with only one of I and J", 3, 11},
        Bad{"G5 X10 Y0 P1 Q1", "G5 without I and J that does not follow a G5", 3, 1},
        Bad{"G1 X1\nG5 X10 Y0 I1 J1 P1 Q1\nG1 X12\nG5 X14 P1 Q1", "does not follow a G5", 6, 1},
        Bad{"G18 G5 X10 Z0 I1 J1 P1 Q1", "G5 spline outside the XY plane", 3, 5},
        Bad{"G5 X10 Y0 Z1 I1 J1 P1 Q1", "Z word on a G5 spline", 3, 11},
        Bad{"G5.1 X10 Y0", "G5.1 without I and J", 3, 1},
        Bad{"G5.1 X10 Y0 I1 J1 P1", "P word with no G code that uses it", 3, 19},
        Bad{"G93 G5 X10 Y0 I1 J1 P1 Q1 F1", "G5 spline in inverse time feed mode (G93) is not supported", 3, 5},
        Bad{"G5 X0 Y0 I0 J0 P0 Q0", "control points all coincide", 3, 1}));

TEST(NurbsGcode, EndOfFileInsideAGroupIsReportedAtItsOpening) {
  for (const char* p : {"G0 X0 Y0\nF100\nG5.2 P1 L3\nX1 Y1 P1\nX2 Y0 P1\n",
                        "G0 X0 Y0\nF100\nG6.2 P3 K0\nK0 X1 Y1\nK0 X2 Y0\nK1\n"}) {
    const auto r = run_program(p, wide_config());
    EXPECT_FALSE(r.check.ok);
    ASSERT_NE(r.first_error(), nullptr);
    EXPECT_NE(r.first_error()->message.find("the program ends inside the G"), std::string::npos)
        << r.first_error()->message;
    EXPECT_NE(r.first_error()->message.find("expected"), std::string::npos);
    EXPECT_EQ(r.first_error()->line, 3);
    EXPECT_EQ(r.first_error()->column, 1);
    EXPECT_TRUE(r.blocks.empty());
  }
}

TEST(NurbsGcode, NoFeedRejected) {
  const auto r = run_program("G0 X0 Y0\nG5.2 P1 L2\nX1 Y1 P1\nG5.3\nM2\n", wide_config());
  EXPECT_FALSE(r.check.ok);
  ASSERT_NE(r.first_error(), nullptr);
  EXPECT_NE(r.first_error()->message.find("no feed rate"), std::string::npos);
  EXPECT_EQ(r.first_error()->line, 2);
}

TEST(NurbsGcode, OneErrorInsideAGroupDoesNotCascade) {
  const auto r = run_program("G0 X0 Y0\nF100\nG5.2 P1 L3\nX1 Y1 P0\nX2 Y1 P1 I4\nX3 Y0 P1\nG5.3\nG1 X5\nM2\n",
                             wide_config());
  EXPECT_FALSE(r.check.ok);
  int errors = 0;
  for (const Diagnostic& d : r.check.diagnostics) errors += d.severity == Diagnostic::Severity::kError;
  EXPECT_EQ(errors, 1);
}

// ---- soft limits and --fit on the curve itself --------------------------------------------
// On the desktop mill (travel 0..25, G54 = (12.5, 12.5, 25)): a quadratic from (-10,0) to
// (10,0) whose middle control point is at Y=h peaks at Y=h/2 (weights 1), i.e. 12.5 + h/2.
std::string arch(double h) {
  char buf[256];
  std::snprintf(buf, sizeof buf, "G0 X-10 Y0 Z-1\nF100\nG5.2 P1 L3\nX0 Y%g P1\nX10 Y0 P1\nG5.3\nM2\n", h);
  return buf;
}

TEST(NurbsGcode, SoftLimitsCheckTheCurveNotItsControlPolygon) {
  // middle control point at machine Y 32.5 (outside), the curve peaks at 22.5 (inside)
  const auto ok = run_program(arch(20), mill_config(), JobOptions{});
  ASSERT_TRUE(ok.check.ok) << (ok.first_error() ? ok.first_error()->message : "");
  EXPECT_NEAR(ok.check.max_point[1], 22.5, 1e-9);
  // the streamed blocks have their control polygons inside the travel (refined by knot
  // insertion), and they are still the same curve
  const auto nb = nurbs_blocks(ok.blocks);
  ASSERT_GE(nb.size(), 1u);
  const MachineConfig cfg = mill_config();
  const NurbsCurve orig = make_nurbs({{2.5, 12.5, 24}, {12.5, 32.5, 24}, {22.5, 12.5, 24}}, {1, 1, 1}, 3);
  int points = 0;
  for (const Block& b : nb) {
    for (int i = 0; i < b.nurbs.point_count; ++i, ++points) {
      for (int a = 0; a < 3; ++a) {
        EXPECT_GE(b.nurbs.points[i][a], cfg.axes[a].travel_min_mm - nurbs_travel_margin(cfg));
        EXPECT_LE(b.nurbs.points[i][a], cfg.axes[a].travel_max_mm + nurbs_travel_margin(cfg));
      }
    }
    const NurbsView v = view_of(b.nurbs);
    for (int k = 0; k <= 50; ++k) {
      const double u = v.u_min() + (v.u_max() - v.u_min()) * k / 50;
      EXPECT_LT(norm(nurbs_point(v, u) - nurbs_point(orig.view(), u)), 1e-12);
    }
  }
  EXPECT_GT(points, 3);  // refined
  // middle control point at 42.5: the curve peaks at 27.5, outside: refused at the G5.2 line
  const auto bad = run_program(arch(30), mill_config(), JobOptions{});
  EXPECT_FALSE(bad.check.ok);
  ASSERT_NE(bad.first_error(), nullptr);
  EXPECT_EQ(bad.first_error()->line, 3);
  EXPECT_NE(bad.first_error()->message.find("Y 27.5000 mm (machine) is above the travel maximum"), std::string::npos)
      << bad.first_error()->message;
  EXPECT_NE(bad.first_error()->message.find("NURBS curve"), std::string::npos);
  EXPECT_TRUE(bad.blocks.empty());
}

TEST(NurbsGcode, FitScalesToTheCurvesExtents) {
  // a curve 20 mm wide whose control polygon reaches Y 40 (the curve: Y 20) — with --fit
  // the 25 mm travel holds it at scale 1; the extents are the curve's
  JobOptions o;
  o.fit = true;
  const auto r = run_program("G0 X-10 Y0 Z0\nF100\nG5.2 P1 L3\nX0 Y40 P1\nX10 Y0 P1\nG5.3\nM2\n", mill_config(), o);
  ASSERT_TRUE(r.check.ok) << (r.first_error() ? r.first_error()->message : "");
  EXPECT_EQ(r.check.transform.scale, 1.0);
  EXPECT_NEAR(r.check.max_point[1] - r.check.min_point[1], 20.0, 1e-9);
  EXPECT_NEAR(r.check.max_point[0] - r.check.min_point[0], 20.0, 1e-9);
  // 40 mm tall curve: scaled to fit
  const auto big = run_program("G0 X-10 Y0 Z0\nF100\nG5.2 P1 L3\nX0 Y80 P1\nX10 Y0 P1\nG5.3\nM2\n", mill_config(), o);
  ASSERT_TRUE(big.check.ok) << (big.first_error() ? big.first_error()->message : "");
  EXPECT_NEAR(big.check.transform.scale, 25.0 / 40.0, 1e-9);
  EXPECT_NEAR(big.check.max_point[1], 25.0, 1e-9);
  EXPECT_NEAR(big.check.min_point[1], 0.0, 1e-9);
  EXPECT_FALSE(nurbs_blocks(big.blocks).empty());
}

// ---- pieces: split at knots, joins flow inside a curve ------------------------------------
TEST(NurbsGcode, LongCurveIsSplitIntoJoinedPiecesThatFlow) {
  std::string p = "G0 X0 Y0 Z0\nF600\nG5.2 P1 L4\n";
  for (int i = 1; i < 100; ++i) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "X%d Y%g P1\n", i, 3.0 * std::sin(i * 0.3));
    p += buf;
  }
  p += "G5.3\nG1 X120 Y0\nM2\n";
  const auto r = run_program(p, wide_config());
  ASSERT_TRUE(r.check.ok) << (r.first_error() ? r.first_error()->message : "");
  const auto nb = nurbs_blocks(r.blocks);
  ASSERT_GE(nb.size(), 4u);  // 100 points, at most 32 per block
  for (std::size_t i = 0; i < nb.size(); ++i) {
    EXPECT_LE(nb[i].nurbs.point_count, kMaxNurbsPoints);
    EXPECT_EQ(nb[i].line, 3u);
    if (i + 1 < nb.size()) {
      EXPECT_LT(norm(nb[i].end - nb[i + 1].start), 1e-12);
      EXPECT_GT(dot(nb[i].dir_end, nb[i + 1].dir_start), std::cos(1e-6));
      EXPECT_EQ(nb[i].contouring, 1) << "joins inside one curve flow";
    }
  }
  EXPECT_EQ(nb.back().contouring, 0) << "the last piece follows M22";
  EXPECT_NEAR(nb.back().end[0], 99.0, 1e-12);
  EXPECT_NEAR(nb.back().end[1], 3.0 * std::sin(99 * 0.3), 1e-5);  // as printed with %g
}

TEST(NurbsGcode, CornerOfACurveFollowsTheProgramsContouring) {
  // degree 1 (L2): a polyline; its vertices are corners
  const char* prog = "G0 X0 Y0 Z0\nF600\nG5.2 P1 L2\nX5 Y0 P1\nX5 Y5 P1\nG5.3\nM2\n";
  const auto r = run_program(prog, wide_config());
  ASSERT_TRUE(r.check.ok);
  const auto nb = nurbs_blocks(r.blocks);
  ASSERT_EQ(nb.size(), 2u);
  EXPECT_EQ(nb[0].contouring, 0);  // a 90 degree corner under M22: stop
  EXPECT_EQ(nb[0].end, (Vec3{5, 0, 0}));
  const auto r21 = run_program(std::string("M21\n") + prog, wide_config());
  ASSERT_EQ(nurbs_blocks(r21.blocks).size(), 2u);
  EXPECT_EQ(nurbs_blocks(r21.blocks)[0].contouring, 1);  // M21: the rt's angle rule decides
}

TEST(NurbsGcode, ManyCurvesStreamOneAfterAnother) {
  std::string p = "G0 X0 Y0 Z0\nF600\n";
  for (int i = 0; i < 200; ++i) {
    char buf[128];
    std::snprintf(buf, sizeof buf, "G5.2 P1 L3\nX%d Y1 P1\nX%d Y0 P1\nG5.3\n", 2 * i + 1, 2 * i + 2);
    p += buf;
  }
  p += "M2\n";
  const auto r = run_program(p, wide_config());
  ASSERT_TRUE(r.check.ok);
  const auto nb = nurbs_blocks(r.blocks);
  ASSERT_EQ(nb.size(), 200u);
  EXPECT_EQ(r.check.moves, 200u);  // the first G0 does not move
  for (std::size_t i = 0; i + 1 < nb.size(); ++i) EXPECT_EQ(nb[i].end, nb[i + 1].start);
  EXPECT_EQ(r.blocks.back().kind, BlockKind::kEnd);
  EXPECT_EQ(r.blocks.back().end, (Vec3{400, 0, 0}));
}

// ---- G5 / G5.1 splines (interpreter_spline.cpp) ----------------------------------------------

// The Bézier curve of control points p at t, by de Casteljau (independent of the NURBS code).
Vec3 bezier(std::vector<Vec3> p, double t) {
  for (std::size_t n = p.size(); n > 1; --n) {
    for (std::size_t i = 0; i + 1 < n; ++i) p[i] = (1.0 - t) * p[i] + t * p[i + 1];
  }
  return p[0];
}

// Each G5 is the cubic from the current point to X Y with inner control points start + (I, J)
// and end + (P, Q); a G5 without I and J continues the one before it (first control point at
// start - previous (P, Q)); G5.1 the quadratic with its control point at start + (I, J); inch
// offsets are converted. The blocks hold exactly those curves, which pass the rt's check.
TEST(SplineGcode, G5AndG51AreTheBezierCurvesLinuxCncDescribes) {
  const auto r = run_program(
      "G21 G17 G0 X0 Y0 Z1\nF600\nG5 X10 Y0 I3 J5 P-3 Q5\nX20 P-3 Q-5\nG5.1 X25 Y5 I5 J0\n"
      "G20 G5 X1.5 Y0.5 I0.1 J0 P0 Q-0.1\nM2\n",
      wide_config());
  ASSERT_TRUE(r.check.ok) << (r.first_error() ? r.first_error()->message : "");
  const auto nb = nurbs_blocks(r.blocks);
  ASSERT_EQ(nb.size(), 4u);
  const double in = 25.4;
  const std::vector<std::vector<Vec3>> want = {
      {{0, 0, 1}, {3, 5, 1}, {7, 5, 1}, {10, 0, 1}},
      {{10, 0, 1}, {13, -5, 1}, {17, -5, 1}, {20, 0, 1}},  // (13, -5): the end direction of the first
      {{20, 0, 1}, {25, 0, 1}, {25, 5, 1}},
      {{25, 5, 1}, {25 + 0.1 * in, 5, 1}, {1.5 * in, 0.4 * in, 1}, {1.5 * in, 0.5 * in, 1}}};
  for (std::size_t k = 0; k < nb.size(); ++k) {
    const Block& b = nb[k];
    const auto& p = want[k];
    EXPECT_EQ(b.line, static_cast<std::uint32_t>(k + 3)) << k;
    EXPECT_EQ(b.nurbs.degree, static_cast<int>(p.size()) - 1) << k;
    ASSERT_EQ(b.nurbs.point_count, static_cast<int>(p.size())) << k;
    for (std::size_t i = 0; i < p.size(); ++i) {
      for (int a = 0; a < 3; ++a) EXPECT_NEAR(b.nurbs.points[i][a], p[i][a], 1e-12) << k << " point " << i;
      EXPECT_EQ(b.nurbs.weights[i], 1.0);
    }
    const NurbsView v = view_of(b.nurbs);
    for (int j = 0; j <= 50; ++j) {
      const double t = j / 50.0;
      const Vec3 q = nurbs_point(v, v.u_min() + t * (v.u_max() - v.u_min()));
      EXPECT_LT(norm(q - bezier(p, t)), 1e-12) << k << " t=" << t;
    }
    EXPECT_EQ(b.start, p.front());
    EXPECT_EQ(b.end, p.back());
  }
  // the continued cubic leaves in the direction the first one arrived
  const Vec3 d_in = nb[0].nurbs.points[3] - nb[0].nurbs.points[2];
  const Vec3 d_out = nb[1].nurbs.points[1] - nb[1].nurbs.points[0];
  EXPECT_LT(norm(d_in - d_out), 1e-12);
  EXPECT_EQ(r.check.moves, 5u);  // the G0 and the four splines
}

}  // namespace
}  // namespace pcnc
