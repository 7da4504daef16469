// trace_compact.cpp — the compact trace builder (see trace_compact.hpp). The window rule and
// the slice index are the report's digest's (host/report/trace_reader.cpp), so that the host
// can rebuild its buckets from the slices exactly.
#include "ipc/trace_compact.hpp"

#include <algorithm>
#include <cmath>

namespace pcnc {

namespace {

constexpr std::size_t kMaxIdleTail = 20000;  // as the report's digest: longer idle closes the window
constexpr double kTimeScale = 1e4, kPosScale = 1e7, kSpeedScale = 1e5;

bool busy(MachineState s) { return s != MachineState::kIdle && s != MachineState::kStarting; }

std::size_t slice_index(double t, double width) { return static_cast<std::size_t>(std::max(0.0, t) / width); }

void merge_slice(CompactSlice& m, const CompactSlice& x) {
  m.t1 = x.t1;
  m.speed_min = std::min(m.speed_min, x.speed_min);
  m.speed_max = std::max(m.speed_max, x.speed_max);
  for (std::size_t i = 0; i < 3; ++i) {
    m.ferr_min[i] = std::min(m.ferr_min[i], x.ferr_min[i]);
    m.ferr_max[i] = std::max(m.ferr_max[i], x.ferr_max[i]);
  }
  m.rows += x.rows;
  m.line_min = std::min(m.line_min, x.line_min);
  m.line_max = std::max(m.line_max, x.line_max);
}

void merge_joint_slice(CompactJointSlice& m, const CompactJointSlice& x) {
  if (x.rows == 0) return;
  if (m.rows == 0) {
    m = x;
    return;
  }
  m.t1 = x.t1;
  for (std::size_t i = 0; i < 3; ++i) {
    m.ferr_min[i] = std::min(m.ferr_min[i], x.ferr_min[i]);
    m.ferr_max[i] = std::max(m.ferr_max[i], x.ferr_max[i]);
  }
  m.rows += x.rows;
}

constexpr double kDeg = 180.0 / 3.14159265358979323846;  // as ipc/trace_format.cpp writes the joints

Vec3 round_vec(const Vec3& v) {
  return {round_like_csv(v[0], kPosScale), round_like_csv(v[1], kPosScale), round_like_csv(v[2], kPosScale)};
}

}  // namespace

Vec3 point_position(const CompactPoint& p) { return {p.actual[0], p.actual[1], p.actual[2]}; }
Vec3 point_ferr(const CompactPoint& p) { return {p.ferr[0], p.ferr[1], p.ferr[2]}; }

double round_like_csv(double x, double scale) { return std::nearbyint(x * scale) / scale; }

TraceSample round_like_csv(const TraceSample& s) {
  TraceSample r = s;
  r.t = round_like_csv(s.t, kTimeScale);
  r.commanded = round_vec(s.commanded);
  r.actual = round_vec(s.actual);
  r.following_error = round_vec(s.following_error);
  r.speed = round_like_csv(s.speed, kSpeedScale);
  return r;
}

CompactTraceBuilder::CompactTraceBuilder(std::function<void(const CompactRun&)> on_run, RotaryMask rotary)
    : on_run_(std::move(on_run)), rotary_(rotary) {
  // reserved once, so they never reallocate (pages are resident only as they fill)
  slices_.reserve(kMaxSlices + 1);
  points_.reserve(kMaxPoints + 1);
  idle_tail_.reserve(kMaxIdleTail);
  if (rotary_ != 0) {
    joint_slices_.reserve(kMaxSlices + 1);
    joint_points_.reserve(kMaxPoints + 1);
  }
}

void CompactTraceBuilder::add(const TraceSample& raw, const TraceJoints& joints) {
  ++totals_.rows;
  if (ended_) return;
  if (!started_) {
    if (raw.state != MachineState::kRunning) return;
    started_ = true;
    t_start_ = round_like_csv(raw.t, kTimeScale);
  }
  if (!busy(raw.state)) {
    if (idle_tail_.size() >= kMaxIdleTail) {
      ended_ = true;
      return;
    }
    idle_tail_.push_back(raw);
    return;
  }
  for (const TraceSample& r : idle_tail_) add_window_row(r, nullptr);  // idle rows carry no joints to keep
  idle_tail_.clear();
  add_window_row(raw, &joints);
}

void CompactTraceBuilder::add_window_row(const TraceSample& raw, const TraceJoints* joints) {
  TraceSample r = raw;  // time and speed as the CSV holds them; the rest is rounded where it is kept
  r.t = round_like_csv(raw.t, kTimeScale);
  r.speed = round_like_csv(raw.speed, kSpeedScale);
  const double t = r.t - t_start_;
  ++totals_.program_rows;
  totals_.duration_s = t;
  totals_.last = raw;
  totals_.speed_max = std::max(totals_.speed_max, r.speed);
  for (std::size_t i = 0; i < 3; ++i) {
    totals_.ferr_abs_max[i] = std::max(totals_.ferr_abs_max[i], std::fabs(raw.following_error[i]));
  }
  if (raw.state == MachineState::kFault || raw.state == MachineState::kEstop || raw.state == MachineState::kHostLost) {
    totals_.saw_fault = 1;
  }
  add_to_run(r, t);  // before the slices: a slice doubling must not split the open run's test
  add_to_slices(r, t);
  add_to_path(raw, r, t);
  if (rotary_ != 0 && joints) add_joints(raw, *joints, t);
}

// A busy row's joints: into the last slice's joint min/max and, when it moved far enough, the points.
void CompactTraceBuilder::add_joints(const TraceSample& raw, const TraceJoints& j, double t) {
  CompactJointSlice& k = joint_slices_.back();
  double ferr[3] = {0, 0, 0};
  for (std::size_t i = 0; i < 3; ++i) {
    if (!has_joint(rotary_, static_cast<int>(i))) continue;
    ferr[i] = round_like_csv((j.commanded[i] - j.actual[i]) * kDeg, kPosScale);  // the CSV's %.7f degrees
    joint_totals_.ferr_abs_max[i] = std::max(joint_totals_.ferr_abs_max[i], std::fabs(ferr[i]));
  }
  if (k.rows == 0) {
    k.t0 = t;
    for (std::size_t i = 0; i < 3; ++i) k.ferr_min[i] = k.ferr_max[i] = ferr[i];
  }
  k.t1 = t;
  for (std::size_t i = 0; i < 3; ++i) {
    k.ferr_min[i] = std::min(k.ferr_min[i], ferr[i]);
    k.ferr_max[i] = std::max(k.ferr_max[i], ferr[i]);
  }
  ++k.rows;

  CompactJointPoint p;
  p.t = t;
  for (std::size_t i = 0; i < 3; ++i) {
    p.commanded[i] = static_cast<float>(raw.commanded[i]);
    p.joints[i] = has_joint(rotary_, static_cast<int>(i)) ? static_cast<float>(j.commanded[i] * kDeg) : 0.0f;
  }
  last_joint_row_ = p;
  have_joint_row_ = true;
  if (!joint_points_.empty() && !keep_joint_point(p, joint_points_.back())) return;
  joint_points_.push_back(p);
  if (joint_points_.size() <= kMaxPoints) return;
  joint_tol_mm_ *= 2.0;
  joint_tol_deg_ *= 2.0;
  auto& v = joint_points_;
  std::size_t out = 1;
  for (std::size_t i = 1; i < v.size(); ++i) {
    if (keep_joint_point(v[i], v[out - 1])) v[out++] = v[i];
  }
  v.resize(out);
}

// Kept when the commanded position lies the tolerance from the last kept point `q` or a joint
// turned the angle tolerance from it.
bool CompactTraceBuilder::keep_joint_point(const CompactJointPoint& p, const CompactJointPoint& q) const {
  double d2 = 0.0, turn = 0.0;
  for (std::size_t i = 0; i < 3; ++i) {
    const double d = static_cast<double>(p.commanded[i]) - q.commanded[i];
    d2 += d * d;
    turn = std::max(turn, std::fabs(static_cast<double>(p.joints[i]) - q.joints[i]));
  }
  return d2 >= joint_tol_mm_ * joint_tol_mm_ || turn >= joint_tol_deg_;
}

void CompactTraceBuilder::add_to_run(const TraceSample& r, double t) {
  const auto speed = static_cast<std::int64_t>(std::llround(r.speed * kSpeedScale));
  const std::size_t slice = slice_index(t, slice_width_);
  if (run_open_ && run_.line == r.line && run_.state() == r.state && run_.speed_e5 == speed &&
      slice_index(run_.t, slice_width_) == slice && run_.count() < 0x0fffffffu) {
    ++run_.count_state;
    return;
  }
  emit_run();
  run_.t = t;
  run_.speed_e5 = speed;
  run_.line = r.line;
  run_.count_state = (static_cast<std::uint32_t>(r.state) << 28) | 1u;
  run_open_ = true;
}

void CompactTraceBuilder::emit_run() {
  if (!run_open_) return;
  ++totals_.runs;
  if (on_run_) on_run_(run_);
  run_open_ = false;
}

void CompactTraceBuilder::add_to_slices(const TraceSample& r, double t) {
  auto& s = slices_;
  if (s.empty() || slice_index(s.back().t0, slice_width_) != slice_index(t, slice_width_)) {
    CompactSlice k;
    k.t0 = k.t1 = t;
    k.speed_min = k.speed_max = r.speed;
    k.ferr_min = k.ferr_max = r.following_error;
    k.line_min = k.line_max = r.line;
    s.push_back(k);
    if (rotary_ != 0) joint_slices_.emplace_back();
  }
  CompactSlice& k = s.back();
  k.t1 = t;
  k.speed_min = std::min(k.speed_min, r.speed);
  k.speed_max = std::max(k.speed_max, r.speed);
  for (std::size_t i = 0; i < 3; ++i) {
    k.ferr_min[i] = std::min(k.ferr_min[i], r.following_error[i]);  // raw: rounded once at the end (monotone)
    k.ferr_max[i] = std::max(k.ferr_max[i], r.following_error[i]);
  }
  k.line_min = std::min(k.line_min, r.line);
  k.line_max = std::max(k.line_max, r.line);
  ++k.rows;
  if (s.size() > kMaxSlices) {
    slice_width_ *= 2.0;  // merge neighbours in place, as the report's buckets do
    std::size_t out = 0;
    const bool joints = rotary_ != 0;
    for (std::size_t i = 0; i < s.size(); ++i) {
      if (out > 0 && slice_index(s[out - 1].t0, slice_width_) == slice_index(s[i].t0, slice_width_)) {
        merge_slice(s[out - 1], s[i]);
        if (joints) merge_joint_slice(joint_slices_[out - 1], joint_slices_[i]);
      } else {
        if (joints) joint_slices_[out] = joint_slices_[i];
        s[out++] = s[i];
      }
    }
    s.resize(out);
    if (joints) joint_slices_.resize(out);
  }
}

void CompactTraceBuilder::add_to_path(const TraceSample& raw, const TraceSample& r, double t) {
  if (!points_.empty()) {
    const Vec3 d = raw.actual - last_kept_;
    if (d[0] * d[0] + d[1] * d[1] + d[2] * d[2] < path_tol_ * path_tol_) return;
  }
  last_kept_ = raw.actual;
  CompactPoint p;
  p.t = t;
  p.speed = static_cast<float>(r.speed);
  for (std::size_t i = 0; i < 3; ++i) {
    p.actual[i] = static_cast<float>(raw.actual[i]);
    p.ferr[i] = static_cast<float>(raw.following_error[i]);
  }
  p.line = r.line;
  points_.push_back(p);
  if (points_.size() <= kMaxPoints) return;
  path_tol_ *= 2.0;
  std::size_t out = 1;
  for (std::size_t i = 1; i < points_.size(); ++i) {
    if (norm(point_position(points_[i]) - point_position(points_[out - 1])) < path_tol_) continue;
    points_[out++] = points_[i];
  }
  points_.resize(out);
  last_kept_ = point_position(points_.back());
}

CompactTotals CompactTraceBuilder::finish() {
  emit_run();
  for (CompactSlice& k : slices_) {
    k.ferr_min = round_vec(k.ferr_min);
    k.ferr_max = round_vec(k.ferr_max);
  }
  totals_.last = round_like_csv(totals_.last);
  totals_.ferr_abs_max = round_vec(totals_.ferr_abs_max);
  totals_.slices = slices_.size();
  totals_.points = points_.size();
  totals_.slice_width_s = slice_width_;
  totals_.path_tolerance_mm = path_tol_;
  totals_.rotary_mask = rotary_;
  if (rotary_ != 0) {
    // the window's last busy row, also when the tolerance left it out or thinned it away
    if (have_joint_row_ && (joint_points_.empty() || joint_points_.back().t != last_joint_row_.t)) {
      joint_points_.push_back(last_joint_row_);
    }
    joint_totals_.points = joint_points_.size();
    joint_totals_.path_tolerance_mm = joint_tol_mm_;
    joint_totals_.angle_tolerance_deg = joint_tol_deg_;
  }
  return totals_;
}

}  // namespace pcnc
