// test_tcp_fit.cpp — --fit of a tool-centre-point program (geometry/tcp_fit.hpp,
// gcode/tcp_fit_travel.hpp) on desktop-5axis.toml: a program with a vertical tool gets the 3-axis
// fit's scale (fit_to_travel); one at a constant tilt the scale computed from its turned
// extents; a tilted helix six times too large a scale whose every joint, sampled densely and
// independently, stays within the travel and touches it somewhere; the committed examples fit
// at scale 1; a TCP-off program that turns a rotary joint, and a tool axis beyond the tilt's
// travel, are refused with the line.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "config/config.hpp"
#include "five_axis_examples.hpp"
#include "five_axis_reader.hpp"
#include "gcode/preflight.hpp"
#include "gcode/tcp_fit_travel.hpp"
#include "geometry/tcp_path.hpp"
#include "test_paths.hpp"
#include "test_constants.hpp"
#include "machine_runner.hpp"

namespace pcnc {
namespace {



Vec3 axis_at(double a, double c) { return forward(Kinematics{KinematicsKind::kTableTable}, {0, 0, 0, a, c}).axis; }

std::vector<FitPose> poses_of(const std::vector<ProgramPose>& pp) {
  std::vector<FitPose> out;
  int line = 1;
  for (const ProgramPose& p : pp) out.push_back(FitPose{ToolPose{p.tip, p.axis}, true, 0.0, 0.0, line++});
  return out;
}

// The smallest distance of any joint x, y, z from its travel limits (negative: outside), at
// `samples` points of every move, tips placed at s·p + o: independent of the fit's own sampling.
double dense_margin(const std::vector<FitPose>& poses, const MachineConfig& c, double s, const Vec3& o, int samples = 101) {
  const JointTravel t = joint_travel(c);
  Joints q = home_joints(c);
  double margin = 1e300;
  auto place = [&](const FitPose& f) { return ToolPose{s * f.pose.tip + o, f.pose.axis}; };
  auto check = [&](const Joints& j) {
    for (std::size_t i = 0; i < 3; ++i) margin = std::min({margin, j[i] - t.min[i], t.max[i] - j[i]});
  };
  q = inverse(c.kinematics, place(poses.front()), q, t.rotary);
  check(q);
  for (std::size_t i = 1; i < poses.size(); ++i) {
    const TcpMove m{place(poses[i - 1]), place(poses[i])};
    const double len = norm(m.end.tip - m.start.tip);
    const double turn = std::acos(std::clamp(dot(m.start.axis, m.end.axis), -1.0, 1.0));
    if (len < 1e-12 && turn < 1e-12) continue;
    for (const JointSample& js : sample_tcp_move(c.kinematics, m, len > 1e-12 ? len : turn, q, samples, t.rotary)) {
      check(js.q);
      q = js.q;
    }
  }
  return margin;
}

TEST(TcpFit, AVerticalToolGetsTheThreeAxisScale) {
  const MachineConfig c = test::five_axis_config();
  // a 40 x 10 x 5 rectangle path, tool vertical
  std::vector<FitPose> p;
  const Vec3 corners[] = {{-20, -5, -10}, {20, -5, -10}, {20, 5, -15}, {-20, 5, -15}, {-20, -5, -10}};
  int line = 1;
  Box box;
  for (const Vec3& v : corners) {
    p.push_back(FitPose{ToolPose{v, {0, 0, 1}}, true, 0, 0, line++});
    box.add(v);
  }
  const TcpFitResult r = fit_tcp_to_travel(p, c);
  ASSERT_TRUE(r.ok) << r.error;
  const FitResult three = fit_to_travel(box, {0, 0, 0}, c);
  EXPECT_NEAR(r.scale, three.scale, 1e-8);
  EXPECT_NEAR(r.scale, 25.0 / 40.0, 1e-8);
  EXPECT_NEAR(r.offset[0], three.offset[0], 1e-6);  // X sets the scale: its offset is the only one
  EXPECT_GE(dense_margin(p, c, r.scale, r.offset), -1e-9);
}

TEST(TcpFit, AConstantTiltScalesByTheTurnedExtents) {
  const MachineConfig c = test::five_axis_config();
  const double a = 30.0 * kDeg, cc = 40.0 * kDeg;
  const Vec3 axis = axis_at(a, cc);
  std::vector<FitPose> p;
  const Vec3 corners[] = {{-15, -12, -20}, {15, -12, -20}, {15, 12, -18}, {-15, 12, -22}, {-15, -12, -20}};
  int line = 1;
  for (const Vec3& v : corners) p.push_back(FitPose{ToolPose{v, axis}, true, 0, 0, line++});
  // machine x, y, z of each corner at these angles, relative to the program origin's
  const Joints fixed{0, 0, 0, a, cc};
  Vec3 lo{1e9, 1e9, 1e9}, hi{-1e9, -1e9, -1e9};
  const Joints o = inverse(c.kinematics, {{0, 0, 0}, axis}, fixed);
  for (const Vec3& v : corners) {
    const Joints j = inverse(c.kinematics, {v, axis}, fixed);
    EXPECT_NEAR(j[kTilt], a, 1e-12);
    for (std::size_t i = 0; i < 3; ++i) {
      lo[i] = std::min(lo[i], j[i] - o[i]);
      hi[i] = std::max(hi[i], j[i] - o[i]);
    }
  }
  double want = 1.0;
  for (std::size_t i = 0; i < 3; ++i) want = std::min(want, 25.0 / (hi[i] - lo[i]));
  ASSERT_LT(want, 0.99);
  const TcpFitResult r = fit_tcp_to_travel(p, c);
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_NEAR(r.scale, want, 1e-8);
  EXPECT_GE(dense_margin(p, c, r.scale, r.offset), -1e-9);
}

TEST(TcpFit, ATooLargeTiltedHelixIsScaledUntilItsJointsFit) {
  const MachineConfig c = test::five_axis_config();
  TiltedHelix h;
  h.radius = 24.0;
  h.pitch = 9.0;
  h.base = {0.0, 0.0, -20.0};
  const std::vector<FitPose> p = poses_of(tilted_helix_example(h).poses);
  EXPECT_LT(dense_margin(p, c, 1.0, c.gcode.work_offsets[0]), -1.0);  // as written it leaves the travel
  const TcpFitResult r = fit_tcp_to_travel(p, c);
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_GT(r.scale, 0.2);
  EXPECT_LT(r.scale, 0.9);
  EXPECT_GT(r.samples, 180 * 16);
  const double m = dense_margin(p, c, r.scale, r.offset, 201);
  // every joint inside its travel, also between the fit's dense samples (8 x 16 per move: what
  // x, y, z bulge between them, about 1/64 of the 0.9 um seen between 16 samples alone, is left)
  EXPECT_GE(m, -1e-4);
  EXPECT_LT(m, 1e-3);   // and one at a limit: the scale is not smaller than it needs to be
  // a little larger fits at no offset the fit knows
  EXPECT_LT(dense_margin(p, c, r.scale * 1.01, r.offset), 0.0);
}

TEST(TcpFit, TheExamplesFitAsWritten) {
  const MachineConfig c = test::five_axis_config();
  for (const FiveAxisExample& e : five_axis_examples()) {
    const TcpFitResult r = fit_tcp_to_travel(poses_of(e.poses), c);
    ASSERT_TRUE(r.ok) << e.file << ": " << r.error;
    EXPECT_EQ(r.scale, 1.0) << e.file;
    EXPECT_GT(r.margin_mm, 0.0) << e.file;
    // the fit's offset leaves at least the margin of the program's own (G54) everywhere
    EXPECT_GE(r.margin_mm + 1e-9, dense_margin(poses_of(e.poses), c, 1.0, c.gcode.work_offsets[0], 17)) << e.file;
    EXPECT_GE(dense_margin(poses_of(e.poses), c, 1.0, r.offset), -1e-6) << e.file;
  }
}

TEST(TcpFit, ScalesThatFitNeedNotStartAtZero) {
  // The tool horizontal, pointing -Y at one end and +Y at the other: the gauge point (Z joint)
  // is (tip - pivot)·axis, which a Z travel of 2..25 keeps between 2 and 25 at both ends, so the
  // ends must lie at least 4 mm and at most 50 mm apart along Y: with 60 mm programmed, s lies
  // in [1/15, 5/6]. At s = 0 nothing fits: the fit must still find 5/6.
  Kinematics kin;
  kin.kind = KinematicsKind::kTableTable;
  kin.tilt_pivot = kin.rotary_pivot = {12.5, 12.5, 0.0};
  JointTravel t;
  t.min = {0.0, 0.0, 2.0};
  t.max = {25.0, 25.0, 25.0};
  const std::vector<FitPose> p = {FitPose{ToolPose{{0, -30, 5}, axis_at(90 * kDeg, 0)}, true, 0, 0, 1},
                                  FitPose{ToolPose{{0, 30, 5}, axis_at(-90 * kDeg, 0)}, true, 0, 0, 2}};
  const TcpFitResult r = fit_tcp_program(p, kin, t, {12.5, 12.5, 25.0, 0.0, 0.0});
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_NEAR(r.scale, 25.0 / 30.0, 1e-6);
  // both ends' Z joints inside 2..25 at (s, o)
  for (const FitPose& f : p) {
    const Joints j = inverse(kin, ToolPose{r.scale * f.pose.tip + r.offset, f.pose.axis}, {12.5, 12.5, 25.0, 0.0, 0.0});
    for (std::size_t i = 0; i < 3; ++i) {
      EXPECT_GE(j[i], t.min[i] - 1e-6) << f.line << " joint " << i;
      EXPECT_LE(j[i], t.max[i] + 1e-6) << f.line << " joint " << i;
    }
  }
}

TEST(TcpFit, ATcpOffProgramThatTurnsARotaryJointIsRefused) {
  const MachineConfig c = test::five_axis_config();
  const std::vector<FitPose> p = {FitPose{ToolPose{{0, 0, -10}, {0, 0, 1}}, false, 0.0, 0.0, 3},
                                  FitPose{ToolPose{{5, 0, -10}, {0, 0, 1}}, false, 20 * kDeg, 0.0, 4}};
  const TcpFitResult r = fit_tcp_to_travel(p, c);
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.error.find("line 4"), std::string::npos) << r.error;
  EXPECT_NE(r.error.find("tool-centre-point control off"), std::string::npos) << r.error;
  // with the angles at 0 a TCP-off program is a 3-axis one and fits
  const std::vector<FitPose> flat = {FitPose{ToolPose{{0, 0, -10}, {0, 0, 1}}, false, 0.0, 0.0, 3},
                                     FitPose{ToolPose{{50, 0, -10}, {0, 0, 1}}, false, 0.0, 0.0, 4}};
  const TcpFitResult f = fit_tcp_to_travel(flat, c);
  ASSERT_TRUE(f.ok) << f.error;
  EXPECT_NEAR(f.scale, 0.5, 1e-8);
}

TEST(TcpFit, AnAxisBeyondTheTiltTravelIsRefused) {
  const MachineConfig c = test::five_axis_config();
  const std::vector<FitPose> p = {FitPose{ToolPose{{0, 0, -10}, {0, 0, 1}}, true, 0, 0, 7},
                                  FitPose{ToolPose{{1, 0, -10}, axis_at(60 * kDeg, 0)}, true, 0, 0, 8},
                                  FitPose{ToolPose{{2, 0, -10}, axis_at(120 * kDeg, 0)}, true, 0, 0, 9}};
  const TcpFitResult r = fit_tcp_to_travel(p, c);
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.error.find("line 9"), std::string::npos) << r.error;
  EXPECT_NE(r.error.find("never the angles"), std::string::npos) << r.error;
}

}  // namespace
}  // namespace pcnc
