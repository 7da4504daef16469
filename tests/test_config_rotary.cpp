// test_config_rotary.cpp — the rotary joints ([axis.a], [axis.b], [axis.c]) and [kinematics] in
// the machine config: configs/desktop-5axis.toml as understood (degrees in the file, radians
// inside; its gains follow the pole-placement rule of docs/servo-tuning.md, recomputed here from
// its plant values), the 3-axis configs unchanged (no rotary joint, trivial kinematics), and the
// same strictness as the linear sections on variants generated from the 5-axis text: every
// rotary key deleted, misspelt and set out of range in turn, and the rules between sections.
#include <gtest/gtest.h>

#include <cmath>
#include <regex>
#include <string>
#include <vector>

#include "config/config.hpp"
#include "config_text.hpp"
#include "subprocess.hpp"
#include "test_paths.hpp"
#include "test_constants.hpp"
#include "text_lines.hpp"

namespace pcnc {
namespace {

const std::string kRotaryOrigin = "five.toml";

std::string five_text() { return test::read_file(test::source_dir() + "/configs/desktop-5axis.toml"); }

std::string rotary_refusal(const std::string& text) {
  try {
    parse_config(text, kRotaryOrigin);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

using test::has;

std::string rotary_with(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  if (at == std::string::npos) throw std::runtime_error("'" + from + "' not in the text");
  return text.replace(at, from.size(), to);
}

using test::KeyLine;

// The key lines of the rotary sections and [kinematics].
std::vector<KeyLine> rotary_keys(const std::string& text) {
  std::vector<KeyLine> keys;
  for (const KeyLine& k : test::key_lines(text)) {
    if (k.section == "axis.a" || k.section == "axis.c" || k.section == "kinematics") keys.push_back(k);
  }
  return keys;
}

TEST(ConfigRotary, ThreeAxisConfigsHaveNoRotaryJoints) {
  for (const char* name : {"desktop-mill.toml", "bench-peers.toml"}) {
    const MachineConfig c = load_config(test::source_dir() + "/configs/" + name);
    for (const auto& r : c.rotary) EXPECT_FALSE(r.has_value()) << name;
    EXPECT_EQ(c.kinematics.kind, KinematicsKind::kTrivial) << name;
    EXPECT_EQ(c.tilt_joint(), nullptr);
    EXPECT_EQ(c.rotary_joint(), nullptr);
    EXPECT_TRUE(std::isinf(c.rotary_travel().tilt_max));
  }
}

TEST(ConfigRotary, FiveAxisTrunnionAsUnderstoodInRadians) {
  const MachineConfig c = load_config(test::source_dir() + "/configs/desktop-5axis.toml");
  EXPECT_EQ(c.name, "desktop-5axis");
  EXPECT_EQ(c.kinematics.kind, KinematicsKind::kTableTable);
  EXPECT_EQ(c.kinematics.tilt_pivot, (Vec3{12.5, 12.5, 0.0}));
  EXPECT_EQ(c.kinematics.rotary_pivot, (Vec3{12.5, 12.5, 0.0}));
  ASSERT_TRUE(c.rotary[0] && c.rotary[2]);
  EXPECT_FALSE(c.rotary[1]);
  const RotaryAxisConfig& a = *c.rotary[0];
  const RotaryAxisConfig& cc = *c.rotary[2];
  EXPECT_EQ(a.letter, 'A');
  EXPECT_EQ(cc.letter, 'C');
  EXPECT_FALSE(a.continuous);
  EXPECT_TRUE(cc.continuous);
  EXPECT_NEAR(a.travel_min_rad, -95.0 * kPi / 180.0, 1e-12);
  EXPECT_NEAR(a.travel_max_rad, 95.0 * kPi / 180.0, 1e-12);
  EXPECT_LE(a.travel_min_rad, -kPi / 2);  // A reaches at least -90 .. +90 deg (issue 16)
  EXPECT_GE(a.travel_max_rad, kPi / 2);
  EXPECT_NEAR(a.max_velocity_rad_s, kPi, 1e-12);          // 180 deg/s
  EXPECT_NEAR(cc.max_accel_rad_s2, 40.0 * kPi, 1e-12);    // 7200 deg/s^2
  EXPECT_NEAR(a.encoder_resolution_rad, 0.0003 * kPi / 180.0, 1e-18);
  EXPECT_EQ(c.tilt_joint(), &a);
  EXPECT_EQ(c.rotary_joint(), &cc);
  const RotaryTravel t = c.rotary_travel();
  EXPECT_DOUBLE_EQ(t.tilt_min, a.travel_min_rad);
  EXPECT_DOUBLE_EQ(t.tilt_max, a.travel_max_rad);
  EXPECT_TRUE(std::isinf(t.rotary_min) && std::isinf(t.rotary_max)) << "C is continuous";
  // X Y Z are the desktop mill's
  const MachineConfig mill = load_config(test::default_config());
  for (int i = 0; i < kAxes; ++i) {
    EXPECT_EQ(c.axes[i].travel_max_mm, mill.axes[i].travel_max_mm);
    EXPECT_EQ(c.axes[i].kp_a_per_mm, mill.axes[i].kp_a_per_mm);
  }
  EXPECT_NE(c.process.shm_name, mill.process.shm_name) << "both machines may run at once";
}

// docs/servo-tuning.md: three poles at -300 rad/s on J s^3 + (Kt kd + b) s^2 + Kt kp s + Kt ki,
// feed-forward J/Kt, b/Kt and 80 % of the Coulomb friction, all per radian inside.
TEST(ConfigRotary, GainsFollowThePolePlacementRule) {
  const MachineConfig c = load_config(test::source_dir() + "/configs/desktop-5axis.toml");
  const double w = 300.0;
  for (const auto& r : c.rotary) {
    if (!r) continue;
    const double J = r->inertia_kg_m2, kt = r->torque_constant_nm_per_a, b = r->viscous_friction_nm_s_per_rad;
    EXPECT_NEAR(r->kp_a_per_rad, 3 * w * w * J / kt, 1e-5 * r->kp_a_per_rad) << r->letter;
    EXPECT_NEAR(r->ki_a_per_rad_s, w * w * w * J / kt, 1e-5 * r->ki_a_per_rad_s) << r->letter;
    EXPECT_NEAR(r->kd_a_s_per_rad, (3 * w * J - b) / kt, 1e-5 * r->kd_a_s_per_rad) << r->letter;
    EXPECT_NEAR(r->accel_ff_a_s2_per_rad, J / kt, 1e-5 * J / kt) << r->letter;
    EXPECT_NEAR(r->velocity_ff_a_s_per_rad, b / kt, 1e-5 * b / kt) << r->letter;
    EXPECT_NEAR(r->friction_ff_a, 0.8 * r->coulomb_friction_nm / kt, 1e-6) << r->letter;
    // the acceleration limit is at most a tenth of what the motor gives the inertia
    EXPECT_LE(r->max_accel_rad_s2, 0.1 * kt * r->current_limit_a / J) << r->letter;
  }
}

TEST(ConfigRotary, EachRotaryKeyDeletedIsRefusedNamingIt) {
  const std::string text = five_text();
  const auto lines = test::config_lines(text);
  const auto keys = rotary_keys(text);
  ASSERT_GE(keys.size(), 40u);
  for (const KeyLine& k : keys) {
    std::vector<std::string> variant = lines;
    variant.erase(variant.begin() + k.line - 1);
    const std::string message = rotary_refusal(test::join_config_lines(variant));
    ASSERT_FALSE(message.empty()) << "deleting " << k.section << "." << k.key << " must be refused";
    if (k.key == "continuous" || k.key == "kind") {
      // C without `continuous` needs its travel; without `kind` the machine is trivial and A, C
      // are no joints of it
      EXPECT_TRUE(has(message, k.key == "kind" ? "is not a joint of the trivial kinematics"
                                               : "[axis.c]: missing key 'travel_min_deg' (deg)"))
          << message;
      continue;
    }
    EXPECT_TRUE(has(message, kRotaryOrigin + ":" + std::to_string(k.section_line) + ":1: [" + k.section +
                                 "]: missing key '" + k.key + "'"))
        << message;
  }
}

TEST(ConfigRotary, EachRotaryKeyMisspeltIsRefusedWithLineAndColumn) {
  const std::string text = five_text();
  const auto lines = test::config_lines(text);
  for (const KeyLine& k : rotary_keys(text)) {
    std::vector<std::string> variant = lines;
    const std::string typo = k.key + k.key.substr(k.key.size() - 1);
    variant[static_cast<std::size_t>(k.line - 1)].replace(0, k.key.size(), typo);
    const std::string message = rotary_refusal(test::join_config_lines(variant));
    EXPECT_TRUE(has(message, kRotaryOrigin + ":" + std::to_string(k.line) + ":1: [" + k.section + "]: unknown key '" + typo +
                                 "' (did you mean '" + k.key + "'?)"))
        << message;
  }
}

// The unit each rotary key's message must show, from its name.
std::string rotary_unit(const std::string& key) {
  static const std::vector<std::pair<std::string, std::string>> suffixes = {
      {"_deg_s2", "deg/s^2"}, {"_deg_s", "deg/s"}, {"_a_per_deg_s", "A/(deg s)"}, {"_a_per_deg", "A/deg"},
      {"_a_s_per_deg", "A s/deg"}, {"_a_s2_per_deg", "A s^2/deg"}, {"_kg_m2", "kg m^2"}, {"_nm_per_a", "N m/A"},
      {"_nm_s_per_rad", "N m s/rad"}, {"_nm", "N m"}, {"_deg", "deg"}, {"_hz", "Hz"}, {"_a", "A"}};
  std::string best, unit;
  for (const auto& [suffix, u] : suffixes) {
    if (suffix.size() > best.size() && key.size() > suffix.size() &&
        key.compare(key.size() - suffix.size(), suffix.size(), suffix) == 0) {
      best = suffix;
      unit = u;
    }
  }
  return unit;
}

TEST(ConfigRotary, EachRotaryNumberOutOfRangeIsRefusedWithItsUnit) {
  const std::string text = five_text();
  const auto lines = test::config_lines(text);
  int checked = 0;
  for (const KeyLine& k : rotary_keys(text)) {
    if (k.value.find_first_not_of("0123456789.-e") != std::string::npos || k.value.find('.') == std::string::npos) continue;
    std::vector<std::string> variant = lines;
    std::string& line = variant[static_cast<std::size_t>(k.line - 1)];
    const std::size_t at = line.find(k.value, k.key.size());
    line.replace(at, k.value.size(), "-1e9");
    const std::string message = rotary_refusal(test::join_config_lines(variant));
    const std::string unit = rotary_unit(k.key);
    ASSERT_FALSE(unit.empty()) << k.key;
    EXPECT_TRUE(has(message, kRotaryOrigin + ":" + std::to_string(k.line) + ":" + std::to_string(at + 1) + ": [" + k.section +
                                 "] " + k.key + " = -1e+09 " + unit + ": out of range, must be "))
        << message;
    EXPECT_TRUE(message.ends_with(" " + unit)) << message;
    ++checked;
  }
  EXPECT_GE(checked, 35);
}

TEST(ConfigRotary, RulesBetweenKeysAndSections) {
  const std::string t = five_text();
  // a continuous axis has no travel
  EXPECT_TRUE(has(rotary_refusal(rotary_with(t, "continuous = true\n", "continuous = true\ntravel_min_deg = 0.0\n")),
                  "[axis.c]: a continuous axis has no travel limits"));
  EXPECT_TRUE(has(rotary_refusal(rotary_with(t, "travel_max_deg = 95.0", "travel_max_deg = -100.0")),
                  "[axis.a]: travel_max_deg (-100 deg) must exceed travel_min_deg (-95 deg)"));
  EXPECT_TRUE(has(rotary_refusal(rotary_with(t, "home_deg = 0.0", "home_deg = 100.0")),
                  "[axis.a]: home_deg (100 deg) must lie within the travel, -95 .. 95 deg"));
  // C limited instead of continuous: accepted, and its travel reaches the inverse kinematics
  const MachineConfig limited =
      parse_config(rotary_with(t, "continuous = true\n", "travel_min_deg = -200.0\ntravel_max_deg = 200.0\n"), kRotaryOrigin);
  EXPECT_NEAR(limited.rotary_travel().rotary_max, 200.0 * kPi / 180.0, 1e-12);
  // kinematics and joints must agree
  EXPECT_TRUE(has(rotary_refusal(rotary_with(t, "kind = \"xyzac-trt\"", "kind = \"xyzac\"")),
                  "[kinematics]: kind 'xyzac' is not a kinematics pcnc has"));
  EXPECT_TRUE(has(rotary_refusal(rotary_with(t, "kind = \"xyzac-trt\"", "kind = \"xyzbc-head-table\"")),
                  "missing section [axis.b]: [kinematics] kind = \"xyzbc-head-table\" needs it"));
  EXPECT_TRUE(has(rotary_refusal(rotary_with(t, "kind = \"xyzac-trt\"", "kind = \"xyzbc-head-table\"")),
                  "[axis.a] is not a joint of [kinematics] kind = \"xyzbc-head-table\""));
  EXPECT_TRUE(has(rotary_refusal(rotary_with(t, "[axis.a]", "[axis.b]")), "missing section [axis.a]"));
  EXPECT_TRUE(has(rotary_refusal(rotary_with(t, "tilt_pivot_mm = [12.5, 12.5, 0.0]\n", "")),
                  "[kinematics]: missing key 'tilt_pivot_mm'"));
  EXPECT_TRUE(has(rotary_refusal(rotary_with(t, "kind = \"xyzac-trt\"", "kind = \"trivial\"")),
                  "[kinematics]: the trivial kinematics has no pivots"));
  EXPECT_TRUE(has(rotary_refusal(rotary_with(t, "rotary_pivot_mm = [12.5, 12.5, 0.0]", "rotary_pivot_mm = [12.5, 12.5]")),
                  "[kinematics] rotary_pivot_mm: expected an array of 3 numbers"));
  EXPECT_TRUE(has(rotary_refusal(rotary_with(t, "continuous = true", "continuous = 1")), "continuous: expected true or false"));
  // a 3-axis config with a rotary joint and no kinematics
  const std::string mill = test::read_file(test::default_config());
  const std::string a_section = t.substr(t.find("[axis.a]"), t.find("# C: the 60 mm") - t.find("[axis.a]"));
  EXPECT_TRUE(has(rotary_refusal(mill + "\n" + a_section),
                  "[axis.a] is not a joint of the trivial kinematics (no [kinematics] kind)"));
  // A and C alone, with the same text, pass when the kinematics names them
  EXPECT_EQ(rotary_refusal(t), "");
}

}  // namespace
}  // namespace pcnc
