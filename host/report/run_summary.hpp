// run_summary.hpp — the machine-readable end of a run: what pcnc-host writes with
// --summary FILE.json after `pcnc run` (check result, transform, job result, final rt status,
// the machine's travel), so that the launcher can build the HTML report from it and the
// trace once both processes have exited, and scripts can read the figures without parsing
// the terminal report. The JSON holds plain numbers in mm, s, µs; to_json and from_json are
// exact inverses for every field listed here.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "config/config.hpp"
#include "report/run_report.hpp"

namespace pcnc {

struct RunSummary {
  int format = 1;
  std::string program;        // path as given
  std::string machine;        // config name
  std::string config_path;
  std::string clock;          // "real" | "virtual"
  bool contouring_at_start = false;
  double contouring_angle_deg = 0.0;
  double path_tolerance_mm = 0.0;  // the run's path tolerance (config or --tolerance; 0: corners stop, nothing smoothed)
  double cycle_hz = 0.0;
  Vec3 travel_min{}, travel_max{};

  // pass 1 (check_program: the whole pipeline to the blocks)
  std::uint64_t lines = 0;
  std::uint64_t moves = 0;
  std::uint64_t warnings = 0;
  Transform transform{};
  Vec3 min_point{}, max_point{}, last_point{};  // machine coordinates
  double feed_length_time_s = 0.0;
  // smoothing: G1 moves made into curves, the curves, their ring blocks, and the largest
  // measured distance of a curve from the programmed moves (mm)
  std::uint64_t smoothed_moves = 0, smoothed_curves = 0, smoothed_blocks = 0;
  double max_path_deviation_mm = 0.0;
  double smoothing_min_tolerance_mm = 0.0;  // the tolerances the curves were fitted to (0 without curves)
  double smoothing_max_tolerance_mm = 0.0;
  // arc packing: arcs packed into exact curves, the curves, their ring blocks, and the largest
  // measured distance of a curve from its arcs (mm)
  std::uint64_t packed_arcs = 0, packed_curves = 0, packed_blocks = 0;
  double packed_max_deviation_mm = 0.0;
  // source lines that hold a rapid block, from the blocks check made (what the run sent):
  // the report draws those parts of the path as rapids
  std::vector<LineRange> rapid_lines;
  // what caps each block's speed and how its junctions pass (gcode/time_cause.hpp): the
  // launcher attributes the trace's time to these causes
  std::vector<LinePlan> plan;
  // the tool length of the program's TCP blocks (CheckResult::tcp_tool_length_mm): the report's
  // tool-axis view uses it with the config's kinematics; 0 without TCP (and in older summaries)
  double tcp_tool_length_mm = 0.0;
  // cutter radius compensation (G41/G42): what it did, the largest tool diameter, and the
  // programmed contour it offset (machine mm, at most 20000 points: the report's top view)
  std::uint64_t comp_entries = 0, comp_moves_in = 0, comp_moves_out = 0;
  std::uint64_t comp_biarcs = 0, comp_moves_replaced = 0;  // biarc fits: biarcs, programmed moves they replaced
  double comp_tool_diameter_mm = 0.0;
  std::vector<std::vector<Vec3>> comp_contour;

  // the job
  std::string end;            // to_string(JobEnd)
  std::string message;
  std::uint64_t pauses = 0;                 // M0/M1 gone on from without the control socket (pcnc run --pauses)
  std::string pauses_mode;                  // "continue" or "ask" ("" with none)
  std::vector<std::uint32_t> pause_lines;   // their source lines (the first 32)
  std::uint64_t blocks_sent = 0;
  std::uint64_t lines_read = 0;
  double wall_time_s = 0.0;
  std::uint64_t refill_count = 0;
  double refill_p50_us = 0.0, refill_p99_us = 0.0, refill_max_us = 0.0;

  Status final_status{};      // the rt's status at the end

  // Where the machine time went: cause key (time_cause_key) -> seconds, adding up to
  // final_status.program_time_s. Filled after the run from the trace and `plan`
  // (report/time_causes.hpp); empty when there was no trace.
  std::map<std::string, double> time_by_cause;
};

RunSummary make_run_summary(const RunReport& report, const MachineConfig& config, const std::string& config_path,
                            bool contouring_at_start);

nlohmann::json to_json(const RunSummary& s);
/// The same without the plan's entries when `with_plan` is false (its text left empty).
nlohmann::json to_json(const RunSummary& s, bool with_plan);
/// Throws nlohmann::json::exception (or std::runtime_error) on a missing or mistyped field.
RunSummary run_summary_from_json(const nlohmann::json& j);

/// Writes the JSON to `path` (pretty-printed). Throws std::runtime_error when it cannot.
void write_run_summary(const RunSummary& s, const std::string& path);
RunSummary read_run_summary(const std::string& path);

/// RMS following error per axis over the program's cycles, mm.
Vec3 rms_following_error(const Status& s);
/// RMS contour error over the program's cycles, mm.
double rms_contour_error(const Status& s);

}  // namespace pcnc
