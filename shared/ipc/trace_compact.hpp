// trace_compact.hpp — the compact trace: what the run report reads from a run, kept by the
// rt's trace writer thread instead of the full per-cycle CSV (pcnc-rt --trace-digest), and
// its file format (docs/replay.md, "The compact trace"). Part of the contract between pcnc-rt
// (which builds and writes it) and the host's report (which reads it, report/trace_compact_reader).
//
// The report's digest (report/trace_reader.hpp) needs the program's window of rows (from the
// first RUNNING row to the last busy one), per time slice the minimum and maximum of each
// plotted value, each row's cause (which needs the check's plan, unknown to the rt) and the
// tool path decimated for the views. The builder keeps, from rows rounded as the CSV rounds
// them (so that a report from either form reads the same numbers):
//   - runs: maximal stretches of consecutive window rows with the same line, state and path
//     speed within one time slice: what the host needs to give every row its cause, its
//     feed/rapid class and planned speed, exactly as it would from the CSV;
//   - slices: per time slice (0.5 ms, doubling while there are more than kMaxSlices) the
//     first and last time, the rows, the minimum and maximum speed, following error and line;
//   - the tool path: a row is kept when it lies at least the path tolerance (1 µm, doubling
//     past kMaxPoints) from the last kept one, in single precision; the host decimates this
//     path again (its last point is the window's last row, exact);
//   - the counts, maxima and the last row of the window;
//   - on a machine with rotary joints (TraceFiles::rotary, CompactTotals::rotary_mask != 0)
//     a joint section after the points: per slice the min and max of each joint's following
//     error over the slice's busy rows (degrees, rounded as the CSV), and the commanded
//     position and joints decimated (a row is kept when it lies 1 µm from the last kept one or
//     a joint turned 0.001° from it, both doubling past kMaxPoints; the window's last busy row
//     is kept) for the report's tool-axis view. A 3-axis machine's file is unchanged.
// Pure: the caller hands rows in and takes records out (runs as they complete, through a
// callback, so memory stays bounded by the slices and the path, not the program's length).
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <type_traits>
#include <vector>

#include "geometry/vec3.hpp"
#include "ipc/trace_format.hpp"

namespace pcnc {

/// Consecutive window rows with the same line, state and speed, in one time slice.
struct CompactRun {
  double t = 0.0;               // program time of its first row, s (CSV-rounded time minus the start)
  std::int64_t speed_e5 = 0;    // path speed in units of 1e-5 mm/s (the CSV's resolution)
  std::uint32_t line = 0;
  std::uint32_t count_state = 0;  // rows in bits 0-27, MachineState in bits 28-31
  std::uint32_t count() const { return count_state & 0x0fffffffu; }
  MachineState state() const { return static_cast<MachineState>(count_state >> 28); }
};
static_assert(std::is_trivially_copyable_v<CompactRun> && sizeof(CompactRun) == 24);

/// One time slice: min and max over its rows (program time; same index rule as the report's buckets).
struct CompactSlice {
  double t0 = 0.0, t1 = 0.0;  // first and last row
  double speed_min = 0.0, speed_max = 0.0;
  Vec3 ferr_min{}, ferr_max{};
  std::uint32_t rows = 0, line_min = 0, line_max = 0, reserved = 0;
};
static_assert(std::is_trivially_copyable_v<CompactSlice>);

/// A kept point of the tool path (measured position) for the views: 40 bytes, so that the rt
/// can keep enough of them. Time as the CSV holds it; position, speed and following error in
/// single precision (on a 25 mm travel a float resolves 2 nm, far below the views' 0.5 µm).
struct CompactPoint {
  double t = 0.0;  // program time, s
  float actual[3] = {0, 0, 0};  // mm
  float ferr[3] = {0, 0, 0};    // mm
  float speed = 0.0f;           // mm/s
  std::uint32_t line = 0;
};
static_assert(std::is_trivially_copyable_v<CompactPoint> && sizeof(CompactPoint) == 40);

/// A slice's rotary joints (rotary machines only, one per CompactSlice, same order): min and
/// max following error over the slice's busy rows (IDLE and STARTING rows are left out, as the
/// report's joint digest leaves them out), degrees, by joint index A, B, C.
struct CompactJointSlice {
  double t0 = 0.0, t1 = 0.0;  // first and last busy row (rows == 0: none)
  double ferr_min[3] = {0, 0, 0}, ferr_max[3] = {0, 0, 0};
  std::uint32_t rows = 0, reserved = 0;
};
static_assert(std::is_trivially_copyable_v<CompactJointSlice> && sizeof(CompactJointSlice) == 72);

/// A kept busy row for the tool-axis view: the commanded position and joints (degrees, by
/// joint index A, B, C), single precision (a float resolves 3e-5° at 360°).
struct CompactJointPoint {
  double t = 0.0;  // program time, s
  float commanded[3] = {0, 0, 0};  // mm
  float joints[3] = {0, 0, 0};     // deg
  std::uint32_t reserved[2] = {0, 0};
};
static_assert(std::is_trivially_copyable_v<CompactJointPoint> && sizeof(CompactJointPoint) == 40);

/// The joint section's own totals, written first in it.
struct CompactJointTotals {
  std::uint64_t points = 0;          // CompactJointPoint records (the slices: CompactTotals::slices)
  double ferr_abs_max[3] = {0, 0, 0};  // deg, over the busy rows of the window
  double path_tolerance_mm = 0.0, angle_tolerance_deg = 0.0;  // the points' final tolerances
  std::uint32_t slice_size = sizeof(CompactJointSlice), point_size = sizeof(CompactJointPoint);
};
static_assert(std::is_trivially_copyable_v<CompactJointTotals>);

/// What holds for the whole trace; written after the runs.
struct CompactTotals {
  std::uint64_t rows = 0;          // every row the writer saw
  std::uint64_t program_rows = 0;  // rows in the program's window
  std::uint64_t runs = 0, slices = 0, points = 0;  // records in the file
  double duration_s = 0.0, speed_max = 0.0;
  Vec3 ferr_abs_max{};
  double slice_width_s = 0.0;      // the slices' final width
  double path_tolerance_mm = 0.0;  // the path's final tolerance
  TraceSample last{};              // the window's last row (CSV-rounded)
  std::uint32_t saw_fault = 0;     // FAULT, ESTOP or HOST_LOST in the window
  std::uint32_t rotary_mask = 0;   // the machine's rotary joints (RotaryMask); 0: no joint section
};
static_assert(std::is_trivially_copyable_v<CompactTotals>);

/// The file: header, runs (streamed), totals, slices, points, [joint section: CompactJointTotals,
/// CompactJointSlice x slices, CompactJointPoint x points], footer. Native byte order;
/// the header names the record sizes so a reader of another build refuses it.
struct CompactHeader {
  char magic[8] = {'P', 'C', 'N', 'C', 'C', 'T', 'R', '1'};
  std::uint32_t version = 1;
  std::uint32_t run_size = sizeof(CompactRun), slice_size = sizeof(CompactSlice), point_size = sizeof(CompactPoint),
                totals_size = sizeof(CompactTotals), reserved = 0;
};
struct CompactFooter {
  std::uint64_t totals_offset = 0;  // byte offset of CompactTotals
  char magic[8] = {'P', 'C', 'N', 'C', 'C', 'E', 'N', 'D'};
};
static_assert(std::is_trivially_copyable_v<CompactHeader> && std::is_trivially_copyable_v<CompactFooter>);

/// A point's position and following error, mm.
Vec3 point_position(const CompactPoint& p);
Vec3 point_ferr(const CompactPoint& p);

/// Rounds as the CSV row does (ipc/trace_format.cpp: t %.4f, positions %.7f, speed %.5f).
double round_like_csv(double x, double scale);
TraceSample round_like_csv(const TraceSample& s);

class CompactTraceBuilder {
 public:
  static constexpr std::size_t kMaxSlices = 4096;   // the report uses at most 920 buckets: slices nest in them
  static constexpr std::size_t kMaxPoints = 65536;  // 2.6 MB at most; the report keeps at most 40,000 points
  static constexpr double kPathToleranceMm = 0.001;
  static constexpr double kAngleToleranceDeg = 0.001;

  /// `on_run` receives each run once it is complete, in time order. `rotary`: the machine's
  /// rotary joints (0: no joint section, the 3-axis file).
  explicit CompactTraceBuilder(std::function<void(const CompactRun&)> on_run, RotaryMask rotary = 0);
  /// One row, in time order (as the rt's queue delivers them), with its joints (rotary only).
  void add(const TraceSample& raw, const TraceJoints& joints = {});
  /// Ends the last run (handed to on_run) and returns the totals; slices() and points() are final.
  CompactTotals finish();
  const std::vector<CompactSlice>& slices() const { return slices_; }
  const std::vector<CompactPoint>& points() const { return points_; }
  /// The joint section (rotary machines; after finish()).
  const CompactJointTotals& joint_totals() const { return joint_totals_; }
  const std::vector<CompactJointSlice>& joint_slices() const { return joint_slices_; }
  const std::vector<CompactJointPoint>& joint_points() const { return joint_points_; }

 private:
  void add_window_row(const TraceSample& raw, const TraceJoints* joints);
  void add_joints(const TraceSample& raw, const TraceJoints& j, double t);
  bool keep_joint_point(const CompactJointPoint& p, const CompactJointPoint& last) const;
  void add_to_slices(const TraceSample& r, double t);
  void add_to_run(const TraceSample& r, double t);
  void add_to_path(const TraceSample& raw, const TraceSample& r, double t);
  void emit_run();

  std::function<void(const CompactRun&)> on_run_;
  CompactTotals totals_;
  std::vector<CompactSlice> slices_;
  std::vector<CompactPoint> points_;
  std::vector<TraceSample> idle_tail_;  // raw IDLE rows after the last busy row
  bool started_ = false, ended_ = false;
  double t_start_ = 0.0;
  double slice_width_ = 0.0005;
  double path_tol_ = kPathToleranceMm;
  Vec3 last_kept_{};  // raw position of the last kept path point
  CompactRun run_{};
  bool run_open_ = false;
  RotaryMask rotary_ = 0;
  CompactJointTotals joint_totals_;
  std::vector<CompactJointSlice> joint_slices_;  // parallel to slices_
  std::vector<CompactJointPoint> joint_points_;
  CompactJointPoint last_joint_row_{};  // the last busy row (kept at finish when thinned away)
  bool have_joint_row_ = false;
  double joint_tol_mm_ = kPathToleranceMm, joint_tol_deg_ = kAngleToleranceDeg;
};

}  // namespace pcnc
