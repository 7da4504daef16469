// joint_digest.cpp — a 5-axis trace's joints for the run report. See joint_digest.hpp.
#include "report/joint_digest.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>

namespace pcnc {
namespace {

constexpr double kRad = std::numbers::pi / 180.0;

bool busy(MachineState s) { return s != MachineState::kIdle && s != MachineState::kStarting; }

int column_of(const std::vector<char>& letters, char l) {
  for (std::size_t i = 0; i < letters.size(); ++i)
    if (letters[i] == l) return static_cast<int>(i);
  return -1;
}

}  // namespace

void merge_joint_bucket(JointBucket& m, const JointBucket& x) {
  m.t1 = x.t1;
  for (std::size_t i = 0; i < kMaxTraceJoints; ++i) {
    m.ferr_min[i] = std::min(m.ferr_min[i], x.ferr_min[i]);
    m.ferr_max[i] = std::max(m.ferr_max[i], x.ferr_max[i]);
  }
  m.rows += x.rows;
}

JointDigester::JointDigester(JointDigestOptions options, std::vector<char> letters) : o_(std::move(options)) {
  d_.letters = std::move(letters);
  o_.max_buckets = std::max<std::size_t>(o_.max_buckets, 2);
  o_.max_marks = std::max<std::size_t>(o_.max_marks, 2);
  tip_tol_ = o_.tip_tolerance_mm;
  d_.axis_every_mm = o_.axis_every_mm > 0.0 ? o_.axis_every_mm : 1.0;
  d_.axis_length_mm = o_.axis_length_mm;
  const KinematicsKind k = o_.kinematics.kind;
  if (o_.has_kinematics && k != KinematicsKind::kTrivial) {
    tilt_ = column_of(d_.letters, k == KinematicsKind::kTableTable ? 'A' : 'B');
    rotary_ = column_of(d_.letters, 'C');
    d_.tool_axis = tilt_ >= 0 && rotary_ >= 0;
  }
}

void JointDigester::add(const TraceSample& row, const TraceJointRow& j) {
  if (!started_) {
    if (row.state != MachineState::kRunning) return;
    started_ = true;
    t_start_ = row.t;
  }
  if (!busy(row.state)) return;
  const double t = row.t - t_start_;
  add_to_buckets(j, t);
  if (d_.tool_axis) add_to_axis(row, j, t);
}

void JointDigester::add_axis_only(const TraceSample& row, const TraceJointRow& j) {
  if (!started_) {
    if (row.state != MachineState::kRunning) return;
    started_ = true;
    t_start_ = row.t;
  }
  if (busy(row.state) && d_.tool_axis) add_to_axis(row, j, row.t - t_start_);
}

void JointDigester::add_to_buckets(const TraceJointRow& j, double t) {
  const std::size_t n = std::min(j.count, d_.letters.size());
  for (std::size_t i = 0; i < n; ++i) d_.ferr_abs_max[i] = std::max(d_.ferr_abs_max[i], std::fabs(j.ferr[i]));
  auto& b = d_.buckets;
  const auto index = static_cast<std::size_t>(std::max(0.0, t) / bucket_width_);
  if (b.empty() || static_cast<std::size_t>(std::max(0.0, b.back().t0) / bucket_width_) != index) {
    JointBucket k;
    k.t0 = k.t1 = t;
    k.ferr_min = k.ferr_max = j.ferr;
    b.push_back(k);
  }
  JointBucket& k = b.back();
  k.t1 = t;
  for (std::size_t i = 0; i < n; ++i) {
    k.ferr_min[i] = std::min(k.ferr_min[i], j.ferr[i]);
    k.ferr_max[i] = std::max(k.ferr_max[i], j.ferr[i]);
  }
  ++k.rows;
  if (b.size() > o_.max_buckets) {
    bucket_width_ *= 2.0;
    std::vector<JointBucket> merged;
    for (const JointBucket& x : b) {
      const auto ix = static_cast<std::size_t>(std::max(0.0, x.t0) / bucket_width_);
      if (!merged.empty() && static_cast<std::size_t>(std::max(0.0, merged.back().t0) / bucket_width_) == ix) {
        merge_joint_bucket(merged.back(), x);
      } else {
        merged.push_back(x);
      }
    }
    b.swap(merged);
  }
}

void JointDigester::add_to_axis(const TraceSample& row, const TraceJointRow& j, double t) {
  const Joints q{row.commanded[0], row.commanded[1], row.commanded[2], j.cmd[static_cast<std::size_t>(tilt_)] * kRad,
                 j.cmd[static_cast<std::size_t>(rotary_)] * kRad};
  const ToolPose pose = forward(o_.kinematics, q);
  if (have_tip_) d_.tip_path_mm += norm(pose.tip - last_tip_);
  have_tip_ = true;
  last_tip_ = pose.tip;
  if (d_.tip_path.empty() || norm(pose.tip - d_.tip_path.back()) >= tip_tol_) {
    d_.tip_path.push_back(pose.tip);
    if (d_.tip_path.size() > o_.max_tip_points) {
      tip_tol_ *= 2.0;
      std::vector<Vec3> kept;
      for (const Vec3& p : d_.tip_path)
        if (kept.empty() || norm(p - kept.back()) >= tip_tol_) kept.push_back(p);
      d_.tip_path.swap(kept);
    }
  }
  if (d_.tip_path_mm + 1e-12 < next_mark_) return;
  d_.marks.push_back(ToolAxisMark{pose.tip, pose.axis, d_.tip_path_mm, t});
  next_mark_ += d_.axis_every_mm;
  while (next_mark_ <= d_.tip_path_mm) next_mark_ += d_.axis_every_mm;  // a rapid jump: one mark
  if (d_.marks.size() > o_.max_marks) {
    d_.axis_every_mm *= 2.0;
    std::vector<ToolAxisMark> kept;
    double next = 0.0;
    for (const ToolAxisMark& m : d_.marks) {
      if (m.s_mm + 1e-12 < next) continue;
      kept.push_back(m);
      next = m.s_mm + d_.axis_every_mm;
    }
    d_.marks.swap(kept);
    next_mark_ = d_.marks.back().s_mm + d_.axis_every_mm;
  }
}

JointDigest JointDigester::finish() {
  // the final tip, also when the tolerance thinned it away
  if (have_tip_ && (d_.tip_path.empty() || norm(d_.tip_path.back() - last_tip_) > 0.0)) d_.tip_path.push_back(last_tip_);
  return std::move(d_);
}

}  // namespace pcnc
