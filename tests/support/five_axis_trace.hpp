// five_axis_trace.hpp — what the two-process 5-axis tests and bench_ruled_machine share: the
// desktop-5axis config written with a private segment name, and the trace read back with the
// rotary joints' columns (ipc/trace_format.hpp). Header only.
#pragma once

#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

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

}  // namespace pcnc::test
