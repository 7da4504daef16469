// test_rotary_pipeline.cpp — the rotary joints through the front end and the contract, on
// configs/desktop-5axis.toml: A/B/C words (degrees, G90/G91) into the blocks' joints (rad), their
// refusal where they cannot move, moves that only turn the tool (length and feed in rad),
// the joints' caps, M428/G43.4/M429/G49 and the TCP block's joint-space plan (tcp_move), the
// rotary block check (block_check_rotary), the preflight's joint limits, and the trace's joint
// columns (trace_format).
#include <gtest/gtest.h>

#include <cmath>

#include "config/joint_map.hpp"
#include "gcode/rotary_move.hpp"
#include "gcode/tcp_move.hpp"
#include "gcode_test_util.hpp"
#include "geometry/tcp_path.hpp"
#include "ipc/block_check.hpp"
#include "ipc/trace_format.hpp"
#include "test_paths.hpp"
#include "machine_runner.hpp"

namespace pcnc {
namespace {

using test::run_program;


JobOptions at_home() {
  JobOptions o;
  o.start_position = Vec3{12.5, 12.5, 25.0};
  return o;
}

// ---- the trace's joint columns ----

TEST(RotaryTrace, HeaderAndRowCarryTheDeclaredJointsInDegrees) {
  EXPECT_EQ(trace_csv_header(0), kTraceCsvHeader);
  EXPECT_EQ(trace_csv_header(0b101), std::string(kTraceCsvHeader) + ",cmd_a,act_a,ferr_a,cmd_c,act_c,ferr_c");
  EXPECT_EQ(trace_csv_header(0b010), std::string(kTraceCsvHeader) + ",cmd_b,act_b,ferr_b");
  TraceSample s;
  s.t = 1.5;
  s.line = 7;
  s.state = MachineState::kRunning;
  s.commanded = {1, 2, 3};
  s.actual = {1, 2, 3};
  TraceJoints j;
  j.mask = 0b101;
  j.commanded = {30.0 * kRadPerDeg, 0.0, -90.0 * kRadPerDeg};
  j.actual = {29.9 * kRadPerDeg, 0.0, -90.5 * kRadPerDeg};
  char buf[640];
  const int n = format_trace_row(buf, sizeof buf, s, j);
  ASSERT_GT(n, 0);
  const std::string row(buf);
  EXPECT_NE(row.find(",30.0000000,29.9000000,0.1000000,-90.0000000,-90.5000000,0.5000000"), std::string::npos) << row;
  // a machine without joints: the row as the 3-axis trace always had it
  EXPECT_EQ(std::string(buf, 0, row.find(",30.0000000")), trace_csv_row(s));
  TraceSample back;
  TraceJoints jb;
  jb.mask = 0b101;
  ASSERT_TRUE(parse_trace_row(row, back, &jb));
  EXPECT_NEAR(jb.commanded[0], j.commanded[0], 1e-9);
  EXPECT_NEAR(jb.actual[2], j.actual[2], 1e-9);
  EXPECT_EQ(jb.commanded[1], 0.0);
  TraceSample plain;
  EXPECT_TRUE(parse_trace_row(row, plain));  // the report's reader skips the joints
  EXPECT_FALSE(parse_trace_row(row + ",1", plain));  // not a whole joint group
}

// ---- the front end ----

TEST(RotaryGcode, AbcWordsInDegreesBecomeTheBlocksJointsInRadians) {
  const auto r = run_program("G21 G90\nG1 X1 A30 C-45 F600\nG91 G1 A10 C10\nG90 G1 Y2\nM2\n", test::five_axis_config(), at_home());
  ASSERT_TRUE(r.check.ok) << (r.first_error() ? r.first_error()->message : "");
  const auto m = r.motion();
  ASSERT_EQ(m.size(), 3u);
  EXPECT_NEAR(m[0].rotary.start[0], 0.0, 1e-15);
  EXPECT_NEAR(m[0].rotary.end[0], 30.0 * kRadPerDeg, 1e-15);
  EXPECT_NEAR(m[0].rotary.end[2], -45.0 * kRadPerDeg, 1e-15);
  EXPECT_EQ(m[0].rotary.tcp, 0);
  EXPECT_EQ(m[0].contouring, 0) << "a block that turns a joint ends at rest";
  // G91: increments of the joints
  EXPECT_NEAR(m[1].rotary.end[0], 40.0 * kRadPerDeg, 1e-15);
  EXPECT_NEAR(m[1].rotary.end[2], -35.0 * kRadPerDeg, 1e-15);
  EXPECT_EQ(m[1].rotary.angular, 1) << "X Y Z stand still";
  EXPECT_NEAR(m[1].length, std::hypot(10.0, 10.0) * kRadPerDeg, 1e-12);
  EXPECT_NEAR(m[1].speed, 600.0 / 60.0 * kRadPerDeg, 1e-12) << "F in deg/min on a move that only turns";
  // the next line keeps the joints
  EXPECT_EQ(m[2].rotary.start, m[2].rotary.end);
  EXPECT_NEAR(m[2].rotary.end[0], 40.0 * kRadPerDeg, 1e-15);
}

TEST(RotaryGcode, TheJointsCapTheSpeedOfAMoveTheyTurnIn) {
  // 1 mm of X while C turns 90 degrees: C at 720 deg/s max would need 100 mm/s * 90 deg/mm
  const MachineConfig cfg = test::five_axis_config();
  const auto r = run_program("G21 G90\nG1 X1 C90 F6000\nG0 A90\nM2\n", cfg, at_home());
  ASSERT_TRUE(r.check.ok) << (r.first_error() ? r.first_error()->message : "");
  const auto m = r.motion();
  const RotaryAxisConfig& c = *cfg.rotary[2];
  EXPECT_NEAR(m[0].speed, c.max_velocity_rad_s / (90.0 * kRadPerDeg), 1e-9);
  EXPECT_NEAR(m[0].accel, std::min(cfg.axes[0].max_accel_mm_s2, c.max_accel_rad_s2 / (90.0 * kRadPerDeg)), 1e-9);
  // a rapid of A alone: A's own limits
  EXPECT_NEAR(m[1].speed, cfg.rotary[0]->max_velocity_rad_s, 1e-12);
  EXPECT_NEAR(m[1].accel, cfg.rotary[0]->max_accel_rad_s2, 1e-12);
}

TEST(RotaryGcode, RotaryWordsWhereTheyCannotMoveAreRefusedAtTheirColumn) {
  auto r = run_program("G21 G90\nG2 X1 Y1 I1 A30 F100\nM2\n", test::five_axis_config(), at_home());
  ASSERT_NE(r.first_error(), nullptr);
  EXPECT_EQ(r.first_error()->line, 2);
  EXPECT_EQ(r.first_error()->column, 13);
  EXPECT_NE(r.first_error()->message.find("rotary joints move with G0 or G1 only"), std::string::npos);
  r = run_program("G21 G90\nG1 B30 F100\nM2\n", test::five_axis_config(), at_home());
  ASSERT_NE(r.first_error(), nullptr);
  EXPECT_NE(r.first_error()->message.find("the machine has no B axis"), std::string::npos);
  EXPECT_EQ(r.first_error()->column, 4);
}

TEST(RotaryGcode, PreflightRefusesAJointOutsideItsTravelBeforeAnythingMoves) {
  const auto r = run_program("G21 G90\nG1 A30 F600\nG1 A100\nG1 A0\nM2\n", test::five_axis_config(), at_home());
  EXPECT_FALSE(r.check.ok);
  ASSERT_NE(r.first_error(), nullptr);
  EXPECT_EQ(r.first_error()->line, 3);
  EXPECT_NE(r.first_error()->message.find("A 100.0000 deg is above the travel maximum 95.0000 deg"), std::string::npos)
      << r.first_error()->message;
  EXPECT_TRUE(r.blocks.empty());
}

TEST(RotaryGcode, NoRotaryMotionOrTcpUnderCutterCompensation) {
  auto r = run_program("G21 G90\nG1 X0 Y0 Z-5 F600\nG41.1 D2\nG1 X5 A10\nM2\n", test::five_axis_config(), at_home());
  ASSERT_NE(r.first_error(), nullptr);
  EXPECT_EQ(r.first_error()->line, 4);
  EXPECT_NE(r.first_error()->message.find("does not turn under cutter radius compensation"), std::string::npos)
      << r.first_error()->message;
  r = run_program("G21 G90\nG1 X0 Y0 Z-5 F600\nG41.1 D2\nG1 X5\nM428\nM2\n", test::five_axis_config(), at_home());
  ASSERT_NE(r.first_error(), nullptr);
  EXPECT_NE(r.first_error()->message.find("M428: tool-centre-point control under cutter radius compensation"),
            std::string::npos)
      << r.first_error()->message;
}

// ---- tool-centre-point control ----

TEST(RotaryTcp, M428KeepsTheMachineWhereItIsAndBlocksFollowTheTip) {
  const MachineConfig cfg = test::five_axis_config();
  const auto r = run_program("G21 G90\nG1 X1 Y1 Z-5 F600\nG1 A20 C30 F3600\nM428\nG1 X2 Y0 Z-6 F300\nM429\nG1 Z-2\nM2\n",
                             cfg, at_home());
  ASSERT_TRUE(r.check.ok) << (r.first_error() ? r.first_error()->message : "");
  const auto m = r.motion();
  ASSERT_EQ(m.size(), 4u);
  const Block& tcp = m[2];
  EXPECT_EQ(tcp.rotary.tcp, 1);
  // its start is the tip the joints give: M428 moved nothing
  const ToolPose at = forward(cfg.kinematics, to_joints(cfg, m[1].end, m[1].rotary.end));
  EXPECT_LT(norm(tcp.start - at.tip), 1e-9);
  // its end is the programmed tip in workpiece coordinates (program point + G54)
  EXPECT_LT(norm(tcp.end - Vec3{14.5, 12.5, 19.0}), 1e-9);
  // the end joints put the tip there with the programmed angles
  const ToolPose end = forward(cfg.kinematics, to_joints(cfg, tcp.rotary.joint_end, tcp.rotary.end));
  EXPECT_LT(norm(end.tip - tcp.end), 1e-9);
  EXPECT_NEAR(tcp.rotary.end[0], 20.0 * kRadPerDeg, 1e-12);
  // M429: the next block continues from the joints, in machine coordinates
  EXPECT_LT(norm(m[3].start - tcp.rotary.joint_end), 1e-9);
}

TEST(RotaryTcp, ToolLengthGoesAlongTheToolAxisNotOntoZ) {
  MachineConfig cfg = test::five_axis_config();
  JobOptions o = at_home();
  o.tools = std::make_shared<ToolTable>(load_tool_table(test::source_dir() + "/configs/desktop-mill.tbl"));
  // T2: 4.25 mm. A tilted 30 deg with TCP on: the gauge point lies 4.25 mm up the tool axis.
  const auto r = run_program("G21 G90\nT2 M6\nG1 X0 Y0 Z-8 F600\nG1 A30 F3600\nG43.4 H2\nG1 X1 F300\nG49\nM2\n", cfg, o);
  ASSERT_TRUE(r.check.ok) << (r.first_error() ? r.first_error()->message : "");
  const auto m = r.motion();
  const Block& tcp = m[2];
  ASSERT_EQ(tcp.rotary.tcp, 1);
  EXPECT_NEAR(tcp.rotary.tool_length, 4.25, 1e-12);
  const Kinematics kin = kinematics_with_tool(cfg, 4.25);
  const Joints qe = to_joints(cfg, tcp.rotary.joint_end, tcp.rotary.end);
  EXPECT_LT(norm(forward(kin, qe).tip - tcp.end), 1e-9);
  // the same joints with no tool put the gauge point 4.25 mm from the tip, along the axis
  const ToolPose gauge = forward(cfg.kinematics, qe);
  EXPECT_NEAR(norm(gauge.tip - tcp.end), 4.25, 1e-9);
  EXPECT_NEAR(dot(gauge.tip - tcp.end, gauge.axis), 4.25, 1e-9);
  // G43.4 moved nothing: the block starts at the tip the joints before it give with the tool, and
  // X1 moves the tip along X alone (its Z is not shifted by the length)
  const Joints before = to_joints(cfg, m[1].end, m[1].rotary.end);
  EXPECT_LT(norm(forward(kin, before).tip - tcp.start), 1e-9);
  EXPECT_NEAR(tcp.end[2], tcp.start[2], 1e-9);
  EXPECT_NEAR(tcp.end[1], tcp.start[1], 1e-9);
  // with the gauge point at program Z -8 (machine 17) and A 30 deg, the tip is 4.25 mm down the tilted axis
  EXPECT_NEAR(norm(forward(cfg.kinematics, before).tip - tcp.start), 4.25, 1e-9);
}

TEST(RotaryTcp, TheTcpBlocksSpeedKeepsEveryJointWithinItsLimits) {
  MachineConfig cfg = test::five_axis_config();
  // a short move with a large turn: the joints, not the feed, set the speed
  const auto r = run_program("G21 G90\nG1 X0 Y0 Z-5 F600\nG1 A10 F3600\nM428\nG1 X1 A30 C40 F3000\nM2\n", cfg, at_home());
  ASSERT_TRUE(r.check.ok) << (r.first_error() ? r.first_error()->message : "");
  const Block b = r.motion()[2];
  ASSERT_EQ(b.rotary.tcp, 1);
  EXPECT_LT(b.speed, 50.0) << "F3000 = 50 mm/s is lowered";
  const TcpMove mv{{b.start, b.rotary.axis_start}, {b.end, b.rotary.axis_end}};
  const Joints q0 = to_joints(cfg, r.motion()[1].end, b.rotary.start);
  const auto samples = sample_tcp_move(cfg.kinematics, mv, b.length, q0, 2000, cfg.rotary_travel());
  Joints v{}, a{};
  for (int i = 0; i < kAxes; ++i) {
    v[static_cast<std::size_t>(i)] = cfg.axes[static_cast<std::size_t>(i)].max_velocity_mm_s;
    a[static_cast<std::size_t>(i)] = cfg.axes[static_cast<std::size_t>(i)].max_accel_mm_s2;
  }
  v[kTilt] = cfg.rotary[0]->max_velocity_rad_s;
  a[kTilt] = cfg.rotary[0]->max_accel_rad_s2;
  v[kRotary] = cfg.rotary[2]->max_velocity_rad_s;
  a[kRotary] = cfg.rotary[2]->max_accel_rad_s2;
  double worst_v = 0.0, worst_a = 0.0;
  for (const JointSample& s : samples) {
    for (int j = 0; j < kJoints; ++j) {
      const auto k = static_cast<std::size_t>(j);
      worst_v = std::max(worst_v, std::abs(s.dq[k]) * b.speed / v[k]);
      worst_a = std::max(worst_a, (std::abs(s.dq[k]) * b.accel + std::abs(s.ddq[k]) * b.speed * b.speed) / a[k]);
    }
  }
  EXPECT_LE(worst_v, 1.0);
  EXPECT_LE(worst_a, 1.0);
  // a joint is near a limit (its speed, or the half of its acceleration the speed may use at the
  // 95 % share of tcp_move.hpp): the cap is not needlessly low
  EXPECT_GT(std::max(worst_v, worst_a), 0.45) << worst_v << " " << worst_a;
}

TEST(RotaryTcp, MovesTheRtCannotRunAsProgrammedAreRefused) {
  // from the pole (A0) the great circle leaves along C = 45, but C stands at 0
  auto r = run_program("G21 G90\nG1 X0 Y0 Z-5 F600\nM428\nG1 X1 A20 C45 F300\nM2\n", test::five_axis_config(), at_home());
  ASSERT_NE(r.first_error(), nullptr);
  EXPECT_EQ(r.first_error()->line, 4);
  EXPECT_NE(r.first_error()->message.find("leaves the pole of the C axis towards C 45 deg but C stands at 0 deg"),
            std::string::npos)
      << r.first_error()->message;
  // C 10 -> 350 with the tool tilted: the orientation goes the short way (through C 0)
  r = run_program("G21 G90\nG1 X0 Y0 Z-5 F600\nG1 A20 C10 F3600\nM428\nG1 X1 C350 F300\nM2\n", test::five_axis_config(), at_home());
  ASSERT_NE(r.first_error(), nullptr);
  EXPECT_NE(r.first_error()->message.find("turns the short way"), std::string::npos) << r.first_error()->message;
  // arcs under TCP
  r = run_program("G21 G90\nG1 X0 Y0 Z-5 F600\nM428\nG2 X1 Y1 I1 F300\nM2\n", test::five_axis_config(), at_home());
  ASSERT_NE(r.first_error(), nullptr);
  EXPECT_NE(r.first_error()->message.find("only G0 and G1 moves run"), std::string::npos);
}

TEST(RotaryTcp, ANullMoveIsAcceptedAndRunsNothingUnderTcpAndOff) {
  // G0 Z-5 where the tip stands (vertical tool, right after M428), and G91 moves of 0 with the
  // tool tilted under TCP: accepted, no block (LinuxCNC accepts a move to where it stands)
  const auto r = run_program(
      "G21 G90\nG1 X0 Y0 Z-5 F600\nM428\nG0 Z-5\nG1 X0 Y0 Z-5\nM429\nG1 A20 C30 F3600\nM428\nG91 G0 Z0\nG1 X0 "
      "F300\nG90\nG1 X1 F300\nM429\nG91 G0 X0\nG90\nM2\n",
      test::five_axis_config(), at_home());
  ASSERT_TRUE(r.check.ok) << (r.first_error() ? r.first_error()->message : "");
  const auto m = r.motion();
  ASSERT_EQ(m.size(), 3u);  // to the start, the tilt, the one TCP move that moves
  EXPECT_EQ(m[2].rotary.tcp, 1);
  EXPECT_GT(m[2].length, 0.5);
  // C turning on the pole with the tip still is still refused under TCP
  const auto c = run_program("G21 G90\nG1 X0 Y0 Z-5 F600\nM428\nG1 C30 F300\nM2\n", test::five_axis_config(), at_home());
  ASSERT_NE(c.first_error(), nullptr);
  EXPECT_EQ(c.first_error()->line, 4);
  EXPECT_NE(c.first_error()->message.find("neither moves the tool tip nor turns the tool axis"), std::string::npos)
      << c.first_error()->message;
}

TEST(RotaryTcp, PassingThroughThePoleKeepsC) {
  const MachineConfig cfg = test::five_axis_config();
  const auto r = run_program("G21 G90\nG1 X0 Y0 Z-5 F600\nG1 A20 C30 F3600\nM428\nG1 X2 A-20 C30 F300\nM2\n", cfg, at_home());
  ASSERT_TRUE(r.check.ok) << (r.first_error() ? r.first_error()->message : "");
  const Block b = r.motion()[2];
  const TcpMovePlan p = [&] {
    Move m;
    m.kind = MoveKind::kLine;
    m.start = b.start;
    m.end = b.end;
    m.rot_start = b.rotary.start;
    m.rot_end = b.rotary.end;
    m.tcp = true;
    return plan_tcp_move(m, cfg, 5.0);
  }();
  ASSERT_TRUE(p.error.empty()) << p.error;
  EXPECT_NEAR(p.q_min[kRotary], 30.0 * kRadPerDeg, 1e-9);
  EXPECT_NEAR(p.q_max[kRotary], 30.0 * kRadPerDeg, 1e-9);
  EXPECT_NEAR(p.q_min[kTilt], -20.0 * kRadPerDeg, 1e-9);
  EXPECT_NEAR(p.q_max[kTilt], 20.0 * kRadPerDeg, 1e-9);
}

// ---- the rotary block check ----

TEST(RotaryBlockCheck, RefusesWhatTheRtCannotRun) {
  const MachineConfig cfg = test::five_axis_config();
  const auto r = run_program("G21 G90\nG1 X0 Y0 Z-5 F600\nG1 A20 C30 F3600\nM428\nG1 X2 Y1 F300\nM2\n", cfg, at_home());
  ASSERT_TRUE(r.check.ok);
  const Block tcp = r.motion()[2];
  const Rot3 tail = tcp.rotary.start;
  EXPECT_EQ(check_rotary(tcp, tail, cfg).fault, FaultCode::kNone);
  Block b = tcp;
  Rot3 off = tail;
  off[2] += 0.01;
  EXPECT_NE(std::string(check_rotary(b, off, cfg).reason).find("start does not continue"), std::string::npos);
  b.rotary.joint_end[0] += 0.01;
  EXPECT_NE(std::string(check_rotary(b, tail, cfg).reason).find("do not put the tool tip at the end"), std::string::npos);
  b = tcp;
  b.rotary.end[0] = 100.0 * kRadPerDeg;
  EXPECT_NE(std::string(check_rotary(b, tail, cfg).reason).find("outside the joint's travel"), std::string::npos);
  b = tcp;
  b.rotary.end[1] = 0.5;  // the machine has no B
  EXPECT_NE(std::string(check_rotary(b, tail, cfg).reason).find("does not have"), std::string::npos);
  b = tcp;
  b.rotary.axis_end = {0.0, 0.0, 2.0};
  EXPECT_NE(std::string(check_rotary(b, tail, cfg).reason).find("unit"), std::string::npos);
  // the TCP start is checked against the tip the previous joints give
  const Vec3 expect = expected_block_start(tcp, r.motion()[1].end, tail, cfg);
  EXPECT_LT(norm(expect - tcp.start), 1e-9);
  // a 3-axis machine refuses any rotary motion
  b = r.motion()[1];
  EXPECT_NE(check_rotary(b, Rot3{}, load_config(test::default_config())).fault, FaultCode::kNone);
}

TEST(RotaryMoves, AngularLengthAndToolAxis) {
  const MachineConfig cfg = test::five_axis_config();
  Move m;
  m.kind = MoveKind::kLine;
  m.rot_end = {0.3, 0.0, 0.4};
  EXPECT_TRUE(moves_rotary(m));
  EXPECT_TRUE(angular_move(m));
  EXPECT_NEAR(angular_length(m, cfg), 0.5, 1e-15);
  m.tcp = true;
  m.rot_start = {0.3, 0.0, 0.0};
  m.rot_end = {0.3, 0.0, 0.4};
  // the axis turns about Z by 0.4 rad on a cone of half-angle 0.3: the great-circle angle between the ends
  const Vec3 a = tool_axis_of(cfg, m.rot_start), b = tool_axis_of(cfg, m.rot_end);
  EXPECT_NEAR(angular_length(m, cfg), std::acos(dot(a, b)), 1e-12);
  // the table-table axis at (A, C), docs/kinematics.md
  const Vec3 v = tool_axis_of(cfg, Rot3{0.3, 0.0, 0.4});
  EXPECT_NEAR(v[0], std::sin(0.3) * std::sin(0.4), 1e-15);
  EXPECT_NEAR(v[1], -std::sin(0.3) * std::cos(0.4), 1e-15);
  EXPECT_NEAR(v[2], std::cos(0.3), 1e-15);
  Move still;
  still.kind = MoveKind::kLine;
  EXPECT_FALSE(moves_rotary(still));
  EXPECT_FALSE(angular_move(still));
}

}  // namespace
}  // namespace pcnc
