// five_axis_trace.hpp — what the two-process 5-axis tests and bench_ruled_machine share: the
// desktop-5axis config written with a private segment name, and the trace read back with the
// rotary joints' columns (ipc/trace_format.hpp). Header only.
#pragma once

#include <cmath>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "config/config.hpp"
#include "config/joint_map.hpp"
#include "ipc/trace_format.hpp"
#include "subprocess.hpp"
#include "test_paths.hpp"

namespace pcnc::test {

/// configs/desktop-5axis.toml as `dir`/five.toml with the segment test_shm_name(tag).
inline std::string write_five_axis_config(const std::string& dir, const std::string& tag) {
  std::string text = read_file(source_dir() + "/configs/desktop-5axis.toml");
  const std::string from = "shm_name = \"/pcnc-desktop-5axis\"";
  const auto at = text.find(from);
  if (at == std::string::npos) throw std::runtime_error("desktop-5axis.toml: no shm_name line");
  text.replace(at, from.size(), "shm_name = \"" + test_shm_name(tag) + "\"");
  const std::string path = dir + "/five.toml";
  std::ofstream(path) << text;
  return path;
}

/// One trace row with the joints' columns.
struct FiveAxisRow {
  TraceSample s;
  TraceJoints j;
};

/// Every row of a trace written for a machine with the joints in `mask`; its header in `header`.
inline std::vector<FiveAxisRow> read_five_axis_trace(const std::string& path, RotaryMask mask, std::string* header = nullptr) {
  std::ifstream f(path);
  std::string line;
  std::getline(f, line);
  if (header) *header = line;
  std::vector<FiveAxisRow> rows;
  while (std::getline(f, line)) {
    FiveAxisRow r;
    r.j.mask = mask;
    if (!parse_trace_row(line, r.s, &r.j)) throw std::runtime_error("bad trace row: " + line);
    rows.push_back(r);
  }
  return rows;
}

/// The first limit the commanded joints of row i break, or "": a linear axis or a rotary joint
/// with a travel outside it, or a joint faster than its velocity limit (its difference from row
/// i - 1 over one cycle, 0.1 % for rounding in the trace).
inline std::string commanded_joint_violation(const MachineConfig& cfg, const std::vector<FiveAxisRow>& rows, std::size_t i) {
  const Joints q = to_joints(cfg, rows[i].s.commanded, rows[i].j.commanded);
  const std::string row = " at row " + std::to_string(i);
  for (int ax = 0; ax < kAxes; ++ax) {
    const AxisConfig& a = cfg.axes[static_cast<std::size_t>(ax)];
    if (!(q[static_cast<std::size_t>(ax)] >= a.travel_min_mm && q[static_cast<std::size_t>(ax)] <= a.travel_max_mm)) {
      return std::string(1, axis_name(ax)) + " outside its travel" + row;
    }
  }
  const int idx[2] = {tilt_index(cfg), rotary_index(cfg)};
  for (int k = 0; k < 2; ++k) {
    if (idx[k] < 0 || !cfg.rotary[static_cast<std::size_t>(idx[k])]) continue;
    const RotaryAxisConfig& r = *cfg.rotary[static_cast<std::size_t>(idx[k])];
    const double v = q[static_cast<std::size_t>(kTilt + k)];
    if (!r.continuous && !(v >= r.travel_min_rad && v <= r.travel_max_rad)) return std::string(1, joint_letter(idx[k])) + " outside its travel" + row;
  }
  if (i == 0) return "";
  const Joints p = to_joints(cfg, rows[i - 1].s.commanded, rows[i - 1].j.commanded);
  const double dt = cfg.cycle_period_s();
  for (int ax = 0; ax < kAxes; ++ax) {
    const auto k = static_cast<std::size_t>(ax);
    if (std::abs(q[k] - p[k]) / dt > cfg.axes[k].max_velocity_mm_s * 1.001) return std::string(1, axis_name(ax)) + " above its velocity" + row;
  }
  for (int k = 0; k < 2; ++k) {
    if (idx[k] < 0 || !cfg.rotary[static_cast<std::size_t>(idx[k])]) continue;
    const auto j = static_cast<std::size_t>(kTilt + k);
    if (std::abs(q[j] - p[j]) / dt > cfg.rotary[static_cast<std::size_t>(idx[k])]->max_velocity_rad_s * 1.001) {
      return std::string(1, joint_letter(idx[k])) + " above its velocity" + row;
    }
  }
  return "";
}

}  // namespace pcnc::test

