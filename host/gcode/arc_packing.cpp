// arc_packing.cpp — chains of short tangent arcs into exact NURBS curves (see arc_packing.hpp).
#include "gcode/arc_packing.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>

#include "geometry/arc_nurbs.hpp"
#include "geometry/nurbs.hpp"
#include "geometry/plane.hpp"

namespace pcnc {
namespace {

constexpr double kHelixSlack = 1e-9;      // mm along the normal axis: a flat arc
constexpr double kJoinGap = 1e-9;         // mm: an arc that starts farther from the last one's end ends a chain
constexpr double kDeviationShare = 0.1;   // of the tolerance: the most a packed chain may be off its arcs
constexpr int kDeviationSamples = 16;     // per arc, where the curve's distance is measured

PlaneArc plane_arc(const Move& m) { return {m.start, m.end, m.center, m.sweep, m.normal_axis}; }

double end_radius(const Move& m) {
  const auto ax = plane_axes(m.normal_axis);
  const auto a = static_cast<std::size_t>(ax[0]), b = static_cast<std::size_t>(ax[1]);
  return std::hypot(m.end[a] - m.center[a], m.end[b] - m.center[b]);
}

// The distance of point p from the arc as the rt runs it: about its center, the radius going
// linearly from the start's to the end's with the angle. p is a curve point between the arc's
// ends: its angle from the start, taken in the sweep's direction, lies in 0..|sweep|.
double distance_from_arc(const Move& m, const Vec3& p) {
  const auto ax = plane_axes(m.normal_axis);
  const auto a = static_cast<std::size_t>(ax[0]), b = static_cast<std::size_t>(ax[1]);
  const double a0 = std::atan2(m.start[b] - m.center[b], m.start[a] - m.center[a]);
  const double ap = std::atan2(p[b] - m.center[b], p[a] - m.center[a]);
  double phi = (ap - a0) * (m.sweep >= 0.0 ? 1.0 : -1.0);
  phi = std::remainder(phi, 2.0 * std::numbers::pi);
  if (phi < 0.0 && std::abs(m.sweep) > std::numbers::pi) phi += 2.0 * std::numbers::pi;
  const double f = std::clamp(phi / std::abs(m.sweep), 0.0, 1.0);
  const double r = m.radius + (end_radius(m) - m.radius) * f;
  const double rho = std::hypot(p[a] - m.center[a], p[b] - m.center[b]);
  const auto n = static_cast<std::size_t>(m.normal_axis);
  return std::hypot(rho - r, p[n] - m.start[n]);
}

}  // namespace

ArcPacker::ArcPacker(const MachineConfig& config) {
  for (int n = 0; n < 3; ++n) {
    const auto ax = plane_axes(n);
    plane_accel_[n] = std::min(config.axes[static_cast<std::size_t>(ax[0])].max_accel_mm_s2,
                               config.axes[static_cast<std::size_t>(ax[1])].max_accel_mm_s2);
  }
}

bool ArcPacker::packable(const Move& m) const {
  if (m.kind != MoveKind::kArc || !m.contouring || !(m.path_tolerance_mm > 0.0) || m.probe_rule != 0 || m.tcp ||
      m.rot_start != m.rot_end || !(std::abs(m.sweep) > 0.0) || !(m.radius > 0.0) ||
      std::abs(m.end[static_cast<std::size_t>(m.normal_axis)] - m.start[static_cast<std::size_t>(m.normal_axis)]) >
          kHelixSlack) {
    return false;
  }
  // only an arc the ring would slow: its curve's cap above the speed that stops within three
  // arcs like it
  const double a = plane_accel_[m.normal_axis];
  const double length = m.radius * std::abs(m.sweep);
  const double packed_cap = std::min(m.feed_mm_s, std::sqrt(kPackedArcNormalShare * a * m.radius));
  return packed_cap * packed_cap > 2.0 * a * 3.0 * length;
}

bool ArcPacker::continues(const Move& last, const Move& m) const {
  const auto n = static_cast<std::size_t>(m.normal_axis);
  if (m.feed_mm_s != last.feed_mm_s || m.path_tolerance_mm != last.path_tolerance_mm ||
      m.machine_frame != last.machine_frame || m.normal_axis != last.normal_axis || m.start[n] != last.start[n] ||
      !(norm(m.start - last.end) <= kJoinGap) || chain_.size() >= kMaxChain) {
    return false;
  }
  const Vec3 t_end = plane_arc_tangent(plane_arc(last), last.sweep);
  const Vec3 t_start = plane_arc_tangent(plane_arc(m), 0.0);
  return dot(t_end, t_start) >= std::cos(kTangentKinkTurn);
}

bool ArcPacker::next(const std::function<bool(Move&)>& pull, Move& out) {
  while (out_.empty()) {
    Move m;
    if (!pull(m)) {
      flush();
      if (out_.empty()) return false;
      break;
    }
    if (!packable(m)) {
      flush();
      out_.push_back(std::move(m));
      continue;
    }
    if (!chain_.empty() && !continues(chain_.back(), m)) flush();
    chain_.push_back(std::move(m));
  }
  out = std::move(out_.front());
  out_.pop_front();
  return true;
}

void ArcPacker::flush() {
  if (!chain_.empty()) pack(0, chain_.size());
  chain_.clear();
}

// Arcs first..last-1 of the chain: one curve, or where the curve turns at a join by more than
// a kink (an end point a rounding off its radius tilts the arc's end tangent, as the rt runs
// it: the radius changing with the angle), two chains cut there.
void ArcPacker::pack(std::size_t first, std::size_t last) {
  if (last - first < 2) {
    for (std::size_t k = first; k < last; ++k) out_.push_back(chain_[k]);
    return;
  }
  std::vector<PlaneArc> arcs;
  arcs.reserve(last - first);
  for (std::size_t k = first; k < last; ++k) arcs.push_back(plane_arc(chain_[k]));
  std::vector<double> starts;
  NurbsCurve curve = arc_chain_nurbs(arcs, &starts);
  if (validate(curve) != "") {
    for (std::size_t k = first; k < last; ++k) out_.push_back(chain_[k]);
    return;
  }
  const std::vector<double> corners = corner_knots(curve);
  if (!corners.empty()) {
    // k: the arcs starting at or before the corner (at least the first: a corner is interior)
    const double t = corners.front();
    const auto k = static_cast<std::size_t>(std::upper_bound(starts.begin(), starts.end(), t) - starts.begin());
    pack(first, first + k - 1);
    if (starts[k - 1] == t) {  // at the join before arc k - 1
      pack(first + k - 1, last);
    } else {                   // inside arc k - 1, where its pieces join: that arc stays whole
      out_.push_back(chain_[first + k - 1]);
      pack(first + k, last);
    }
    return;
  }

  // measured: the curve's distance from each arc it stands for
  double deviation = 0.0;
  const NurbsView v = curve.view();
  for (std::size_t k = 0; k < starts.size(); ++k) {
    const double u0 = starts[k], u1 = k + 1 < starts.size() ? starts[k + 1] : curve.u_max();
    for (int j = 1; j < kDeviationSamples; ++j) {
      const Vec3 p = nurbs_point(v, u0 + (u1 - u0) * j / kDeviationSamples);
      deviation = std::max(deviation, distance_from_arc(chain_[first + k], p));
    }
  }
  if (!(deviation <= kDeviationShare * chain_[first].path_tolerance_mm)) {
    for (std::size_t k = first; k < last; ++k) out_.push_back(chain_[k]);
    return;
  }

  auto marks = std::make_shared<std::vector<LineMark>>();
  for (std::size_t k = 0; k < starts.size(); ++k) marks->push_back({starts[k], chain_[first + k].line});
  Move c = chain_[first];
  c.kind = MoveKind::kNurbs;
  c.end = chain_[last - 1].end;
  c.known = chain_[last - 1].known;
  c.packed_arcs = true;
  c.nurbs = std::make_shared<const NurbsCurve>(std::move(curve));
  c.line_marks = std::move(marks);
  out_.push_back(std::move(c));
  stats_.arcs += last - first;
  stats_.curves += 1;
  stats_.max_deviation_mm = std::max(stats_.max_deviation_mm, deviation);
}

}  // namespace pcnc
