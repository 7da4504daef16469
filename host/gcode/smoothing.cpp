// smoothing.cpp — runs of G1 moves into curves within the path tolerance (see smoothing.hpp).
#include "gcode/smoothing.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>

#include "gcode/spline_fit_memo.hpp"
#include "geometry/junction_deviation.hpp"
#include "geometry/nurbs.hpp"
#include "geometry/spline_fit.hpp"

namespace pcnc {

Smoother::Smoother(const MachineConfig& config)
    : cos_corner_(std::cos(config.motion.smoothing_angle_deg * std::numbers::pi / 180.0)) {
  for (std::size_t i = 0; i < static_cast<std::size_t>(kAxes); ++i) {
    travel_min_[i] = config.axes[i].travel_min_mm;
    travel_max_[i] = config.axes[i].travel_max_mm;
    accel_[i] = config.axes[i].max_accel_mm_s2;
  }
}

// The curve lies in its control points' hull (weights 1): within the travel if they are, to a
// tenth of the preflight's rounding allowance. A run that fills the travel (--fit scales a
// program to touch both ends of an axis) may otherwise be smoothed a few µm beyond it, and the
// preflight would refuse the program.
bool Smoother::within_travel(const NurbsCurve& c) const {
  constexpr double kSlack = 1e-7;  // mm
  for (const Vec3& p : c.points) {
    for (std::size_t i = 0; i < static_cast<std::size_t>(kAxes); ++i) {
      if (p[i] < travel_min_[i] - kSlack || p[i] > travel_max_[i] + kSlack) return false;
    }
  }
  return true;
}

// Two moves fitted alone make a rounded corner: within the tolerance its tightest radius is
// about the junction-deviation circle's (spiral_lines.ngc's pairs: the curve's 99.6 mm/s at the
// axes' acceleration against the corner's 99.9; not a bound proven for every pair), the rt's schedule gives the normal part only a
// share of the acceleration, and the curve's end tangents leave the chords (by 0.6° there),
// which sharpens the corners at its ends. Where the corner is slower than the feed, the rt's
// corner (blended within the tolerance) is the faster way through.
bool Smoother::corner_binds(std::size_t k) const {
  const Move& m = run_[k];
  const double v = junction_deviation_speed(normalized(m.end - m.start), normalized(run_[k + 1].end - run_[k + 1].start),
                                            accel_, m.path_tolerance_mm);
  return v < m.feed_mm_s;
}

bool Smoother::smoothable(const Move& m) const {
  return m.kind == MoveKind::kLine && m.contouring && m.path_tolerance_mm > 0.0 && m.probe_rule == 0 && !m.tcp &&
         m.rot_start == m.rot_end;
}

bool Smoother::continues(const Move& last, const Move& m) const {
  if (m.feed_mm_s != last.feed_mm_s || m.path_tolerance_mm != last.path_tolerance_mm ||
      m.machine_frame != last.machine_frame || run_.size() >= kMaxRun) {
    return false;
  }
  const Vec3 a = normalized(last.end - last.start), b = normalized(m.end - m.start);
  return dot(a, b) >= cos_corner_;  // a turn above the smoothing angle is a real corner
}

bool Smoother::next(const std::function<bool(Move&)>& pull, Move& out) {
  while (out_.empty()) {
    Move m;
    if (!pull(m)) {
      flush_run();
      if (out_.empty()) return false;
      break;
    }
    if (!smoothable(m)) {
      flush_run();
      out_.push_back(std::move(m));
      continue;
    }
    if (!(norm(m.end - m.start) > 1e-9)) {  // no displacement: inside a run it adds nothing
      if (run_.empty()) out_.push_back(std::move(m));
      continue;
    }
    if (!run_.empty() && !continues(run_.back(), m)) flush_run();
    if (run_.empty()) points_.assign(1, m.start);
    points_.push_back(m.end);
    run_.push_back(std::move(m));
  }
  out = std::move(out_.front());
  out_.pop_front();
  return true;
}

void Smoother::flush_run() {
  fit_work_left_ = kFitWork * points_.size();
  if (!run_.empty()) fit_range(0, points_.size() - 1);
  run_.clear();
  points_.clear();
}

// Move k of the run goes from points_[k] to points_[k + 1].
void Smoother::fit_range(std::size_t first, std::size_t last) {
  const std::size_t count = last - first + 1;
  // a single move, two whose corner binds, or the run's work spent: lines
  if (last - first < 2 || (last - first == 2 && corner_binds(first)) || count > fit_work_left_) {
    for (std::size_t k = first; k < last; ++k) out_.push_back(run_[k]);
    return;
  }
  fit_work_left_ -= count;
  const std::vector<Vec3> pts(points_.begin() + static_cast<std::ptrdiff_t>(first),
                              points_.begin() + static_cast<std::ptrdiff_t>(last) + 1);
  const double tolerance = run_[first].path_tolerance_mm;
  SplineFit fit = fit_polyline_memo(pts, tolerance);  // the check's fit, when the stream asks again
  if (fit.ok && validate(fit.curve) == "" && !within_travel(fit.curve)) {
    // a fit that would leave the travel where the programmed moves stay inside: fit the two
    // halves (at worst the moves as programmed)
    const std::size_t mid = first + (last - first) / 2;
    fit_range(first, mid);
    fit_range(mid, last);
    return;
  }
  if (!fit.ok || validate(fit.curve) != "") {
    // a corner the angle did not see: keep it, fit both sides
    const std::size_t cut = first + std::clamp<std::size_t>(static_cast<std::size_t>(std::max(fit.worst_point, 0)), 1,
                                                             pts.size() - 2);
    fit_range(first, cut);
    fit_range(cut, last);
    return;
  }
  auto marks = std::make_shared<std::vector<LineMark>>();
  double u = 0.0;
  for (std::size_t k = first; k < last; ++k) {
    marks->push_back({u, run_[k].line});
    u += norm(points_[k + 1] - points_[k]);
  }
  Move c = run_[first];
  c.kind = MoveKind::kNurbs;
  c.start = pts.front();
  c.end = pts.back();
  c.known = run_[last - 1].known;
  c.smoothed = true;
  c.nurbs = std::make_shared<const NurbsCurve>(std::move(fit.curve));
  c.line_marks = std::move(marks);
  out_.push_back(std::move(c));
  stats_.moves += last - first;
  stats_.curves += 1;
  stats_.max_deviation_mm = std::max(stats_.max_deviation_mm, fit.deviation);
  stats_.min_tolerance_mm = stats_.curves == 1 ? tolerance : std::min(stats_.min_tolerance_mm, tolerance);
  stats_.max_tolerance_mm = std::max(stats_.max_tolerance_mm, tolerance);
}

}  // namespace pcnc
