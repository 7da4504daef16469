// joint_digest.hpp — what the run report draws from a 5-axis trace's joint columns
// (trace_joints.hpp): the joints' following error over program time as min..max buckets (the
// axes' plots, report_plots.hpp), and the tool seen from the workpiece: the commanded tool tip
// and, every N mm along its path, the tool axis as a short line, both from the forward
// kinematics (geometry/kinematics.hpp) of the commanded joints with the machine's config. One
// streaming pass beside the 3-axis digest (trace_reader.hpp), memory bounded by its options.
#pragma once

#include <array>
#include <cstddef>
#include <vector>

#include "geometry/kinematics.hpp"
#include "ipc/trace_format.hpp"
#include "report/trace_joints.hpp"

namespace pcnc {

struct JointDigestOptions {
  bool has_kinematics = false;  // false: no tool axis (the plots still are)
  Kinematics kinematics{};      // the machine's, with the tool length the marks use
  double axis_every_mm = 1.0;   // a tool-axis mark every this much of the tip's path
  double axis_length_mm = 3.0;  // drawn this long, from the tip along the axis
  std::size_t max_marks = 1500;      // beyond this the spacing doubles and every other mark goes
  double tip_tolerance_mm = 0.02;    // the tip path keeps points at least this far apart
  std::size_t max_tip_points = 20000;
  std::size_t max_buckets = 1200;
};

struct JointBucket {
  double t0 = 0.0, t1 = 0.0;  // program time of its first and last row, s
  std::array<double, kMaxTraceJoints> ferr_min{}, ferr_max{};  // deg
  std::uint32_t rows = 0;
};

/// `x` (the later bucket) merged into `m`.
void merge_joint_bucket(JointBucket& m, const JointBucket& x);

/// One tool-axis mark: where the tip was and which way the tool pointed (workpiece coordinates).
struct ToolAxisMark {
  Vec3 tip{};
  Vec3 axis{0.0, 0.0, 1.0};
  double s_mm = 0.0;  // tip path length from the start
  double t = 0.0;     // program time, s
};

struct JointDigest {
  std::vector<char> letters;  // 'A', 'B', 'C' in the trace's order; empty: a 3-axis trace
  std::array<double, kMaxTraceJoints> ferr_abs_max{};  // deg, over the program window
  std::vector<JointBucket> buckets;
  bool tool_axis = false;       // kinematics given and the joints it needs are in the trace
  std::vector<ToolAxisMark> marks;
  std::vector<Vec3> tip_path;   // the commanded tool tip, workpiece coordinates
  double tip_path_mm = 0.0;     // its length
  double axis_every_mm = 0.0;   // the marks' spacing finally used
  double axis_length_mm = 0.0;
};

/// Rows from the first RUNNING row on; rows while the machine is idle or starting are left out.
class JointDigester {
 public:
  JointDigester(JointDigestOptions options, std::vector<char> letters);
  void add(const TraceSample& row, const TraceJointRow& joints);
  JointDigest finish();
  /// For rows that carry no following error (the compact trace's kept points): only the tip path and marks.
  void add_axis_only(const TraceSample& row, const TraceJointRow& joints);

 private:
  void add_to_buckets(const TraceJointRow& j, double t);
  void add_to_axis(const TraceSample& row, const TraceJointRow& j, double t);

  JointDigestOptions o_;
  JointDigest d_;
  int tilt_ = -1, rotary_ = -1;  // columns of the kinematics' tilt and rotary joints
  bool started_ = false;
  double t_start_ = 0.0;
  double bucket_width_ = 0.0005;
  double tip_tol_ = 0.0;
  bool have_tip_ = false;
  Vec3 last_tip_{};
  double next_mark_ = 0.0;
};

}  // namespace pcnc
