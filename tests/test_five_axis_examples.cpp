// test_five_axis_examples.cpp — the project's 5-axis test programs (examples/5axis/, written by
// tools/five_axis_examples.cpp): the committed files are what the generator writes for
// configs/desktop-5axis.toml; read back with the project's lexer, every pose's A and C give a
// tool axis (forward kinematics) that, with the programmed tip, lies on the intended geometry
// (the blade's flank offsets, the helix, the dome's normals); every move, sampled as the
// tool-centre-point interpolation runs it (tip on the line, axis on the great circle), keeps
// every joint inside the config's travel, and ends on the written A and C; the TCP-off moves only
// turn C on the pole; and each file passes the whole front end (`pcnc check`'s run_check_command
// on the 5-axis config) with no error or warning.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "config/config.hpp"
#include "five_axis_examples.hpp"
#include "check.hpp"
#include "five_axis_reader.hpp"
#include "geometry/kinematics.hpp"
#include "geometry/tcp_path.hpp"
#include "test_paths.hpp"
#include "test_constants.hpp"
#include "machine_runner.hpp"

namespace pcnc {
namespace {

constexpr double kTipTol = 1.5e-4;   // X Y Z written with 4 decimals
constexpr double kAxisTol = 3e-5;    // rad; A C written with 4 decimals (1.7e-6 rad), tips over 5 mm


Joints home(const MachineConfig& c) {
  return {c.axes[0].home_mm, c.axes[1].home_mm, c.axes[2].home_mm, c.tilt_joint()->home_rad, c.rotary_joint()->home_rad};
}

std::string read_file(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string example_text(const FiveAxisExample& e, const MachineConfig& c) {
  std::string text;
  for (const std::string& l : five_axis_program_lines(e, c.kinematics, c.rotary_travel(), c.gcode.work_offsets[0], home(c)))
    text += l + "\n";
  return text;
}

Vec3 axis_of(const MachineConfig& c, const test::ReadPose& p) {
  return forward(c.kinematics, Joints{0.0, 0.0, 0.0, p.a_deg * kDeg, p.c_deg * kDeg}).axis;
}

double angle_between_axes(const Vec3& a, const Vec3& b) { return std::atan2(norm(cross(a, b)), dot(a, b)); }

test::ReadProgram read_example(const std::string& file) {
  const std::string text = read_file(test::source_dir() + "/examples/5axis/" + file);
  EXPECT_FALSE(text.empty()) << file;
  return test::read_five_axis_program(text);
}

TEST(FiveAxisExamples, CommittedFilesAreWhatTheGeneratorWrites) {
  const MachineConfig c = test::five_axis_config();
  for (const FiveAxisExample& e : five_axis_examples()) {
    const std::string committed = read_file(test::source_dir() + "/examples/5axis/" + e.file);
    EXPECT_EQ(committed, example_text(e, c)) << e.file << ": regenerate with `pcnc examples-5axis --config "
                                                           "configs/desktop-5axis.toml -o examples/5axis`";
  }
}

// Every move from the home pose on, under TCP: joints inside the travel at every sample, and the
// move's end joints are the written A and C.
void check_joints(const std::string& file, int* pole_crossings = nullptr, int* turns_off_tcp = nullptr) {
  const MachineConfig c = test::five_axis_config();
  const test::ReadProgram prog = read_example(file);
  ASSERT_TRUE(prog.errors.empty()) << file << ": " << prog.errors.front();
  EXPECT_EQ(prog.warnings, 0u) << file << ": the lexer warns (LinuxCNC refuses what it warns about)";
  ASSERT_GT(prog.poses.size(), 10u);
  EXPECT_TRUE(prog.ended) << file;
  EXPECT_FALSE(prog.tcp_at_end) << file << ": M429 before the end";
  const Vec3 g54 = c.gcode.work_offsets[0];
  const RotaryTravel travel = c.rotary_travel();
  const RotaryAxisConfig& a = *c.tilt_joint();
  Joints q = home(c);
  ToolPose from = forward(c.kinematics, q);
  int samples_checked = 0;
  int turns = 0;
  for (const test::ReadPose& p : prog.poses) {
    if (!p.tcp) {
      // TCP off: only C turns, on the pole (the tool axis stays on the C axis)
      EXPECT_TRUE(p.rapid) << file << ":" << p.line;
      EXPECT_NEAR(q[kTilt], 0.0, 1e-12) << file << ":" << p.line << ": a TCP-off turn off the pole";
      EXPECT_NEAR(p.a_deg, 0.0, 1e-12) << file << ":" << p.line;
      q[kRotary] = p.c_deg * kDeg;
      from = forward(c.kinematics, q);
      ++turns;
      continue;
    }
    const ToolPose to{p.tip + g54, axis_of(c, p)};
    const double length = norm(to.tip - from.tip);
    const double turn = angle_between_axes(from.axis, to.axis);
    if (length < 1e-12 && turn < 1e-12) continue;
    const std::vector<JointSample> s =
        sample_tcp_move(c.kinematics, TcpMove{from, to}, length > 1e-12 ? length : turn, q, 64, travel);
    for (const JointSample& js : s) {
      for (int i = 0; i < 3; ++i) {
        EXPECT_GE(js.q[i], c.axes[i].travel_min_mm - 1e-9) << file << ":" << p.line << " axis " << axis_name(i);
        EXPECT_LE(js.q[i], c.axes[i].travel_max_mm + 1e-9) << file << ":" << p.line << " axis " << axis_name(i);
      }
      EXPECT_GE(js.q[kTilt], a.travel_min_rad) << file << ":" << p.line;
      EXPECT_LE(js.q[kTilt], a.travel_max_rad) << file << ":" << p.line;
      ++samples_checked;
    }
    const Joints end = s.back().q;
    EXPECT_NEAR(end[kTilt] / kDeg, p.a_deg, 1e-3) << file << ":" << p.line;
    EXPECT_NEAR(end[kRotary] / kDeg, p.c_deg, 1e-3) << file << ":" << p.line;
    // the joints put the tip where it was programmed
    const ToolPose back = forward(c.kinematics, end);
    EXPECT_LT(norm(back.tip - to.tip), 1e-9) << file << ":" << p.line;
    if (pole_crossings && (q[kTilt] < 0.0) != (end[kTilt] < 0.0) && std::abs(q[kTilt]) + std::abs(end[kTilt]) > 1e-9)
      ++*pole_crossings;
    q = end;
    from = to;
  }
  EXPECT_GT(samples_checked, 1000) << file;
  if (turns_off_tcp) *turns_off_tcp = turns;
}

TEST(FiveAxisExamples, BladeJointsStayInsideTheTravel) {
  int turns = 0;
  check_joints("impeller-blade.ngc", nullptr, &turns);
  EXPECT_EQ(turns, 1);  // C turned at the start, before the first move leaves the pole
}
TEST(FiveAxisExamples, HelixJointsStayInsideTheTravel) {
  int turns = 0;
  check_joints("tilted-helix.ngc", nullptr, &turns);
  EXPECT_EQ(turns, 1);
}
TEST(FiveAxisExamples, SingularityJointsStayInsideTheTravel) {
  int crossings = 0, turns = 0;
  check_joints("singularity.ngc", &crossings, &turns);
  EXPECT_GE(crossings, 1);  // A changes sign: the path goes through the pole
  EXPECT_EQ(turns, 4);      // at the start and before each of pass 3's moves leaving the pole
}

// Every committed example through the whole front end, as `pcnc check` runs it on the 5-axis
// config (interpreter, preflight with the joints' soft limits, TCP planning with its pole check,
// the rt's block check): accepted, with no error and no warning.
TEST(FiveAxisExamples, CommittedFilesPassTheFrontEnd) {
  for (const FiveAxisExample& e : five_axis_examples()) {
    CheckCommandOptions o;
    o.file = test::source_dir() + "/examples/5axis/" + e.file;
    o.config_path = test::source_dir() + "/configs/desktop-5axis.toml";
    o.quiet = true;
    std::ostringstream out, err;
    const int status = run_check_command(o, out, err);
    EXPECT_EQ(status, 0) << e.file << ":\n" << err.str() << out.str();
    EXPECT_EQ(err.str().find("error"), std::string::npos) << e.file << ":\n" << err.str();
    EXPECT_EQ(err.str().find("warning"), std::string::npos) << e.file << ":\n" << err.str();
  }
}

TEST(FiveAxisExamples, BladeFlankPassesLieOnTheOffsetRuledSurface) {
  const MachineConfig c = test::five_axis_config();
  const Blade b;
  const test::ReadProgram prog = read_example("impeller-blade.ngc");
  const double offsets[2] = {b.half_thickness + b.tool_radius + b.stock, b.half_thickness + b.tool_radius};
  int cutting = 0, per_face[2] = {0, 0};
  for (const test::ReadPose& p : prog.poses) {
    if (p.rapid) continue;
    ++cutting;
    EXPECT_TRUE(p.has_f && p.f == 240.0) << p.line;
    const Vec3 axis = axis_of(c, p);
    // the u where the tool's flank touches: the ruling parallel to the programmed axis, then
    // the tip one offset from the hub edge along the surface normal
    double best = 1e9, best_u = 0.0;
    for (int i = 0; i <= 4000; ++i) {
      const double u = i / 4000.0;
      const double d = angle_between_axes(axis, blade_ruling(b, u));
      if (d < best) { best = d; best_u = u; }
    }
    // refine by ternary search around the best grid point
    double lo = std::max(0.0, best_u - 1.0 / 4000), hi = std::min(1.0, best_u + 1.0 / 4000);
    for (int k = 0; k < 100; ++k) {
      const double m1 = lo + (hi - lo) / 3, m2 = hi - (hi - lo) / 3;
      if (angle_between_axes(axis, blade_ruling(b, m1)) < angle_between_axes(axis, blade_ruling(b, m2))) hi = m2; else lo = m1;
    }
    const double u = 0.5 * (lo + hi);
    EXPECT_LT(angle_between_axes(axis, blade_ruling(b, u)), kAxisTol) << p.line;
    double nearest = 1e9;
    int face = -1;
    for (int side = 0; side < 2; ++side)
      for (double d : offsets) {
        const double e = norm(p.tip - (blade_hub(b, u) + ((side ? -1.0 : 1.0) * d) * blade_normal(b, u)));
        if (e < nearest) { nearest = e; face = side; }
      }
    EXPECT_LT(nearest, 3e-4) << p.line << " at u " << u;
    ++per_face[face];
  }
  EXPECT_EQ(cutting, 4 * 41);
  EXPECT_EQ(per_face[0], 2 * 41);
  EXPECT_EQ(per_face[1], 2 * 41);
}

TEST(FiveAxisExamples, HelixPointsLieOnTheTiltedHelixInInverseTime) {
  const MachineConfig c = test::five_axis_config();
  const TiltedHelix h;
  Vec3 w, e1, e2;
  helix_frame(h, w, e1, e2);
  const test::ReadProgram prog = read_example("tilted-helix.ngc");
  double theta = 0.0, last_theta = 0.0;
  bool first = true;
  Vec3 last_tip{};
  int cutting = 0;
  for (const test::ReadPose& p : prog.poses) {
    EXPECT_TRUE(p.inverse_time) << p.line;
    if (p.rapid) {
      last_tip = p.tip;
      continue;
    }
    ++cutting;
    const Vec3 q = p.tip - h.base;
    const double along = dot(q, w);
    const Vec3 radial = q - along * w;
    EXPECT_NEAR(norm(radial), h.radius, kTipTol) << p.line;
    const double raw = std::atan2(dot(radial, e2), dot(radial, e1));
    theta = first ? raw : last_theta + std::remainder(raw - last_theta, 2.0 * std::numbers::pi);
    if (first) {
      EXPECT_NEAR(theta, 0.0, 1e-4);
    }
    EXPECT_NEAR(along, h.pitch * theta / (2.0 * std::numbers::pi), kTipTol) << p.line;
    const double lean = h.lean_deg * kDeg;
    const Vec3 want = std::cos(lean) * w + std::sin(lean) * normalized(radial);
    EXPECT_LT(angle_between_axes(axis_of(c, p), want), kAxisTol) << p.line;
    // G93: F is the inverse of the move's minutes at 300 mm/min of the tip
    ASSERT_TRUE(p.has_f) << p.line;
    const double length = norm(p.tip - last_tip);
    ASSERT_GT(length, 0.1) << p.line;
    EXPECT_NEAR(p.f * length, 300.0, 300.0 * 3e-4 / length + 1e-3) << p.line;  // tips to 1e-4 mm
    last_theta = theta;
    last_tip = p.tip;
    first = false;
  }
  EXPECT_NEAR(theta, h.turns * 2.0 * std::numbers::pi, 1e-4);  // three whole turns
  EXPECT_EQ(cutting, 181);
}

TEST(FiveAxisExamples, DomePassesAreNormalToTheDomeAndCrossThePole) {
  const MachineConfig c = test::five_axis_config();
  const Dome d;
  const test::ReadProgram prog = read_example("singularity.ngc");
  std::vector<std::vector<test::ReadPose>> passes(1);
  for (const test::ReadPose& p : prog.poses) {
    if (p.rapid) {
      if (!passes.back().empty()) passes.emplace_back();
      continue;
    }
    const Vec3 r = p.tip - d.centre;
    EXPECT_NEAR(norm(r), d.radius, kTipTol) << p.line;
    EXPECT_LT(angle_between_axes(axis_of(c, p), r), kAxisTol) << p.line;
    EXPECT_TRUE(p.has_f && p.f == 200.0) << p.line;
    passes.back().push_back(p);
  }
  if (passes.back().empty()) passes.pop_back();
  ASSERT_EQ(passes.size(), 5u);
  // 1: through the pole: one pose at A = 0, A changes sign, C never moves
  const auto& one = passes[0];
  int at_pole = 0;
  for (const auto& p : one) {
    at_pole += p.a_deg == 0.0;
    EXPECT_EQ(p.c_deg, one.front().c_deg) << p.line;
  }
  EXPECT_EQ(at_pole, 1);
  EXPECT_LT(one.front().a_deg * one.back().a_deg, 0.0);
  // 2: beside the pole: the tilt never falls below the miss, C turns through nearly 180 deg
  double min_a = 1e9;
  for (const auto& p : passes[1]) min_a = std::min(min_a, std::abs(p.a_deg));
  EXPECT_GE(min_a, d.beside_deg - 1e-3);
  EXPECT_GT(std::abs(passes[1].back().c_deg - passes[1].front().c_deg), 150.0);
  // 3: three passes leaving the pole (A = 0 at their first pose), each in another direction
  for (int k = 2; k < 5; ++k) {
    EXPECT_EQ(passes[static_cast<std::size_t>(k)].front().a_deg, 0.0);
    EXPECT_NEAR(std::abs(passes[static_cast<std::size_t>(k)].back().a_deg), d.reach_deg, 1e-3);
  }
}

}  // namespace
}  // namespace pcnc
