// trace_compact_reader.cpp — the compact trace file read back and finished into the report's
// digest (see trace_compact_reader.hpp): runs give each row's cause and feed/rapid class,
// slices carry min and max, and the buckets are rebuilt from the slices by the digest's own
// doubling rule.
#include "report/trace_compact_reader.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <stdexcept>

#include "ipc/trace_compact.hpp"

namespace pcnc {

namespace {

using File = std::unique_ptr<std::FILE, int (*)(std::FILE*)>;

std::size_t bucket_index(double t, double width) { return static_cast<std::size_t>(std::max(0.0, t) / width); }

template <typename T>
void read_exact(std::FILE* f, T* out, std::size_t n, const std::string& path, const char* what) {
  if (n > 0 && std::fread(out, sizeof(T), n, f) != n) {
    throw std::runtime_error("compact trace '" + path + "' is cut short (" + what + ")");
  }
}

struct Contents {
  CompactTotals totals;
  std::vector<CompactSlice> slices;
  std::vector<CompactPoint> points;
  CompactJointTotals joint_totals;  // a rotary machine's joint section (totals.rotary_mask != 0)
  std::vector<CompactJointSlice> joint_slices;
  std::vector<CompactJointPoint> joint_points;
};

// Header, footer, totals, slices and points; leaves the file at the first run.
Contents read_contents(std::FILE* f, const std::string& path) {
  CompactHeader h;
  const CompactHeader want;
  if (std::fread(&h, sizeof h, 1, f) != 1 || std::memcmp(h.magic, want.magic, sizeof h.magic) != 0) {
    throw std::runtime_error("'" + path + "' is not a pcnc compact trace");
  }
  if (h.version != want.version || h.run_size != want.run_size || h.slice_size != want.slice_size ||
      h.point_size != want.point_size || h.totals_size != want.totals_size) {
    throw std::runtime_error("compact trace '" + path + "' has another layout (version " + std::to_string(h.version) +
                             ", this build reads version " + std::to_string(want.version) + ")");
  }
  CompactFooter foot;
  const CompactFooter want_foot;
  if (std::fseek(f, -static_cast<long>(sizeof foot), SEEK_END) != 0 || std::fread(&foot, sizeof foot, 1, f) != 1 ||
      std::memcmp(foot.magic, want_foot.magic, sizeof foot.magic) != 0) {
    throw std::runtime_error("compact trace '" + path + "' is incomplete: pcnc-rt did not close it");
  }
  Contents c;
  if (std::fseek(f, static_cast<long>(foot.totals_offset), SEEK_SET) != 0) {
    throw std::runtime_error("compact trace '" + path + "' is damaged (totals offset)");
  }
  read_exact(f, &c.totals, 1, path, "totals");
  if (foot.totals_offset != sizeof h + c.totals.runs * sizeof(CompactRun)) {
    throw std::runtime_error("compact trace '" + path + "' is damaged (its run count does not match its size)");
  }
  c.slices.resize(c.totals.slices);
  read_exact(f, c.slices.data(), c.slices.size(), path, "slices");
  c.points.resize(c.totals.points);
  read_exact(f, c.points.data(), c.points.size(), path, "path");
  if (c.totals.rotary_mask != 0) {
    read_exact(f, &c.joint_totals, 1, path, "joint totals");
    const CompactJointTotals want_joints;
    if (c.joint_totals.slice_size != want_joints.slice_size || c.joint_totals.point_size != want_joints.point_size) {
      throw std::runtime_error("compact trace '" + path + "' has another layout (its joint records)");
    }
    c.joint_slices.resize(c.totals.slices);
    read_exact(f, c.joint_slices.data(), c.joint_slices.size(), path, "joint slices");
    c.joint_points.resize(c.joint_totals.points);
    read_exact(f, c.joint_points.data(), c.joint_points.size(), path, "joint points");
  }
  if (std::fseek(f, static_cast<long>(sizeof h), SEEK_SET) != 0) throw std::runtime_error("cannot read '" + path + "'");
  return c;
}

TraceBucket bucket_of(const CompactSlice& s) {
  TraceBucket b;
  b.t0 = s.t0;
  b.t1 = s.t1;
  b.speed_min = s.speed_min;
  b.speed_max = s.speed_max;
  b.ferr_min = s.ferr_min;
  b.ferr_max = s.ferr_max;
  b.rows = s.rows;
  b.line_min = s.line_min;
  b.line_max = s.line_max;
  return b;
}

// The runs, one pass: each row's cause, feed or rapid, into its slice's bucket and the totals.
void add_runs(std::FILE* f, const std::string& path, const Contents& c, const DigestOptions& o,
              std::vector<TraceBucket>& slices, TraceDigest& d) {
  std::vector<CompactRun> buf(4096);
  std::uint64_t left = c.totals.runs;
  std::size_t j = 0;  // slice of the current run, and its bucket index
  std::size_t slice_at = slices.empty() ? 0 : bucket_index(slices[0].t0, c.totals.slice_width_s);
  double prev_speed = 0.0;
  const double w = c.totals.slice_width_s;
  // runs follow the program: most are on the line of the run before (one lookup per line)
  std::uint32_t last_line = 0;
  bool have_line = false, rapid = false;
  LineTime* lt = nullptr;
  while (left > 0) {
    const std::size_t n = static_cast<std::size_t>(std::min<std::uint64_t>(left, buf.size()));
    read_exact(f, buf.data(), n, path, "runs");
    left -= n;
    for (std::size_t i = 0; i < n; ++i) {
      const CompactRun& r = buf[i];
      const std::size_t at = bucket_index(r.t, w);
      while (j + 1 < slices.size() && slice_at < at) slice_at = bucket_index(slices[++j].t0, w);
      if (slices.empty() || slice_at != at) {
        throw std::runtime_error("compact trace '" + path + "' is damaged (a run outside every slice)");
      }
      TraceBucket& k = slices[j];
      TraceSample row;
      row.t = r.t;
      row.line = r.line;
      row.state = r.state();
      row.speed = static_cast<double>(r.speed_e5) / 1e5;  // as strtod reads the CSV's %.5f
      const std::uint32_t count = r.count();
      if (!have_line || row.line != last_line) {
        have_line = true;
        last_line = row.line;
        rapid = o.is_rapid_line && o.is_rapid_line(row.line);
        lt = o.cause_of ? &d.line_time[row.line] : nullptr;
      }
      RowCause first, rest;
      if (o.cause_of) {
        first = o.cause_of(row, prev_speed);
        if (count > 1) rest = o.cause_of(row, row.speed);
        const auto c1 = static_cast<std::size_t>(first.cause), cn = static_cast<std::size_t>(rest.cause);
        lt->rows += count;
        ++d.cause_rows[c1];
        ++lt->cause_rows[c1];
        ++k.cause_rows[c1];
        if (count > 1) {
          d.cause_rows[cn] += count - 1;
          lt->cause_rows[cn] += count - 1;
          k.cause_rows[cn] += count - 1;
        }
      }
      prev_speed = row.speed;
      if (rapid) {
        k.rapid_rows += count;
      } else {
        k.feed_speed_min = k.feed_rows ? std::min(k.feed_speed_min, row.speed) : row.speed;
        k.feed_speed_max = k.feed_rows ? std::max(k.feed_speed_max, row.speed) : row.speed;
        k.planned_max = std::max({k.planned_max, first.planned_speed, count > 1 ? rest.planned_speed : 0.0});
        k.feed_rows += count;
      }
    }
  }
}

// The digest's buckets from the slices, by its own rule: a bucket per index at the current
// width; past max_buckets, neighbours merge and the width doubles (once per row). For the
// 3-axis buckets (TraceBucket) and the joints' (JointBucket), each with its merge.
template <typename Bucket, typename Merge>
std::vector<Bucket> rebuild_buckets(const std::vector<Bucket>& slices, double slice_width, std::size_t max_buckets,
                                    Merge merge) {
  std::vector<Bucket> b;
  double width = slice_width;
  for (const Bucket& x : slices) {
    if (b.empty() || bucket_index(b.back().t0, width) != bucket_index(x.t0, width)) {
      b.push_back(x);
    } else {
      merge(b.back(), x);
    }
    for (std::uint32_t r = 0; r < x.rows && b.size() > max_buckets; ++r) {
      width *= 2.0;
      std::vector<Bucket> merged;
      merged.reserve(b.size() / 2 + 1);
      for (const Bucket& y : b) {
        if (!merged.empty() && bucket_index(merged.back().t0, width) == bucket_index(y.t0, width)) {
          merge(merged.back(), y);
        } else {
          merged.push_back(y);
        }
      }
      b.swap(merged);
    }
  }
  return b;
}

// The report's path rule over the rt's points: a point is kept when the rapid class changes
// or it lies the tolerance from the last kept one; past max_path_points the tolerance doubles.
std::vector<ToolPathPoint> decimate_path(const std::vector<CompactPoint>& points, const DigestOptions& o, double& tol) {
  std::vector<ToolPathPoint> path;
  path.reserve(std::min(points.size(), o.max_path_points) + 1);
  auto thin = [&] {
    tol *= 2.0;
    std::vector<ToolPathPoint> kept;
    kept.reserve(path.capacity());
    for (const ToolPathPoint& p : path) {
      if (!kept.empty() && p.rapid == kept.back().rapid && norm(p.p - kept.back().p) < tol) continue;
      kept.push_back(p);
    }
    path.swap(kept);
  };
  std::uint32_t last_line = 0;
  bool have_line = false, rapid = false;
  for (const CompactPoint& c : points) {
    if (!have_line || c.line != last_line) {  // one lookup per run of points on a line
      have_line = true;
      last_line = c.line;
      rapid = o.is_rapid_line && o.is_rapid_line(c.line);
    }
    const Vec3 p = point_position(c);
    if (!path.empty() && rapid == path.back().rapid && norm(p - path.back().p) < tol) continue;
    path.push_back(ToolPathPoint{p, static_cast<double>(c.speed), rapid, c.t, c.line, point_ferr(c)});
    if (path.size() > o.max_path_points) thin();
  }
  return path;
}

// A rotary machine's joints as the CSV's joint digest gives them: the buckets rebuilt from the
// joint slices (exact), the tip path and tool-axis marks from the kept points (the rt's
// decimation: within its tolerances of the CSV's).
JointDigest joint_digest(const Contents& c, const JointDigestOptions& options) {
  std::vector<char> letters;
  std::vector<std::size_t> index;  // column -> joint index (A, B, C)
  for (int i = 0; i < kRotaryJoints; ++i) {
    if (!has_joint(static_cast<RotaryMask>(c.totals.rotary_mask), i)) continue;
    letters.push_back(joint_letter(i));
    index.push_back(static_cast<std::size_t>(i));
  }
  JointDigester digester(options, letters);
  for (const CompactJointPoint& p : c.joint_points) {
    TraceSample row;
    row.t = p.t;
    row.state = MachineState::kRunning;
    row.commanded = {p.commanded[0], p.commanded[1], p.commanded[2]};
    TraceJointRow j;
    j.count = letters.size();
    for (std::size_t k = 0; k < index.size(); ++k) j.cmd[k] = p.joints[index[k]];
    digester.add_axis_only(row, j);
  }
  JointDigest d = digester.finish();
  std::vector<JointBucket> slices;
  for (const CompactJointSlice& s : c.joint_slices) {
    if (s.rows == 0) continue;  // idle rows only
    JointBucket b;
    b.t0 = s.t0;
    b.t1 = s.t1;
    b.rows = s.rows;
    for (std::size_t k = 0; k < index.size(); ++k) {
      b.ferr_min[k] = s.ferr_min[index[k]];
      b.ferr_max[k] = s.ferr_max[index[k]];
    }
    slices.push_back(b);
  }
  d.buckets = rebuild_buckets(slices, c.totals.slice_width_s, std::max<std::size_t>(options.max_buckets, 2),
                              [](JointBucket& m, const JointBucket& x) { merge_joint_bucket(m, x); });
  for (std::size_t k = 0; k < index.size(); ++k) d.ferr_abs_max[k] = c.joint_totals.ferr_abs_max[index[k]];
  return d;
}

}  // namespace

bool is_compact_trace_file(const std::string& path) {
  File f(std::fopen(path.c_str(), "rb"), &std::fclose);
  if (!f) return false;
  char magic[8] = {};
  const CompactHeader want;
  return std::fread(magic, 1, sizeof magic, f.get()) == sizeof magic && std::memcmp(magic, want.magic, sizeof magic) == 0;
}

TraceDigest digest_compact_trace(const std::string& path, const DigestOptions& options) {
  File f(std::fopen(path.c_str(), "rb"), &std::fclose);
  if (!f) throw std::runtime_error("cannot read compact trace '" + path + "': " + std::strerror(errno));
  const Contents c = read_contents(f.get(), path);
  DigestOptions o = options;
  o.max_buckets = std::max<std::size_t>(o.max_buckets, 2);

  TraceDigest d;
  std::vector<TraceBucket> slices;
  slices.reserve(c.slices.size());
  for (const CompactSlice& s : c.slices) slices.push_back(bucket_of(s));
  add_runs(f.get(), path, c, o, slices, d);
  d.buckets = rebuild_buckets(slices, c.totals.slice_width_s, o.max_buckets,
                              [](TraceBucket& m, const TraceBucket& x) { merge_bucket(m, x); });

  const CompactTotals& t = c.totals;
  d.rows = t.rows;
  d.program_rows = t.program_rows;
  d.duration_s = t.duration_s;
  d.speed_max = t.speed_max;
  d.ferr_abs_max = t.ferr_abs_max;
  d.last = t.last;
  d.saw_fault = t.saw_fault != 0;
  d.classified = static_cast<bool>(o.cause_of);
  double tol = o.path_tolerance_mm;
  d.path = decimate_path(c.points, o, tol);
  // the final position: the last row of the window, also when the path thinned it away
  if (d.program_rows > 0 && (d.path.empty() || norm(d.path.back().p - d.last.actual) > 0.0)) {
    d.path.push_back(ToolPathPoint{d.last.actual, d.last.speed, o.is_rapid_line && o.is_rapid_line(d.last.line),
                                   d.duration_s, d.last.line, d.last.following_error});
  }
  d.path_tolerance_mm = tol;
  if (c.totals.rotary_mask != 0) d.joints = joint_digest(c, o.joints);
  return d;
}

}  // namespace pcnc
