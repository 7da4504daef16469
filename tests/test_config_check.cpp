// test_config_check.cpp — `pcnc config check`: the machine as understood on stdout (axes with
// travel, limits, drive and gains; cycle rate; contouring; timing) and exit 0, or every
// problem on stderr and exit 2; a drive too weak for its acceleration limit is a warning.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "config_check.hpp"
#include "subprocess.hpp"
#include "test_paths.hpp"
#include "text_lines.hpp"

namespace pcnc {
namespace {

using test::has;

TEST(ConfigCheck, PrintsTheDefaultMachineAsUnderstood) {
  std::ostringstream out, err;
  ASSERT_EQ(run_config_check(test::default_config(), false, out, err), 0) << err.str();
  const std::string text = out.str();
  EXPECT_TRUE(has(text, ": OK: machine 'desktop-mill'")) << text;
  EXPECT_TRUE(has(text, "cycle        2000 Hz (period 500 us)")) << text;
  EXPECT_TRUE(has(text, "contouring   angle 10 deg, at program start off (M22)")) << text;
  // one row per axis in each table: travel and limits, drive, gains
  EXPECT_TRUE(has(text, "\n  X     0 .. 25 (25)        12.5      100         2000        ")) << text;
  EXPECT_TRUE(has(text, "\n  Z     0 .. 25 (25)        25        50          1000        ")) << text;
  EXPECT_TRUE(has(text, "\n  Z     0.8      10      3        30       7.85       ")) << "mass, Kf, I_max, F_max, gravity: " << text;
  EXPECT_TRUE(has(text, "\n  X     45       4500         0.14933    800  ")) << "Kp, Ki, Kd, filter: " << text;
  EXPECT_TRUE(has(text, "timing       host lost after 0.1 s, rt lost after 0.1 s, jog dead-man 0.5 s")) << text;
  EXPECT_TRUE(has(text, "offsets      G54 (12.5, 12.5, 25) mm")) << text;
  EXPECT_TRUE(has(text, "probe        ball R 1 mm, pre-travel axial 0.004 mm, lateral 0.008 + 0.003 x cos 3az mm")) << text;
  EXPECT_TRUE(has(text, "table        workpiece top z = 15 + 0 x + 0 y mm\n")) << text;
  EXPECT_TRUE(err.str().empty()) << "no warning for the shipped machine: " << err.str();
}

TEST(ConfigCheck, EveryProblemOnStderrAndExit2) {
  const std::string dir = test::make_temp_dir("cfgcheck");
  std::string text = test::read_file(test::default_config());
  text.erase(text.find("[axis.z]"));
  text.replace(text.find("cycle_hz"), 8, "cyle_hz");
  const std::string path = dir + "/broken.toml";
  std::ofstream(path) << text;
  std::ostringstream out, err;
  EXPECT_EQ(run_config_check(path, false, out, err), 2);
  EXPECT_TRUE(out.str().empty()) << out.str();
  EXPECT_TRUE(has(err.str(), path + ": missing section [axis.z]")) << err.str();
  EXPECT_TRUE(has(err.str(), "unknown key 'cyle_hz' (did you mean 'cycle_hz'?)")) << err.str();
  EXPECT_TRUE(has(err.str(), path + ": 3 problems; the config is refused")) << err.str();
}

TEST(ConfigCheck, AnAccelerationTheDriveCannotGiveIsAWarning) {
  const std::string dir = test::make_temp_dir("cfgweak");
  std::string text = test::read_file(test::default_config());
  text.replace(text.find("max_accel_mm_s2 = 2000.0"), 24, "max_accel_mm_s2 = 30000.0");  // X: 48 N / 2 kg = 24 m/s^2
  const std::string path = dir + "/weak.toml";
  std::ofstream(path) << text;
  std::ostringstream out, err;
  EXPECT_EQ(run_config_check(path, false, out, err), 0) << "a warning, not a refusal";
  EXPECT_TRUE(has(err.str(), "warning: [axis.x] max_accel_mm_s2 30000 mm/s^2 is more than the drive can give (24000"))
      << err.str();
}

// The 5-axis trunnion: the kinematics and one row per rotary joint in each table, in degrees
// (the config holds radians); no note any more that the rt does not drive them.
TEST(ConfigCheck, PrintsTheRotaryJointsAndKinematicsInDegrees) {
  std::ostringstream out, err;
  ASSERT_EQ(run_config_check(test::source_dir() + "/configs/desktop-5axis.toml", false, out, err), 0) << err.str();
  const std::string text = out.str();
  EXPECT_TRUE(has(text, "kinematics   xyzac-trt (A tilts the table, C turns it); tilt pivot (12.5, 12.5, 0) mm, "
                        "rotary pivot (12.5, 12.5, 0) mm")) << text;
  EXPECT_TRUE(has(text, "\n  A     -95 .. 95 (190)       0         180          3600           0.2              0.0003\n"))
      << text;
  EXPECT_TRUE(has(text, "\n  C     continuous            0         360          7200 ")) << text;
  EXPECT_TRUE(has(text, "\n  A     0.002     0.4       5        2          0.01               0.03         ")) << text;
  EXPECT_TRUE(has(text, "\n  A     23.5619   2356.19       0.0781035   800  ")) << "gains per degree again: " << text;
  EXPECT_TRUE(has(text, "\n  C     6.28319   628.319       0.0207112   800  ")) << text;
  EXPECT_FALSE(has(err.str(), "does not drive them")) << "pcnc-rt drives the joints: " << err.str();
  EXPECT_FALSE(has(err.str(), "warning")) << err.str();
  // the 3-axis mill says it has none
  std::ostringstream out3, err3;
  ASSERT_EQ(run_config_check(test::default_config(), false, out3, err3), 0);
  EXPECT_TRUE(has(out3.str(), "kinematics   trivial (X Y Z, no rotary joints)")) << out3.str();
}

}  // namespace
}  // namespace pcnc
