// segment_merge.cpp — merging runs of collinear feed moves (see segment_merge.hpp).
#include "gcode/segment_merge.hpp"

#include <algorithm>

#include "geometry/spline_fit.hpp"

namespace pcnc {

bool SegmentMerger::fits(const std::vector<Vec3>& points, const Vec3& end, double tolerance) {
  if (points.empty() || !(norm(end - points.front()) > 1e-9)) return false;
  for (std::size_t i = 1; i < points.size(); ++i) {
    if (point_segment_distance(points[i], points.front(), end) > tolerance) return false;
  }
  return true;
}

bool SegmentMerger::next(const std::function<bool(Move&)>& pull, Move& out) {
  Move m;
  if (have_stash_) {
    m = std::move(stash_);
    have_stash_ = false;
  } else if (!pull(m)) {
    return false;
  }
  if (!mergeable(m)) {
    out = std::move(m);
    return true;
  }
  points_.clear();
  points_.push_back(m.start);
  points_.push_back(m.end);
  Move n;
  while (pull(n)) {
    if (points_.size() <= kMaxRun && mergeable(n) && n.feed_mm_s == m.feed_mm_s && n.machine_frame == m.machine_frame &&
        n.path_tolerance_mm == m.path_tolerance_mm && fits(points_, n.end, m.path_tolerance_mm)) {
      points_.push_back(n.end);
      m.end = n.end;
      m.line = n.line;
      m.known = n.known;
      continue;
    }
    stash_ = std::move(n);
    have_stash_ = true;
    break;
  }
  out = std::move(m);
  return true;
}

}  // namespace pcnc
