// test_ruled_pipeline.cpp — G5.4 ... G5.5 through the front end (no processes): the one pipeline
// check and run share reads the group, places the points, checks the first against the pose the
// tool stands in, walks the joints (soft limits before anything moves, the pole), and makes
// `ruled` blocks that the rt's block check accepts, split at 32 segments; errors at file:line:col.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <sstream>

#include "config/joint_map.hpp"
#include "gcode/program.hpp"
#include "geometry/kinematics.hpp"
#include "test_paths.hpp"
#include "test_constants.hpp"
#include "machine_runner.hpp"

namespace pcnc {
namespace {


// The tool tilted (TCP off: G0 X-4 Y-2 Z-5, G1 A12 C35), then M428 and a G5.4 group of
// `points` + 1 set points along X from the tip, the axis swinging by `swing` rad toward +Y.
std::string program(const MachineConfig& cfg, int points, double length, double swing, double first_offset = 0.0,
                    double a_deg = 12.0) {
  const Vec3 xyz = Vec3{-4.0, -2.0, -5.0} + kG54;
  const Rot3 rot{a_deg * kRadPerDeg, 0.0, 35.0 * kRadPerDeg};
  const ToolPose p0 = forward(kinematics_with_tool(cfg, 0.0), to_joints(cfg, xyz, rot));
  std::ostringstream o;
  char buf[200];
  std::snprintf(buf, sizeof buf, "G21 G90 G94\nG0 X-4 Y-2 Z-5\nG1 A%.3f C35 F3600\nM428\nG5.4 F600\n", a_deg);
  o << buf;
  for (int k = 0; k <= points; ++k) {
    const double t = static_cast<double>(k) / points;
    const Vec3 p = p0.tip - kG54 + Vec3{length * t + (k == 0 ? first_offset : 0.0), 0.3 * std::sin(3.14159 * t), 0.0};
    const Vec3 a = normalized(p0.axis + (swing * std::sin(3.14159 * t)) * Vec3{0.0, 1.0, 0.0});
    std::snprintf(buf, sizeof buf, "X%.6f Y%.6f Z%.6f I%.9f J%.9f K%.9f\n", p[0], p[1], p[2], a[0], a[1], a[2]);
    o << buf;
  }
  o << "G5.5\nM429\nM2\n";
  return o.str();
}

std::string check_errors(const CheckResult& r) {
  std::string s;
  for (const Diagnostic& d : r.diagnostics) {
    if (d.severity == Diagnostic::Severity::kError) s += format_diagnostic(d) + "\n";
  }
  return s;
}

TEST(RuledPipeline, GroupBecomesRuledBlocksSplitAtThirtyTwoSegments) {
  const MachineConfig cfg = test::five_axis_config();
  std::vector<Block> blocks;
  const CheckResult r =
      check_program_text(program(cfg, 40, 8.0, 0.1), "r.ngc", cfg, JobOptions{}, [&](const Block& b) { blocks.push_back(b); });
  ASSERT_TRUE(r.ok) << check_errors(r);
  std::vector<Block> ruled;
  for (const Block& b : blocks) {
    if (b.kind == BlockKind::kRuled) ruled.push_back(b);
  }
  ASSERT_EQ(ruled.size(), 2u);
  EXPECT_EQ(ruled[0].ruled.segment_count, 32);
  EXPECT_EQ(ruled[1].ruled.segment_count, 8);
  EXPECT_EQ(ruled[0].line, 5u) << "the G5.4's line";
  EXPECT_EQ(ruled[0].ruled.start_speed, 0.0);
  EXPECT_NEAR(ruled[0].ruled.end_speed, 10.0, 1e-12) << "the split flows at the feed";
  EXPECT_NEAR(ruled[1].ruled.start_speed, 10.0, 1e-12);
  EXPECT_EQ(ruled[1].ruled.end_speed, 0.0);
  EXPECT_EQ(ruled[0].rotary.tcp, 1);
  EXPECT_EQ(ruled[1].rotary.start, ruled[0].rotary.end) << "the joints continue";
  EXPECT_NEAR(ruled[0].length + ruled[1].length, 8.0, 0.1);
  EXPECT_EQ(format_block(ruled[0]).rfind("L5 ruled (", 0), 0u) << format_block(ruled[0]);
}

TEST(RuledPipeline, FirstPointMustBeWhereTheToolStands) {
  const MachineConfig cfg = test::five_axis_config();
  const CheckResult r = check_program_text(program(cfg, 4, 4.0, 0.05, 0.2), "r.ngc", cfg, JobOptions{});
  EXPECT_FALSE(r.ok);
  EXPECT_NE(check_errors(r).find("r.ngc:6:1: error: the first set point of the G5.4 group is 0.2"), std::string::npos) << check_errors(r);
}

TEST(RuledPipeline, JointsOutsideTheTravelAreRefusedBeforeAnythingMoves) {
  const MachineConfig cfg = test::five_axis_config();
  // 30 mm along X: the linear joints leave the 25 mm travel along the piece
  const CheckResult r = check_program_text(program(cfg, 30, 30.0, 0.05), "r.ngc", cfg, JobOptions{});
  EXPECT_FALSE(r.ok);
  EXPECT_NE(check_errors(r).find("r.ngc:5:1: error: X "), std::string::npos) << check_errors(r);
  EXPECT_NE(check_errors(r).find("(machine, along the TCP move) is above the travel maximum 25.0000 mm"), std::string::npos) << check_errors(r);
}

TEST(RuledPipeline, LeavingThePoleTowardAnotherAngleIsRefused) {
  const MachineConfig cfg = test::five_axis_config();
  // the tool vertical (A0): the piece tilts it toward +Y, which C = 35 does not point to
  const CheckResult r = check_program_text(program(cfg, 8, 4.0, 0.1, 0.0, 0.0), "r.ngc", cfg, JobOptions{});
  EXPECT_FALSE(r.ok);
  EXPECT_NE(check_errors(r).find("r.ngc:5:1: error: G5.4 group: the ruled piece turns the rotary joint by"), std::string::npos)
      << check_errors(r);
}

}  // namespace
}  // namespace pcnc
