// arc_split.cpp — arcs cut into pieces that follow the plane axes' limits (see arc_split.hpp).
#include "gcode/arc_split.hpp"

#include <algorithm>
#include <cmath>

#include "geometry/plane.hpp"

namespace pcnc {

std::vector<Move> split_arc(const Move& m, int n) {
  if (m.kind != MoveKind::kArc || n <= 1) return {m};
  const auto pa = plane_axes(m.normal_axis);
  const auto a0 = static_cast<std::size_t>(pa[0]), a1 = static_cast<std::size_t>(pa[1]);
  const auto nk = static_cast<std::size_t>(m.normal_axis);
  const double theta0 = std::atan2(m.start[a1] - m.center[a1], m.start[a0] - m.center[a0]);
  const double r0 = std::hypot(m.start[a0] - m.center[a0], m.start[a1] - m.center[a1]);
  const double r1 = std::hypot(m.end[a0] - m.center[a0], m.end[a1] - m.center[a1]);
  std::vector<Move> out;
  out.reserve(static_cast<std::size_t>(n));
  Vec3 at = m.start;
  for (int k = 1; k <= n; ++k) {
    const double u = static_cast<double>(k) / n;
    Move p = m;
    p.start = at;
    if (k == n) {
      p.end = m.end;
    } else {
      const double th = theta0 + m.sweep * u, r = r0 + (r1 - r0) * u;
      p.end[a0] = m.center[a0] + r * std::cos(th);
      p.end[a1] = m.center[a1] + r * std::sin(th);
      p.end[nk] = m.start[nk] + (m.end[nk] - m.start[nk]) * u;
    }
    p.center[nk] = p.start[nk];
    p.radius = std::hypot(p.start[a0] - m.center[a0], p.start[a1] - m.center[a1]);
    p.sweep = m.sweep / n;
    if (m.inverse_time_s > 0.0) p.inverse_time_s = m.inverse_time_s / n;  // G93: the move's time shared
    out.push_back(p);
    at = p.end;
  }
  return out;
}

int arc_pieces(const Move& m, const MachineConfig& config) {
  // (an arc turns no rotary joint; one that did would need its turn shared between the pieces)
  if (m.kind != MoveKind::kArc || !m.contouring || m.tcp || m.rot_start != m.rot_end) return 1;
  const auto pa = plane_axes(m.normal_axis);
  const double a0 = config.axes[static_cast<std::size_t>(pa[0])].max_accel_mm_s2;
  const double a1 = config.axes[static_cast<std::size_t>(pa[1])].max_accel_mm_s2;
  if (!(std::abs(a0 - a1) > 1e-9 * std::max(a0, a1))) return 1;  // the same cap along any sweep
  const auto nk = static_cast<std::size_t>(m.normal_axis);
  const double helix = m.end[nk] - m.start[nk];
  const double length = std::hypot(m.radius * std::abs(m.sweep), helix);
  const double by_sweep = std::ceil(std::abs(m.sweep) / kArcPieceSweep - 1e-9);
  const double by_length = std::floor(length / kArcPieceMinMm);
  const double n = std::min(by_sweep, by_length);
  return n >= 2.0 && n <= 4096.0 ? static_cast<int>(n) : 1;
}

bool ArcSplitter::next(const std::function<bool(Move&)>& pull, Move& out) {
  if (pending_.empty()) {
    Move m;
    if (!pull(m)) return false;
    const int n = arc_pieces(m, config_);
    if (n <= 1) {
      out = std::move(m);
      return true;
    }
    for (Move& p : split_arc(m, n)) pending_.push_back(std::move(p));
  }
  out = std::move(pending_.front());
  pending_.pop_front();
  return true;
}

}  // namespace pcnc
