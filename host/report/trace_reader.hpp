// trace_reader.hpp — reads the per-cycle trace CSV that pcnc-rt writes (--trace) and boils it
// down to what the run report draws: a time series of path speed and following error, and
// the tool path in space. One streaming pass, memory bounded by the plot resolution, not by
// the trace length (a ten-minute program is 1.2 million rows).
//
// Time series: rows fall into time buckets that keep each value's minimum and maximum, so
// peaks survive any decimation; when the buckets run out, neighbours merge pairwise and the
// bucket width doubles. Tool path: a point is kept when it lies farther than a tolerance
// from the last kept point, or when the speed class or the source line's kind changes.
#pragma once

#include <cstdint>
#include <cstdio>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include <array>
#include <unordered_map>

#include "gcode/time_cause.hpp"
#include "ipc/trace_format.hpp"
#include "geometry/vec3.hpp"
#include "report/joint_digest.hpp"
#include "report/trace_joints.hpp"

namespace pcnc {

/// Streams a trace file row by row. Throws std::runtime_error when the file cannot be read
/// or its header is not the trace header (with or without a 5-axis machine's joint columns,
/// trace_joints.hpp); next() throws on a malformed row, naming its line.
class TraceReader {
 public:
  explicit TraceReader(const std::string& path);
  ~TraceReader();
  TraceReader(const TraceReader&) = delete;
  TraceReader& operator=(const TraceReader&) = delete;
  bool next(TraceSample& row);
  std::uint64_t rows() const { return rows_; }
  /// The rotary joints the header declares ('A', 'B', 'C'; empty: a 3-axis trace), and the
  /// last row's values of them.
  const std::vector<char>& joint_letters() const { return joint_letters_; }
  const TraceJointRow& joint_row() const { return joint_row_; }

 private:
  std::string path_;
  std::FILE* file_ = nullptr;
  std::string buf_;
  std::uint64_t rows_ = 0;
  std::vector<char> joint_letters_;
  TraceJointRow joint_row_;
};

/// One time bucket of the decimated series: min and max of each value over its rows.
struct TraceBucket {
  double t0 = 0.0, t1 = 0.0;  // time of its first and last row, s (program time)
  double speed_min = 0.0, speed_max = 0.0;
  Vec3 ferr_min{}, ferr_max{};
  std::uint32_t rows = 0;
  // feed (not rapid) rows only: their speed range and the planned speed limit (the F, or what
  // caps it); rapid_rows counts the rest
  double feed_speed_min = 0.0, feed_speed_max = 0.0, planned_max = 0.0;
  std::uint32_t feed_rows = 0, rapid_rows = 0;
  std::uint32_t line_min = 0, line_max = 0;  // source lines of its rows
  std::array<std::uint32_t, kTimeCauseCount> cause_rows{};  // rows per cause (when classified)
};

/// x's rows into m (x follows m in time): min and max, counts, the later end time.
void merge_bucket(TraceBucket& m, const TraceBucket& x);

/// What a row's time is attributed to, and the planned speed limit there (0: none).
struct RowCause {
  TimeCause cause = TimeCause::kOther;
  double planned_speed = 0.0;
};

/// Rows of one source line, per cause: the "slowest stretches" table.
struct LineTime {
  std::uint64_t rows = 0;
  std::array<std::uint32_t, kTimeCauseCount> cause_rows{};
};

/// A kept point of the tool path (actual, measured position, machine coordinates).
struct ToolPathPoint {
  Vec3 p{};
  double speed = 0.0;  // commanded path speed there, mm/s
  bool rapid = false;  // the block in execution was a rapid (G00)
  double t = 0.0;          // program time of the row, s (the 3D view's time slider)
  std::uint32_t line = 0;  // source line in execution
  Vec3 ferr{};             // following error there, mm
};

struct DigestOptions {
  std::size_t max_buckets = 1200;       // time resolution of the plots
  double path_tolerance_mm = 0.02;      // tool path: keep points at least this far apart
  std::size_t max_path_points = 200000; // beyond this the tolerance doubles and the path thins
  /// Is the block on this source line a rapid? (From the program; empty: never.)
  std::function<bool(std::uint32_t line)> is_rapid_line;
  /// The cause of each row of the program's window, given the previous row's speed (from the
  /// plan, report/time_causes.hpp); empty: no attribution.
  std::function<RowCause(const TraceSample& row, double prev_speed)> cause_of;
  /// A trace with joint columns: how its joints are digested (the kinematics for the tool axis).
  JointDigestOptions joints;
};

/// What the report needs from a trace. Times are program time: 0 at the first RUNNING row.
struct TraceDigest {
  std::uint64_t rows = 0;           // all rows read
  std::uint64_t program_rows = 0;   // rows from the first RUNNING row to the last non-idle one
  double duration_s = 0.0;          // of that window
  double speed_max = 0.0;           // mm/s
  Vec3 ferr_abs_max{};              // mm, over the window
  std::vector<TraceBucket> buckets;
  std::vector<ToolPathPoint> path;
  double path_tolerance_mm = 0.0;   // the tolerance finally used
  TraceSample last{};                  // the last row of the window
  bool saw_fault = false;           // FAULT, ESTOP or HOST_LOST appeared
  bool classified = false;          // cause_of was given: the counts below are filled
  std::array<std::uint64_t, kTimeCauseCount> cause_rows{};  // program rows per cause
  std::unordered_map<std::uint32_t, LineTime> line_time;     // per source line
  JointDigest joints;               // a 5-axis trace's joints (joints.letters empty: none)
};

/// Reads the whole trace once and digests it.
TraceDigest digest_trace(const std::string& path, const DigestOptions& options = {});

/// The same digest over rows from any source (tests).
class TraceDigester {
 public:
  explicit TraceDigester(DigestOptions options);
  void add(const TraceSample& row);
  TraceDigest finish();

 private:
  void add_to_buckets(const TraceSample& row, double t);
  void add_to_path(const TraceSample& row);
  void thin_path();

  DigestOptions o_;
  TraceDigest d_;
  bool started_ = false;
  double t_start_ = 0.0;
  double bucket_width_ = 0.0005;  // s; doubles as buckets merge
  double path_tol_ = 0.0;
  // IDLE rows after the last busy row: part of the program only if a busy row follows.
  std::vector<TraceSample> idle_tail_;
  bool ended_ = false;  // a long idle stretch closed the window
  double prev_speed_ = 0.0;
};

}  // namespace pcnc
