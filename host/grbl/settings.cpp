// settings.cpp — the config as grbl settings (see settings.hpp).
#include "grbl/settings.hpp"

#include <charconv>
#include <cmath>
#include <cstdio>

#include "grbl/error_codes.hpp"

namespace pcnc::grbl {

std::vector<Setting> settings_for(const MachineConfig& c) {
  const auto& a = c.axes;
  std::vector<Setting> s = {
      {0, 10, 0},   // step pulse, µs (no steppers: grbl's default)
      {1, 25, 0},   // step idle delay
      {2, 0, 0},    {3, 0, 0}, {4, 0, 0}, {5, 0, 0}, {6, 0, 0},
      {10, 1, 0},   // status report: MPos
      {11, c.motion.path_tolerance_mm, 3},    // junction deviation: pcnc's path tolerance
      {12, c.gcode.arc_radius_tolerance_mm, 3},
      {13, 0, 0},   // report in mm
      {20, 1, 0},   // soft limits: always (the preflight and the rt)
      {21, 0, 0},   // hard limits: no switches on the simulated mill
      {22, 1, 0},   // homing: $H moves to the config's home position
      {23, 0, 0},   {24, 25, 3}, {25, 500, 3}, {26, 250, 0}, {27, 1, 3},
      {30, 1000, 0}, {31, 0, 0}, {32, 0, 0},
  };
  for (int i = 0; i < 3; ++i) {
    const double res = a[static_cast<std::size_t>(i)].encoder_resolution_mm;
    s.push_back({100 + i, res > 0 ? 1.0 / res : 0.0, 3});  // counts per mm of the encoder
  }
  for (int i = 0; i < 3; ++i) s.push_back({110 + i, a[static_cast<std::size_t>(i)].max_velocity_mm_s * 60.0, 3});
  for (int i = 0; i < 3; ++i) s.push_back({120 + i, a[static_cast<std::size_t>(i)].max_accel_mm_s2, 3});
  for (int i = 0; i < 3; ++i) {
    const auto& ax = a[static_cast<std::size_t>(i)];
    s.push_back({130 + i, ax.travel_max_mm - ax.travel_min_mm, 3});
  }
  return s;
}

std::string format_setting(const Setting& s) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "$%d=%.*f", s.number, s.decimals, s.value);
  return buf;
}

int write_setting(const std::vector<Setting>& settings, std::string_view text) {
  const auto eq = text.find('=');
  if (eq == std::string_view::npos || eq == 0) return kInvalidStatement;
  int number = 0;
  const auto key = text.substr(0, eq);
  if (auto r = std::from_chars(key.data(), key.data() + key.size(), number); r.ec != std::errc() || r.ptr != key.data() + key.size())
    return kInvalidStatement;
  const auto val = text.substr(eq + 1);
  double value = 0.0;
  if (auto r = std::from_chars(val.data(), val.data() + val.size(), value); r.ec != std::errc() || r.ptr != val.data() + val.size())
    return kBadNumberFormat;
  for (const Setting& s : settings) {
    if (s.number != number) continue;
    if (value < 0.0) return kNegativeValue;
    // what grbl would print for the setting: the same value within its decimals
    return std::abs(value - s.value) <= 0.5 * std::pow(10.0, -s.decimals) ? 0 : kSettingDisabled;
  }
  return kInvalidStatement;
}

}  // namespace pcnc::grbl
