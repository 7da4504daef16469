// trace_reader.cpp — streaming trace file reader (rows parsed by ipc/trace_format) and the one-pass digest for the run report.
#include "report/trace_reader.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>

namespace pcnc {

namespace {

constexpr std::size_t kMaxIdleTail = 20000;  // 10 s at 2 kHz: longer idle closes the program window

bool trace_busy(MachineState s) { return s != MachineState::kIdle && s != MachineState::kStarting; }

}  // namespace

void merge_bucket(TraceBucket& m, const TraceBucket& x) {
  m.t1 = x.t1;
  m.speed_min = std::min(m.speed_min, x.speed_min);
  m.speed_max = std::max(m.speed_max, x.speed_max);
  for (std::size_t i = 0; i < 3; ++i) {
    m.ferr_min[i] = std::min(m.ferr_min[i], x.ferr_min[i]);
    m.ferr_max[i] = std::max(m.ferr_max[i], x.ferr_max[i]);
  }
  if (x.feed_rows) {
    m.feed_speed_min = m.feed_rows ? std::min(m.feed_speed_min, x.feed_speed_min) : x.feed_speed_min;
    m.feed_speed_max = m.feed_rows ? std::max(m.feed_speed_max, x.feed_speed_max) : x.feed_speed_max;
  }
  m.planned_max = std::max(m.planned_max, x.planned_max);
  m.feed_rows += x.feed_rows;
  m.rapid_rows += x.rapid_rows;
  m.line_min = std::min(m.line_min, x.line_min);
  m.line_max = std::max(m.line_max, x.line_max);
  for (std::size_t c = 0; c < m.cause_rows.size(); ++c) m.cause_rows[c] += x.cause_rows[c];
  m.rows += x.rows;
}

TraceReader::TraceReader(const std::string& path) : path_(path) {
  file_ = std::fopen(path.c_str(), "r");
  if (!file_) throw std::runtime_error("cannot read trace '" + path + "': " + std::strerror(errno));
  buf_.resize(1024);
  if (!std::fgets(buf_.data(), static_cast<int>(buf_.size()), file_)) {
    std::fclose(file_);
    throw std::runtime_error("trace '" + path + "' is empty (no header)");
  }
  std::string_view h(buf_.data());
  while (!h.empty() && (h.back() == '\n' || h.back() == '\r')) h.remove_suffix(1);
  if (!parse_trace_joint_header(h, joint_letters_)) {
    std::fclose(file_);
    throw std::runtime_error("'" + path + "' is not a pcnc trace: its first line is not the trace header");
  }
}

TraceReader::~TraceReader() {
  if (file_) std::fclose(file_);
}

bool TraceReader::next(TraceSample& row) {
  for (;;) {
    if (!std::fgets(buf_.data(), static_cast<int>(buf_.size()), file_)) return false;
    std::string_view s(buf_.data());
    if (s.empty() || s.back() != '\n') {
      // the last row of a trace cut short (process killed mid-write) has no newline: skip it
      if (std::feof(file_)) return false;
      throw std::runtime_error(path_ + ": row " + std::to_string(rows_ + 2) + " is too long");
    }
    s.remove_suffix(1);
    if (s.empty()) continue;
    std::string_view base = s;
    if (!split_trace_joint_row(s, joint_letters_.size(), base, joint_row_) || !parse_trace_row(base, row)) {
      throw std::runtime_error(path_ + ": line " + std::to_string(rows_ + 2) + " is not a trace row: " + std::string(s));
    }
    ++rows_;
    return true;
  }
}

// ---- digest ----

TraceDigester::TraceDigester(DigestOptions options) : o_(std::move(options)) {
  o_.max_buckets = std::max<std::size_t>(o_.max_buckets, 2);
  path_tol_ = o_.path_tolerance_mm;
}

void TraceDigester::add(const TraceSample& row) {
  ++d_.rows;
  if (ended_) return;
  if (!started_) {
    if (row.state != MachineState::kRunning) return;
    started_ = true;
    t_start_ = row.t;
  }
  if (!trace_busy(row.state)) {
    if (idle_tail_.size() >= kMaxIdleTail) {
      ended_ = true;
      return;
    }
    idle_tail_.push_back(row);
    return;
  }
  for (const TraceSample& r : idle_tail_) {
    add_to_buckets(r, r.t - t_start_);
    add_to_path(r);
  }
  idle_tail_.clear();
  add_to_buckets(row, row.t - t_start_);
  add_to_path(row);
}

void TraceDigester::add_to_buckets(const TraceSample& row, double t) {
  ++d_.program_rows;
  d_.duration_s = t;
  d_.last = row;
  d_.speed_max = std::max(d_.speed_max, row.speed);
  for (std::size_t i = 0; i < 3; ++i) d_.ferr_abs_max[i] = std::max(d_.ferr_abs_max[i], std::fabs(row.following_error[i]));
  if (row.state == MachineState::kFault || row.state == MachineState::kEstop || row.state == MachineState::kHostLost) {
    d_.saw_fault = true;
  }

  const bool rapid = o_.is_rapid_line && o_.is_rapid_line(row.line);
  RowCause rc;
  if (o_.cause_of) {
    rc = o_.cause_of(row, prev_speed_);
    const auto c = static_cast<std::size_t>(rc.cause);
    ++d_.cause_rows[c];
    LineTime& lt = d_.line_time[row.line];
    ++lt.rows;
    ++lt.cause_rows[c];
  }
  prev_speed_ = row.speed;

  auto& b = d_.buckets;
  const auto index = static_cast<std::size_t>(std::max(0.0, t) / bucket_width_);
  if (b.empty() || static_cast<std::size_t>(std::max(0.0, b.back().t0) / bucket_width_) != index) {
    TraceBucket k;
    k.t0 = k.t1 = t;
    k.speed_min = k.speed_max = row.speed;
    k.ferr_min = k.ferr_max = row.following_error;
    k.line_min = k.line_max = row.line;
    b.push_back(k);
  }
  TraceBucket& k = b.back();
  k.t1 = t;
  k.speed_min = std::min(k.speed_min, row.speed);
  k.speed_max = std::max(k.speed_max, row.speed);
  for (std::size_t i = 0; i < 3; ++i) {
    k.ferr_min[i] = std::min(k.ferr_min[i], row.following_error[i]);
    k.ferr_max[i] = std::max(k.ferr_max[i], row.following_error[i]);
  }
  k.line_min = std::min(k.line_min, row.line);
  k.line_max = std::max(k.line_max, row.line);
  if (rapid) {
    ++k.rapid_rows;
  } else {
    k.feed_speed_min = k.feed_rows ? std::min(k.feed_speed_min, row.speed) : row.speed;
    k.feed_speed_max = k.feed_rows ? std::max(k.feed_speed_max, row.speed) : row.speed;
    k.planned_max = std::max(k.planned_max, rc.planned_speed);
    ++k.feed_rows;
  }
  if (o_.cause_of) ++k.cause_rows[static_cast<std::size_t>(rc.cause)];
  ++k.rows;
  if (b.size() > o_.max_buckets) {
    // merge neighbours (in pairs of the doubled width) and go on with twice the width
    bucket_width_ *= 2.0;
    std::vector<TraceBucket> merged;
    merged.reserve(b.size() / 2 + 1);
    for (const TraceBucket& x : b) {
      const auto ix = static_cast<std::size_t>(std::max(0.0, x.t0) / bucket_width_);
      if (!merged.empty() && static_cast<std::size_t>(std::max(0.0, merged.back().t0) / bucket_width_) == ix) {
        merge_bucket(merged.back(), x);
      } else {
        merged.push_back(x);
      }
    }
    b.swap(merged);
  }
}

void TraceDigester::add_to_path(const TraceSample& row) {
  const bool rapid = o_.is_rapid_line && o_.is_rapid_line(row.line);
  auto& path = d_.path;
  if (!path.empty()) {
    const ToolPathPoint& last = path.back();
    if (rapid == last.rapid && norm(row.actual - last.p) < path_tol_) return;
  }
  path.push_back(ToolPathPoint{row.actual, row.speed, rapid, row.t - t_start_, row.line, row.following_error});
  if (path.size() > o_.max_path_points) thin_path();
}

void TraceDigester::thin_path() {
  path_tol_ *= 2.0;
  std::vector<ToolPathPoint> kept;
  kept.reserve(d_.path.size() / 2 + 1);
  for (const ToolPathPoint& p : d_.path) {
    if (!kept.empty() && p.rapid == kept.back().rapid && norm(p.p - kept.back().p) < path_tol_) continue;
    kept.push_back(p);
  }
  d_.path.swap(kept);
}

TraceDigest TraceDigester::finish() {
  // the final position: the last row of the window, also when the path thinned it away
  if (d_.program_rows > 0 && (d_.path.empty() || norm(d_.path.back().p - d_.last.actual) > 0.0)) {
    d_.path.push_back(ToolPathPoint{d_.last.actual, d_.last.speed, o_.is_rapid_line && o_.is_rapid_line(d_.last.line),
                                    d_.last.t - t_start_, d_.last.line, d_.last.following_error});
  }
  d_.path_tolerance_mm = path_tol_;
  d_.classified = static_cast<bool>(o_.cause_of);
  return std::move(d_);
}

TraceDigest digest_trace(const std::string& path, const DigestOptions& options) {
  TraceReader reader(path);
  TraceDigester digester(options);
  TraceSample row;
  if (reader.joint_letters().empty()) {
    while (reader.next(row)) digester.add(row);
    return digester.finish();
  }
  JointDigester joints(options.joints, reader.joint_letters());
  while (reader.next(row)) {
    digester.add(row);
    joints.add(row, reader.joint_row());
  }
  TraceDigest d = digester.finish();
  d.joints = joints.finish();
  return d;
}

}  // namespace pcnc
