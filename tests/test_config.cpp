// test_config.cpp — the machine config loader's strictness, on variants generated from the
// shipped config text: every section deleted in turn, every key deleted, misspelt and set
// out of range in turn; each refusal must name the file, the section, the key, the line and
// (for a value) its unit. The shipped configs themselves must pass.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <regex>
#include <set>
#include <string>
#include <vector>

#include "config/config.hpp"
#include "config_text.hpp"
#include "subprocess.hpp"
#include "test_paths.hpp"
#include "text_lines.hpp"

namespace pcnc {
namespace {

const std::string kOrigin = "variant.toml";

// The keys a config may leave out (docs/configuration.md lists their defaults).
const std::set<std::string> kOptionalKeys = {
    "path_tolerance_mm", "smoothing_angle_deg", "rapid_speed_mm_s", "max_feed_mm_min", "g55", "g56",
    "g57",                 "g58",              "g59",             "nurbs_knots",  "nurbs_chord_tolerance_mm",
    "socket_path",         "socket_mode",      "socket_group",    "state_dir",    "client_idle_timeout_s",
    "rt_priority",         "rt_spin_us",       "on_trace_failure", "max_executed_lines", "tool_table",
    "pause_on_tool_change"};

using test::KeyLine;
using test::key_lines;

std::string shipped_text() { return test::read_file(test::default_config()); }

// The refusal's message, or "" when the text was accepted.
std::string config_refusal(const std::string& text) {
  try {
    parse_config(text, kOrigin);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

using test::has;

// The generated variants, from each shipped config's text.
class ShippedConfig : public ::testing::TestWithParam<std::string> {
 protected:
  std::string text() const { return test::read_file(test::source_dir() + "/configs/" + GetParam()); }
};
INSTANTIATE_TEST_SUITE_P(Configs, ShippedConfig, ::testing::Values("desktop-mill.toml", "bench-peers.toml"),
                         [](const auto& info) { return info.param.substr(0, info.param.find('-')); });

TEST(Config, ShippedConfigsPass) {
  int checked = 0;
  for (const auto& entry : std::filesystem::directory_iterator(test::source_dir() + "/configs")) {
    if (entry.path().extension() != ".toml") continue;
    EXPECT_NO_THROW(load_config(entry.path().string())) << entry.path();
    ++checked;
  }
  EXPECT_GE(checked, 2);
  EXPECT_GE(key_lines(shipped_text()).size(), 80u) << "the test sees the shipped keys";
}

TEST(Config, DefaultConfigLoadsWithItsTravel) {
  const MachineConfig c = load_config(test::default_config());
  for (int i = 0; i < kAxes; ++i) {
    EXPECT_LT(c.axes[i].travel_min_mm, c.axes[i].travel_max_mm);
    EXPECT_NEAR(c.axes[i].travel_max_mm - c.axes[i].travel_min_mm, 25.0, 5.0) << "about 25 mm of travel";
    EXPECT_GT(c.axes[i].max_velocity_mm_s, 0.0);
  }
  EXPECT_DOUBLE_EQ(c.motion.cycle_hz, 2000.0);
  EXPECT_DOUBLE_EQ(c.motion.contouring_angle_deg, 10.0);
  EXPECT_EQ(c.process.socket_mode, 0600);
}

TEST_P(ShippedConfig, EachSectionDeletedIsRefusedNamingFileSectionAndKeys) {
  const auto lines = test::config_lines(text());
  std::vector<std::pair<std::size_t, std::string>> headers;  // index, name
  const std::regex header(R"(^\[([a-z._]+)\])");
  for (std::size_t i = 0; i < lines.size(); ++i) {
    std::smatch m;
    if (std::regex_search(lines[i], m, header)) headers.emplace_back(i, m[1]);
  }
  // [probe] and [workpiece] are optional sections: a machine without a probe (docs/probe.md)
  const std::set<std::string> optional_sections = {"probe", "workpiece"};
  std::size_t required_sections = 0;
  for (const auto& [at, name] : headers) required_sections += optional_sections.count(name) ? 0 : 1;
  ASSERT_EQ(required_sections, 6u) << "motion, gcode, process, axis.x, axis.y, axis.z";
  const auto keys = key_lines(text());
  for (std::size_t h = 0; h < headers.size(); ++h) {
    const std::size_t end = h + 1 < headers.size() ? headers[h + 1].first : lines.size();
    std::vector<std::string> variant(lines.begin(), lines.begin() + static_cast<long>(headers[h].first));
    variant.insert(variant.end(), lines.begin() + static_cast<long>(end), lines.end());
    const std::string name = headers[h].second;
    const std::string message = config_refusal(test::join_config_lines(variant));
    if (optional_sections.count(name)) {
      EXPECT_EQ(message, "") << "[" << name << "] is optional";
      continue;
    }
    ASSERT_FALSE(message.empty()) << "deleting [" << name << "] must be refused, not defaulted";
    EXPECT_TRUE(has(message, kOrigin + ": missing section [" + name + "]")) << message;
    for (const KeyLine& k : keys) {
      if (k.section == name && !kOptionalKeys.count(k.key)) {
        EXPECT_TRUE(has(message, k.key)) << k.key << ": " << message;
      }
    }
  }
}

TEST_P(ShippedConfig, EachKeyDeletedIsRefusedUnlessOptional) {
  const auto lines = test::config_lines(text());
  int required = 0;
  for (const KeyLine& k : key_lines(text())) {
    std::vector<std::string> variant = lines;
    variant.erase(variant.begin() + k.line - 1);
    const std::string message = config_refusal(test::join_config_lines(variant));
    if (kOptionalKeys.count(k.key)) {
      EXPECT_EQ(message, "") << k.key << " is optional";
      continue;
    }
    ++required;
    ASSERT_FALSE(message.empty()) << "deleting " << k.section << "." << k.key << " must be refused";
    const std::string section = k.section.empty() ? "(top level)" : "[" + k.section + "]";
    // a section's missing key: at the section's header; a top-level one: the file
    const std::string where = k.section.empty() ? kOrigin + ": " : kOrigin + ":" + std::to_string(k.section_line) + ":1: ";
    EXPECT_TRUE(has(message, where + section + ": missing key '" + k.key + "'")) << message;
  }
  EXPECT_GE(required, 70);
}

TEST_P(ShippedConfig, EachKeyMisspeltIsRefusedWithFileLineAndColumn) {
  const auto lines = test::config_lines(text());
  for (const KeyLine& k : key_lines(text())) {
    std::vector<std::string> variant = lines;
    const std::string typo = k.key + k.key.substr(k.key.size() - 1);  // last letter doubled
    variant[static_cast<std::size_t>(k.line - 1)].replace(0, k.key.size(), typo);
    const std::string message = config_refusal(test::join_config_lines(variant));
    const std::string section = k.section.empty() ? "(top level)" : "[" + k.section + "]";
    EXPECT_TRUE(has(message, kOrigin + ":" + std::to_string(k.line) + ":1: " + section + ": unknown key '" + typo + "'"))
        << k.key << ": " << message;
    EXPECT_TRUE(has(message, "did you mean '" + k.key + "'")) << message;
  }
}

// The unit the message must show for a key, from the unit its name ends in (the longest
// matching suffix); "" for the few keys whose name carries no unit (fractions, counts).
std::string unit_of(const std::string& key) {
  static const std::vector<std::pair<std::string, std::string>> suffixes = {
      {"_mm_s2", "mm/s^2"}, {"_mm_s", "mm/s"}, {"_mm_min", "mm/min"}, {"_n_per_a", "N/A"}, {"_n_s_per_m", "N s/m"},
      {"_a_per_mm_s", "A/(mm s)"}, {"_a_per_mm", "A/mm"}, {"_a_s_per_mm", "A s/mm"}, {"_a_s2_per_mm", "A s^2/mm"},
      {"_mm", "mm"}, {"_hz", "Hz"}, {"_kg", "kg"}, {"_deg", "deg"}, {"_us", "us"}, {"_s", "s"}, {"_n", "N"}, {"_a", "A"}};
  std::string best, unit_found;
  for (const auto& [suffix, unit] : suffixes) {
    if (suffix.size() > best.size() && key.size() > suffix.size() &&
        key.compare(key.size() - suffix.size(), suffix.size(), suffix) == 0) {
      best = suffix;
      unit_found = unit;
    }
  }
  return unit_found;
}

TEST_P(ShippedConfig, EachNumberOutOfRangeIsRefusedWithItsUnitAndPosition) {
  const auto lines = test::config_lines(text());
  int checked = 0;
  for (const KeyLine& k : key_lines(text())) {
    // floating-point numbers only (integers, booleans, strings and arrays have their own tests)
    if (k.value.find_first_not_of("0123456789.-e") != std::string::npos || k.value.find('.') == std::string::npos) continue;
    std::vector<std::string> variant = lines;
    std::string& line = variant[static_cast<std::size_t>(k.line - 1)];
    const std::size_t at = line.find(k.value, k.key.size());
    line.replace(at, k.value.size(), "-1e9");
    const std::string message = config_refusal(test::join_config_lines(variant));
    const std::string section = k.section.empty() ? "(top level)" : "[" + k.section + "]";
    const std::string unit = unit_of(k.key);
    const std::string value = "-1e+09" + (unit.empty() ? "" : " " + unit + ": out of range, must be ");
    EXPECT_TRUE(has(message, kOrigin + ":" + std::to_string(k.line) + ":" + std::to_string(at + 1) + ": " + section + " " +
                                 k.key + " = " + value))
        << k.key << ": " << message;
    EXPECT_TRUE(has(message, "out of range, must be ")) << message;
    if (!unit.empty()) {
      EXPECT_TRUE(message.ends_with(" " + unit)) << "the range has the unit too: " << message;
    }
    ++checked;
  }
  EXPECT_GE(checked, 70);
}

std::string config_with(const std::string& from, const std::string& to) {
  std::string text = shipped_text();
  const auto at = text.find(from);
  if (at == std::string::npos) throw std::runtime_error("'" + from + "' not in the shipped config");
  return text.replace(at, from.size(), to);
}

TEST(Config, WrongTypesAndRulesBetweenKeysAreRefused) {
  EXPECT_TRUE(has(config_refusal(config_with("cycle_hz = 2000.0", "cycle_hz = \"fast\"")),
                  "[motion] cycle_hz: expected a number (Hz), not a string"));
  const std::string text = shipped_text();
  const auto travel_line = 1 + std::count(text.begin(), text.begin() + static_cast<long>(text.find("travel_max_mm = 25.0")), '\n');
  EXPECT_TRUE(has(config_refusal(config_with("travel_max_mm = 25.0", "travel_max_mm = -5.0")),
                  kOrigin + ":" + std::to_string(travel_line) +
                      ":17: [axis.x]: travel_max_mm (-5 mm) must exceed travel_min_mm (0 mm)"))
      << "at the value";
  EXPECT_TRUE(has(config_refusal(config_with("home_mm = 25.0", "home_mm = 26.0")), "[axis.z]: home_mm (26 mm) must lie within the travel"));
  EXPECT_TRUE(has(config_refusal(config_with("shm_name = \"/pcnc-desktop-mill\"", "shm_name = \"no-slash\"")), "[process]: shm_name"));
  EXPECT_TRUE(has(config_refusal(config_with("contouring_default = false", "contouring_default = 0")),
                  "contouring_default: expected true or false, not an integer"));
  EXPECT_TRUE(has(config_refusal(config_with("g54 = [12.5, 12.5, 25.0]", "g54 = [12.5, 12.5]")), "[gcode] g54: expected an array of 3"));
  const std::string syntax = config_refusal(config_with("[motion]", "[motion"));
  EXPECT_TRUE(has(syntax, kOrigin + ":8:")) << "a TOML syntax error names its line: " << syntax;
  EXPECT_TRUE(has(config_refusal(config_with("[axis.z]", "[axis.w]")), "unknown section [axis.w]"));
  EXPECT_TRUE(has(config_refusal(config_with("name = \"desktop-mill\"", "name = \"../mill\"")), "(top level): name '../mill' must name"));
  EXPECT_TRUE(config_refusal(config_with("rt_spin_us = 0.0", "rt_spin_us = 200.0")).empty());
}

TEST(Config, EveryProblemIsReportedAtOnce) {
  std::string text = config_with("cycle_hz = 2000.0", "cyle_hz = 2000.0");
  text.replace(text.find("kp_a_per_mm = 45.0"), 18, "kp_a_per_mm = -45.0");
  try {
    parse_config(text, kOrigin);
    FAIL() << "refused";
  } catch (const ConfigError& e) {
    ASSERT_EQ(e.problems.size(), 3u) << e.what();  // cycle_hz missing, cyle_hz unknown, kp out of range
    EXPECT_TRUE(has(e.what(), "missing key 'cycle_hz' (Hz)")) << e.what();
    EXPECT_TRUE(has(e.what(), "unknown key 'cyle_hz' (did you mean 'cycle_hz'?)")) << e.what();
    EXPECT_TRUE(has(e.what(), "kp_a_per_mm = -45 A/mm: out of range, must be 0 .. 1e+09 A/mm")) << e.what();
    EXPECT_TRUE(has(e.problems[0], "cycle_hz") && has(e.problems[2], "kp_a_per_mm")) << "in the file's order: " << e.what();
  }
}

TEST(Config, OnTraceFailureIsStopOrContinueAndStopByDefault) {
  const std::string line = "on_trace_failure = \"stop\"";
  EXPECT_TRUE(load_config(test::default_config()).process.trace_failure_stops);
  EXPECT_TRUE(parse_config(config_with(line, ""), "t").process.trace_failure_stops) << "optional: stop";
  EXPECT_FALSE(parse_config(config_with(line, "on_trace_failure = \"continue\""), "t").process.trace_failure_stops);
  EXPECT_THROW(parse_config(config_with(line, "on_trace_failure = \"pause\""), "t"), ConfigError);
  EXPECT_THROW(parse_config(config_with(line, "on_trace_failure = true"), "t"), ConfigError);
}

// Issue 14: corner_tolerance_mm became path_tolerance_mm; the old name is refused naming the new.
TEST(Config, TheOldCornerToleranceIsRefusedNamingThePathTolerance) {
  std::string text = shipped_text();
  const std::string key = "path_tolerance_mm = 0.005";
  ASSERT_NE(text.find(key), std::string::npos);
  text.replace(text.find(key), key.size(), "corner_tolerance_mm = 0.005");
  const std::string message = config_refusal(text);
  EXPECT_TRUE(has(message, "corner_tolerance_mm: renamed to path_tolerance_mm")) << message;
  EXPECT_EQ(parse_config(shipped_text(), kOrigin).motion.path_tolerance_mm, 0.005);
}

TEST(Config, AMissingFileIsNamed) {
  try {
    load_config("/nonexistent/machine.toml");
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_TRUE(has(e.what(), "/nonexistent/machine.toml")) << e.what();
  }
}

}  // namespace
}  // namespace pcnc
