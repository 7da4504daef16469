// test_block_check.cpp — the rt's block check (shared/ipc/block_check) reads the whole plan:
// blocks from the real preprocessor pass; a block whose seed driving-axis plan (driving_axis,
// driving_dir, driving_speed, driving_accel, decel_start), arc plan (angular_speed,
// angular_accel, decel_start_angle), motion class, arc tangents or optional-stop flag
// disagrees with its path, or a NURBS schedule that asks an axis for more than its velocity or
// acceleration limit, is refused with kBadBlock and a reason naming the field, and the
// machine faults on it naming the block's line. (Every corpus program's blocks pass:
// test_corpus.)
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <numbers>
#include <string>
#include <vector>

#include "gcode/preprocessor.hpp"
#include "gcode_test_util.hpp"
#include "ipc/block_check.hpp"
#include "machine_runner.hpp"
#include "make_blocks.hpp"

namespace pcnc {
namespace {

// A program through the real front end with one of each kind of block: rapids, single-axis,
// plane and space lines (a three-way tie), a short line, arcs in G17/G18/G19, a helix, a
// NURBS curve (fast enough that its schedule varies along it: many schedule points), a dwell,
// an optional stop and the end.
const char* kProgram =
    "G21 G90 G17\n"
    "G0 X0 Y0 Z-1\n"
    "G1 X5 F600\n"
    "G1 X8 Y4\n"
    "G1 X9 Y5 Z-2\n"
    "G1 X9.002\n"
    "G3 X4.002 Y10 I-5 J0\n"
    "G2 X9.002 Y5 I0 J-5\n"
    "G3 X9.002 Y5 Z-4 I-5 J0\n"
    "G18 G2 X5.002 Z-8 I-4 K0\n"
    "G19 G3 Y1 Z-4 J-4 K0\n"
    "G17 G4 P0.1\n"
    "M1\n"
    "G0 X0 Y0\n"
    "G5.2 P1 L3 F6000\n"
    "  X0 Y1 P1\n"
    "  X2 Y2 P1\n"
    "  X2 Y0 P1\n"
    "  X0 Y0 P2\n"
    "G5.3\n"
    "M2\n";

// Each block of a program with its sequence number and where the previous one ended, as the
// rt's executor checks it.
struct Checked {
  Block block;
  Vec3 tail;
};

std::vector<Checked> program_blocks(const MachineConfig& c) {
  JobOptions o;
  o.start_position = c.gcode.work_offsets[0];
  const test::RunResult r = test::run_program(kProgram, c, o);
  EXPECT_TRUE(r.check.ok) << (r.first_error() ? r.first_error()->message : "");
  std::vector<Checked> out;
  Vec3 tail = c.gcode.work_offsets[0];
  std::uint64_t seq = 0;
  for (Block b : r.blocks) {
    b.seq = ++seq;
    out.push_back({b, tail});
    if (b.kind != BlockKind::kDwell && b.kind != BlockKind::kPause && b.kind != BlockKind::kEnd) tail = b.end;
  }
  return out;
}

BlockVerdict check(const Checked& k, const MachineConfig& c) { return check_block(k.block, k.tail, k.block.seq, c); }

bool is_motion(const Block& b) {
  return b.kind == BlockKind::kRapid || b.kind == BlockKind::kLine || b.kind == BlockKind::kArc ||
         b.kind == BlockKind::kNurbs;
}

TEST(BlockCheck, EveryBlockOfTheRealPreprocessorPasses) {
  const MachineConfig c = test::mill_config();
  const std::vector<Checked> blocks = program_blocks(c);
  int lines = 0, arcs = 0, helices = 0, nurbs = 0, others = 0;
  for (const Checked& k : blocks) {
    const BlockVerdict v = check(k, c);
    EXPECT_EQ(v.fault, FaultCode::kNone) << "line " << k.block.line << ": " << v.reason;
    const Block& b = k.block;
    if (b.kind == BlockKind::kLine || b.kind == BlockKind::kRapid) ++lines;
    if (b.kind == BlockKind::kArc) ++(std::abs(b.arc.helix) > 0.0 ? helices : arcs);
    if (b.kind == BlockKind::kNurbs) ++nurbs;
    if (!is_motion(b)) ++others;
  }
  EXPECT_EQ(lines, 6);
  EXPECT_EQ(arcs, 4);     // two in G17, one each in G18 and G19
  EXPECT_EQ(helices, 1);  // the full G17 circle down 2 mm
  EXPECT_GE(nurbs, 1);
  EXPECT_EQ(others, 3);  // G4, M1, M2
}

// The plan of a single move as the preprocessor makes it, in the cases its formulas branch on.
TEST(BlockCheck, PreprocessorPlansOfSingleMovesPass) {
  MachineConfig c = test::wide_config();
  auto line = [](Vec3 a, Vec3 b, double feed) {
    Move m;
    m.kind = MoveKind::kLine;
    m.start = a;
    m.end = b;
    m.feed_mm_s = feed;
    return m;
  };
  auto arc = [](Vec3 start, Vec3 center, double r, double sweep, double helix, int normal, double feed) {
    Move m;
    m.kind = MoveKind::kArc;
    m.start = start;
    const auto pa = plane_axes(normal);
    const double th0 = std::atan2(start[pa[1]] - center[pa[1]], start[pa[0]] - center[pa[0]]);
    m.end = start;
    m.end[pa[0]] = center[pa[0]] + r * std::cos(th0 + sweep);
    m.end[pa[1]] = center[pa[1]] + r * std::sin(th0 + sweep);
    m.end[normal] += helix;
    m.center = center;
    m.center[normal] = start[normal];
    m.radius = r;
    m.sweep = sweep;
    m.normal_axis = normal;
    m.feed_mm_s = feed;
    return m;
  };
  const std::vector<Move> moves = {
      line({0, 0, 0}, {0, -10, 0}, 20),        // single axis, negative
      line({0, 0, 0}, {30, 40, 0}, 1000),      // plane, projected speed
      line({0, 0, 0}, {1, 1, 1}, 100),         // three-way tie, triangular profile
      line({0, 0, 0}, {0.001, 0, 0}, 100),     // a micrometre
      line({5, 5, 5}, {5, 5, 5 - 1e-10}, 10),  // below the moving threshold: no axis moves
      arc({10, 0, 0}, {0, 0, 0}, 10, std::numbers::pi / 2, 0, 2, 20),     // G17 quarter
      arc({10, 0, 0}, {0, 0, 0}, 10, -0.001, 0, 2, 200),                  // short: midpoint rule
      arc({10, 0, 0}, {0, 0, 0}, 10, 6 * std::numbers::pi, -3, 2, 10),    // helix down, 3 turns
      arc({0, 0, 10}, {0, 0, 0}, 10, -std::numbers::pi, 2, 1, 30),        // G18 helix up
      arc({0, 10, 0}, {0, 0, 0}, 10, 0.5, 0, 0, 30),                      // G19
  };
  for (std::size_t i = 0; i < moves.size(); ++i) {
    Block b = make_block(moves[i], c);
    b.seq = 1;
    const BlockVerdict v = check_block(b, moves[i].start, 1, c);
    EXPECT_EQ(v.fault, FaultCode::kNone) << "move " << i << ": " << v.reason;
  }
}

struct Corruption {
  const char* what;
  std::function<bool(const Block&)> applies;
  std::function<void(Block&)> corrupt;
  const char* reason;
};

bool straight(const Block& b) { return b.kind == BlockKind::kLine || b.kind == BlockKind::kRapid; }
bool arc(const Block& b) { return b.kind == BlockKind::kArc; }
bool nurbs(const Block& b) { return b.kind == BlockKind::kNurbs; }
bool planned(const Block& b) { return straight(b) || arc(b); }

const std::vector<Corruption>& corruptions() {
  static const std::vector<Corruption> list = {
      {"driving axis", [](const Block& b) { return is_motion(b); },
       [](Block& b) { b.driving_axis = static_cast<std::uint8_t>((b.driving_axis + 1) % kAxes); },
       "driving axis plan disagrees with the path: driving_axis"},
      {"driving axis out of range", [](const Block& b) { return is_motion(b); }, [](Block& b) { b.driving_axis = 7; },
       "driving axis plan disagrees with the path: driving_axis"},
      {"driving dir", [](const Block& b) { return is_motion(b); }, [](Block& b) { b.driving_dir = static_cast<std::int8_t>(-b.driving_dir); },
       "driving axis plan disagrees with the path: driving_dir"},
      {"driving speed", planned, [](Block& b) { b.driving_speed = b.driving_speed * 1.001 + 0.001 * b.speed; },
       "driving axis plan disagrees with the path: driving_speed"},
      {"driving speed NaN", planned, [](Block& b) { b.driving_speed = std::nan(""); },
       "driving axis plan disagrees with the path: driving_speed"},
      {"driving speed of a NURBS block", nurbs, [](Block& b) { b.driving_speed = 1.0; },
       "driving axis plan disagrees with the path: driving_speed"},
      {"driving accel", planned, [](Block& b) { b.driving_accel = b.driving_accel * 1.001 + 0.001 * b.accel; },
       "driving axis plan disagrees with the path: driving_accel"},
      {"decel start", [](const Block& b) { return is_motion(b); }, [](Block& b) { b.decel_start += 0.01; },
       "driving axis plan disagrees with the path: decel_start"},
      // a host that forgets the short-block rule: the full braking distance before the end
      {"decel start without the short-block rule", [](const Block& b) {
         return straight(b) && b.speed * b.speed / (2.0 * b.accel) > 0.5 * b.length + 0.01; },
       [](Block& b) {
         const int k = b.driving_axis;
         b.decel_start = b.end[k] - b.driving_dir * b.driving_speed * b.driving_speed / (2.0 * b.driving_accel);
       },
       "driving axis plan disagrees with the path: decel_start"},
      {"angular speed", arc, [](Block& b) { b.arc.angular_speed *= 1.001; },
       "arc plan disagrees with the path: angular_speed"},
      {"angular accel", arc, [](Block& b) { b.arc.angular_accel *= 1.001; },
       "arc plan disagrees with the path: angular_accel"},
      {"decel start angle", arc, [](Block& b) { b.arc.decel_start_angle += 0.01; },
       "arc plan disagrees with the path: decel_start_angle"},
      {"motion class", [](const Block& b) { return is_motion(b); },
       [](Block& b) { b.motion_class = b.motion_class == MotionClass::kSpace ? MotionClass::kPlane : MotionClass::kSpace; },
       "motion class disagrees with the axes that move"},
      {"arc tangent", arc, [](Block& b) { b.dir_end = -1.0 * b.dir_end; }, "arc: direction cosines disagree with the tangents"},
      {"optional stop on a move", [](const Block& b) { return is_motion(b); }, [](Block& b) { b.optional_stop = 1; },
       "optional_stop is set on a block that is not a pause, or is not 0 or 1"},
      // a NURBS schedule whose tangential accelerations leave no room for the normal part
      {"NURBS schedule acceleration above what the axes leave", nurbs,
       [](Block& b) {
         for (int j = 0; j < b.nurbs.schedule_count; ++j) b.nurbs.schedule_accel[j] *= 1.2;
       },
       "nurbs: feed schedule above an axis's acceleration limit"},
      {"NURBS block acceleration above its schedule's", nurbs, [](Block& b) { b.accel *= 1.01; },
       "nurbs: block acceleration above its schedule's"},
      {"NURBS schedule acceleration zero", nurbs, [](Block& b) { b.nurbs.schedule_accel[0] = 0.0; },
       "nurbs: feed schedule acceleration not positive"},
      {"NURBS schedule arc lengths halved", nurbs,
       [](Block& b) {
         for (int j = 0; j < b.nurbs.schedule_count; ++j) b.nurbs.schedule_s[j] *= 0.5;
       },
       "nurbs: feed schedule arc lengths do not run from 0 to the block length"},
      {"NURBS schedule arc length shorter than a chord", [](const Block& b) { return nurbs(b) && b.nurbs.schedule_count >= 3; },
       [](Block& b) { b.nurbs.schedule_s[1] = b.nurbs.schedule_s[0]; },
       "nurbs: feed schedule arc length shorter than the chord"},
      {"NURBS schedule speed above an axis's velocity", nurbs,
       [](Block& b) {
         for (int j = 0; j < b.nurbs.schedule_count; ++j) b.nurbs.schedule_speed[j] = 150.0;
       },
       "nurbs: feed schedule above an axis's velocity limit"},
  };
  return list;
}

TEST(BlockCheck, EveryCorruptedPlanFieldIsRefusedNamingTheField) {
  const MachineConfig c = test::mill_config();
  const std::vector<Checked> blocks = program_blocks(c);
  for (const Corruption& k : corruptions()) {
    int applied = 0;
    for (const Checked& good : blocks) {
      if (!k.applies(good.block)) continue;
      ++applied;
      Checked bad = good;
      k.corrupt(bad.block);
      const BlockVerdict v = check(bad, c);
      EXPECT_EQ(v.fault, FaultCode::kBadBlock) << k.what << ", line " << good.block.line;
      EXPECT_STREQ(v.reason, k.reason) << k.what << ", line " << good.block.line;
    }
    EXPECT_GE(applied, 1) << k.what << ": no block of the program to corrupt";
  }
}

// Rounding is not a wrong plan: a plan off by far less than the tolerances passes.
TEST(BlockCheck, RoundingInThePlanPasses) {
  const MachineConfig c = test::mill_config();
  for (Checked k : program_blocks(c)) {
    if (!planned(k.block)) continue;
    Block& b = k.block;
    b.driving_speed *= 1.0 + 1e-12;
    b.driving_accel *= 1.0 - 1e-12;
    b.decel_start += 0.1 * c.motion.block_tolerance_mm;
    b.arc.angular_speed *= 1.0 + 1e-12;
    b.arc.angular_accel *= 1.0 - 1e-12;
    const BlockVerdict v = check(k, c);
    EXPECT_EQ(v.fault, FaultCode::kNone) << "line " << b.line << ": " << v.reason;
  }
}

TEST(BlockCheck, OptionalStopOnlyOnAPause) {
  const MachineConfig c = test::mill_config();
  for (const Checked& k : program_blocks(c)) {
    if (k.block.kind != BlockKind::kPause) continue;
    EXPECT_EQ(k.block.optional_stop, 1);  // M1
    Checked bad = k;
    bad.block.optional_stop = 2;
    EXPECT_EQ(check(bad, c).fault, FaultCode::kBadBlock);
  }
}

// The rt refuses such a block before moving on it: a fault naming the block's line and the field.
TEST(BlockCheck, TheMachineFaultsOnAWrongPlanNamingTheBlock) {
  const MachineConfig c = test::default_machine_config();
  struct Case {
    int which;
    void (*corrupt)(Block&);
    const char* reason;
  };
  const Case cases[] = {
      {1, [](Block& b) { b.decel_start += 0.05; }, "driving axis plan disagrees with the path: decel_start"},
      {2, [](Block& b) { b.arc.angular_accel *= 2.0; }, "arc plan disagrees with the path: angular_accel"},
      {2, [](Block& b) { b.driving_speed += 1.0; }, "driving axis plan disagrees with the path: driving_speed"},
  };
  for (const Case& k : cases) {
    test::MachineRunner run(c);
    test::ProgramBuilder p(c, test::home(c));
    p.line({14.0, 12.5, 25.0}, 10.0).line({14.0, 14.0, 25.0}, 10.0).arc({11.0, 14.0, 25.0}, {12.5, 14.0, 25.0}, 2, false, 10.0);
    p.end();
    k.corrupt(p.blocks()[static_cast<std::size_t>(k.which)]);
    run.start(p.blocks());
    run.run_until_done(20000);
    const Status& s = run.status();
    ASSERT_EQ(s.state, MachineState::kFault) << k.reason;
    EXPECT_EQ(s.fault, FaultCode::kBadBlock) << k.reason;
    EXPECT_EQ(s.fault_line, static_cast<std::uint32_t>(k.which + 1)) << k.reason;
    EXPECT_STREQ(run.machine().fault_reason(), k.reason);
  }
  // the same program untouched runs to its end
  test::MachineRunner run(c);
  test::ProgramBuilder p(c, test::home(c));
  p.line({14.0, 12.5, 25.0}, 10.0).line({14.0, 14.0, 25.0}, 10.0).arc({11.0, 14.0, 25.0}, {12.5, 14.0, 25.0}, 2, false, 10.0);
  p.end();
  run.start(p.blocks());
  run.run_until_done();
  EXPECT_EQ(run.status().program_done, 1) << run.machine().fault_reason();
}

}  // namespace
}  // namespace pcnc
