// test_surfacing_limits.cpp — smoothed 3D surfacing through the rt, in-process (issue 14's
// speed goal must never cost the axes' limits): LHchips4 and blur_torus of the CAM corpus on the
// desktop mill with the bench's settings (--fit, M21, path tolerance 0.005 mm), every block made
// by the real front end and run cycle by cycle by the Machine (executor, PID, plant) as under
// --clock virtual. The commanded setpoints must keep every axis within its velocity limit (first
// differences, every cycle) and, on the smoothed curves (three cycles inside NURBS blocks, or
// across the tangent joins between the pieces of one curve), within its acceleration limit
// (second differences). Real corners between blocks are passed at the junction-deviation speed,
// rounded by the rt's corner blend over a short window (docs/rt-executor.md, "Corner blending");
// those cycles are not the curves': the blend asks more than an axis's limit there, for a few
// cycles (far less than the sharp corner's velocity step did in one), which is printed and held
// to a bound of its own.
// The arcs (the programs' G2/G3: LHchips4's lead-in and lead-out arcs, rgh's 643 small arcs;
// at most 0.95 of the plane's acceleration for the centripetal part, the tangential part by
// speed) are held to the same limits on the cycles inside one arc block.
// The setpoints are exact doubles here (no trace rounding); the only margin is 0.1 % of the
// limit for the second difference averaging the acceleration over two cycles while the
// curvature and the tangent turn. The worst ratios are printed as figures.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "check.hpp"
#include "gcode_test_util.hpp"
#include "machine_runner.hpp"
#include "make_blocks.hpp"
#include "test_paths.hpp"

namespace pcnc {
namespace {

constexpr double kAccelMargin = 1e-3;  // second differences against the limit (see above)
// In the corner blends' windows: the worst axis's acceleration as a ratio to its limit. The sharp
// corners asked 15 times Z's limit in one cycle at LHchips4's line 4954 (a 7.4 mm/s step) and
// about 29 times at line 8120 (two turns 2 µm apart, 14.6 mm/s in one cycle); the blend's worst,
// at line 8120 (a group window of 24 µm: 2.5 cycles at 19 mm/s), was 12.4; with the arcs ramped by
// speed it is 12.8, at line 3287 (another pair of turns around a 2 µm line).
constexpr double kBlendAccelBound = 15.0;

struct Run {
  std::size_t blocks = 0, nurbs = 0, curve_cycles = 0, arc_cycles = 0, blend_cycles = 0;
  double machine_time_s = 0.0;
  double worst_velocity = 0.0, worst_accel = 0.0, worst_arc_accel = 0.0, worst_blend_accel = 0.0;  // ratios to the limits
  std::uint32_t worst_blend_line = 0;
  int accel_violations = 0;
  std::string first_violation;
};

Run run_smoothed(const std::string& file) {
  MachineConfig c = test::mill_config();
  set_operator_tolerance(c.motion, 0.005);  // --tolerance 0.005 (the programs' G64 P would say 0.1)
  JobOptions o;
  o.fit = true;
  o.contouring = true;
  o.start_position = test::home(c);
  std::vector<Block> blocks;
  const CheckResult r = check_program(file, c, o, [&](const Block& b) { blocks.push_back(b); });
  EXPECT_TRUE(r.ok) << file;
  Run out;
  for (std::size_t i = 0; i < blocks.size(); ++i) {
    blocks[i].seq = i + 1;
    if (blocks[i].kind == BlockKind::kNurbs) ++out.nurbs;
  }
  out.blocks = blocks.size();
  test::MachineRunner run(c);
  run.start(blocks);
  run.run_until_done(4'000'000);
  EXPECT_EQ(run.status().program_done, 1) << file << ": " << run.machine().fault_reason();
  const double dt = run.dt();
  const auto& rec = run.records();
  out.machine_time_s = static_cast<double>(rec.size()) * dt;
  // a cycle on a curve: its block is NURBS and any join crossed since the cycle before last is
  // tangent (the pieces of one curve meet with the curve's own tangent)
  auto nurbs_seq = [&](std::uint64_t seq) { return seq >= 1 && seq <= blocks.size() && blocks[seq - 1].kind == BlockKind::kNurbs; };
  auto on_curve = [&](std::size_t k) {
    for (std::uint64_t q = rec[k - 2].seq; q <= rec[k].seq; ++q) {
      if (!nurbs_seq(q)) return false;
      if (q < rec[k].seq && !(q < blocks.size() && nurbs_seq(q + 1) && dot(blocks[q - 1].dir_end, blocks[q].dir_start) > 1.0 - 1e-9)) {
        return false;
      }
    }
    return true;
  };
  auto on_arc = [&](std::size_t k) {
    const std::uint64_t q = rec[k].seq;
    return rec[k - 2].seq == q && q >= 1 && q <= blocks.size() && blocks[q - 1].kind == BlockKind::kArc;
  };
  for (std::size_t k = 2; k < rec.size(); ++k) {
    const bool blend = rec[k].blend || rec[k - 1].blend || rec[k - 2].blend;
    const bool curve = !blend && on_curve(k);
    const bool arc = !blend && on_arc(k);
    if (curve) ++out.curve_cycles;
    if (arc) ++out.arc_cycles;
    if (blend) ++out.blend_cycles;
    for (int i = 0; i < kAxes; ++i) {
      const AxisConfig& ax = c.axes[static_cast<std::size_t>(i)];
      const double v = std::abs(rec[k].cmd[i] - rec[k - 1].cmd[i]) / dt;
      const double a = std::abs(rec[k].cmd[i] - 2.0 * rec[k - 1].cmd[i] + rec[k - 2].cmd[i]) / (dt * dt);
      out.worst_velocity = std::max(out.worst_velocity, v / ax.max_velocity_mm_s);
      if (blend && a / ax.max_accel_mm_s2 > out.worst_blend_accel) {
        out.worst_blend_accel = a / ax.max_accel_mm_s2;
        out.worst_blend_line = rec[k].line;
      }
      if (!curve && !arc) continue;
      double& worst = curve ? out.worst_accel : out.worst_arc_accel;
      worst = std::max(worst, a / ax.max_accel_mm_s2);
      if (a > ax.max_accel_mm_s2 * (1.0 + kAccelMargin) && out.accel_violations++ == 0) {
        out.first_violation = "cycle " + std::to_string(k) + " line " + std::to_string(rec[k].line) + " axis " +
                              std::to_string(i) + ": " + std::to_string(a) + " mm/s^2";
      }
    }
  }
  return out;
}

// What a program must exercise for its check to mean something: NURBS blocks, cycles on the
// curves and on the arcs, cycles in corner blends.
struct Coverage {
  std::size_t nurbs = 10, curve_cycles = 10000, arc_cycles = 1000, blend_cycles = 1000;
};

void expect_within_limits(const char* name, Coverage least = {}) {
  const std::string file = test::shared_dir() + "/gcode/cam/linuxcnc-tp/" + name;
  const Run r = run_smoothed(file);
  EXPECT_GT(r.nurbs, least.nurbs) << name << ": smoothed into curves";
  EXPECT_GT(r.curve_cycles, least.curve_cycles) << name;
  EXPECT_GT(r.arc_cycles, least.arc_cycles) << name << ": the programs' arcs";
  EXPECT_LE(r.worst_velocity, 1.0 + 1e-9) << name;
  EXPECT_EQ(r.accel_violations, 0) << name << ": first " << r.first_violation;
  EXPECT_GT(r.blend_cycles, least.blend_cycles) << name << ": the real corners are blended";
  EXPECT_LT(r.worst_blend_accel, kBlendAccelBound) << name;
  std::printf("[ figures  ] %s: %zu blocks (%zu NURBS), machine time %.2f s, worst setpoint velocity %.4f of "
              "the axis limit, on the curves (%zu cycles) acceleration %.4f, on the arcs (%zu cycles) %.4f, in the "
              "corner blends (%zu cycles) %.4f (line %u)\n",
              name, r.blocks, r.nurbs, r.machine_time_s, r.worst_velocity, r.curve_cycles, r.worst_accel, r.arc_cycles,
              r.worst_arc_accel, r.blend_cycles, r.worst_blend_accel, r.worst_blend_line);
}

TEST(SurfacingLimits, LHchips4KeepsEveryAxisWithinItsLimits) { expect_within_limits("LHchips4.ngc"); }

TEST(SurfacingLimits, BlurTorusKeepsEveryAxisWithinItsLimits) { expect_within_limits("blur_torus.ngc"); }

// 643 small arcs (radius 0.1–33 mm, median 0.7) between short lines: the arcs' acceleration
// shared by speed (rt/motion/path.hpp arc_path_accel) ramps and brakes them near the plane's
// limit at every speed.
TEST(SurfacingLimits, RghArcsKeepEveryAxisWithinItsLimits) {
  Coverage least;
  least.nurbs = 5;
  least.curve_cycles = 50;
  least.arc_cycles = 5000;
  least.blend_cycles = 100;
  expect_within_limits("rgh.ngc", least);
}

}  // namespace
}  // namespace pcnc
