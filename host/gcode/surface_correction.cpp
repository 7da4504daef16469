// surface_correction.cpp — the surface-correction stage (see surface_correction.hpp).
#include "gcode/surface_correction.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "gcode/nurbs_rough.hpp"  // distance_to_segment
#include "geometry/nurbs.hpp"
#include "geometry/plane.hpp"

namespace pcnc {
namespace {

// The smallest X/Y distance between neighbouring control points: the scale of the surface's detail.
double control_spacing(const BSplineSurface& s) {
  double d = INFINITY;
  for (int j = 0; j < s.count_v; ++j)
    for (int i = 0; i < s.count_u; ++i) {
      const Vec3& p = s.point(i, j);
      if (i + 1 < s.count_u) d = std::min(d, std::hypot(s.point(i + 1, j)[0] - p[0], s.point(i + 1, j)[1] - p[1]));
      if (j + 1 < s.count_v) d = std::min(d, std::hypot(s.point(i, j + 1)[0] - p[0], s.point(i, j + 1)[1] - p[1]));
    }
  return std::isfinite(d) && d > 1e-6 ? d : 1e-3;
}

// The point at fraction t of an arc move (center, signed sweep, helix along the normal).
Vec3 arc_point(const Move& m, double t) {
  const auto ax = plane_axes(m.normal_axis);
  const auto a = static_cast<std::size_t>(ax[0]), b = static_cast<std::size_t>(ax[1]);
  const auto n = static_cast<std::size_t>(m.normal_axis);
  const double a0 = std::atan2(m.start[b] - m.center[b], m.start[a] - m.center[a]) + m.sweep * t;
  Vec3 p = m.start;
  p[a] = m.center[a] + m.radius * std::cos(a0);
  p[b] = m.center[b] + m.radius * std::sin(a0);
  p[n] = m.start[n] + t * (m.end[n] - m.start[n]);
  return p;
}

}  // namespace

SurfaceCorrection::SurfaceCorrection(std::shared_ptr<const BSplineSurface> surface, double reference_z,
                                     double tolerance_mm, DiagnosticSink* sink)
    : surface_(std::move(surface)),
      reference_(reference_z),
      tolerance_(tolerance_mm > 0.0 ? tolerance_mm : 0.001),
      sink_(sink),
      sample_step_(0.25 * control_spacing(*surface_)) {}

double SurfaceCorrection::reference_at(const BSplineSurface& surface, const Vec3& work_origin) {
  return surface_height(surface, work_origin[0], work_origin[1]).z;
}

double SurfaceCorrection::offset_at(double x, double y) const { return surface_height(*surface_, x, y).z - reference_; }

bool SurfaceCorrection::next(const std::function<bool(Move&)>& pull, Move& out) {
  while (next_ >= pending_.size()) {
    Move m;
    if (!pull(m)) return false;
    pending_.clear();
    next_ = 0;
    correct(m);
  }
  out = pending_[next_++];
  last_end_ = out.end;
  have_last_ = true;
  return true;
}

void SurfaceCorrection::correct(const Move& m) {
  if (!have_last_) {
    last_end_ = m.start;  // the machine's position: where the first move starts, uncorrected
    have_last_ = true;
  }
  switch (m.kind) {
    case MoveKind::kRapid:
    case MoveKind::kLine:
      if (m.machine_frame) break;
      split(m, [&m](double t) { return m.start + t * (m.end - m.start); });
      return;
    case MoveKind::kArc:
      split(m, [&m](double t) { return arc_point(m, t); });
      return;
    case MoveKind::kNurbs:
      if (m.nurbs) {
        const NurbsView c = m.nurbs->view();
        split(m, [c](double t) { return nurbs_point(c, c.u_min() + t * (c.u_max() - c.u_min())); });
        return;
      }
      break;
    case MoveKind::kRuled:  // a 5-axis piece under TCP: not corrected (docs/ruled-surface.md)
      break;
    case MoveKind::kDwell:
    case MoveKind::kPause:
    case MoveKind::kEnd: {
      Move still = m;  // stays where the machine is
      still.start = still.end = last_end_;
      pending_.push_back(still);
      return;
    }
  }
  Move as_is = m;
  as_is.start = last_end_;
  pending_.push_back(as_is);
}

void SurfaceCorrection::split(const Move& m, const std::function<Vec3(double)>& path) {
  bool outside = false;
  auto on_surface = [&](double t) {
    Vec3 p = path(t);
    const SurfaceHeight h = surface_height(*surface_, p[0], p[1]);
    outside = outside || !h.inside;
    p[2] += h.z - reference_;
    return p;
  };
  // A move that does not start on the corrected path (the first, or one after a machine-frame
  // move) is followed as the corrected path plus the start's difference fading out along it.
  const Vec3 start_gap = last_end_ - on_surface(0.0);
  auto lifted = [&](double t) { return on_surface(t) + (1.0 - t) * start_gap; };
  // Pieces [t0, t1] on a stack, the first on top; each is kept when every sample of the
  // lifted path lies within the tolerance of its chord, else bisected.
  struct Piece {
    double t0, t1;
    Vec3 a, b;
    int depth;
  };
  std::vector<Piece> stack{{0.0, 1.0, last_end_, lifted(1.0), 0}};
  const Vec3 end = stack.back().b;
  Move piece = m;
  if (m.kind == MoveKind::kArc || m.kind == MoveKind::kNurbs) {
    piece.kind = MoveKind::kLine;
    piece.nurbs.reset();
    piece.radius = piece.sweep = 0.0;
    piece.center = {};
  }
  while (!stack.empty()) {
    const Piece p = stack.back();
    stack.pop_back();
    // samples: no farther apart than sample_step_ along the chord in X/Y, and at least 3
    const Vec3 pa = path(p.t0), pb = path(p.t1);
    const double reach = std::hypot(pb[0] - pa[0], pb[1] - pa[1]) +
                         (m.kind == MoveKind::kLine || m.kind == MoveKind::kRapid ? 0.0 : norm(pb - pa));
    const int samples = std::clamp(static_cast<int>(std::ceil(reach / sample_step_)), 3, 64);
    bool fits = true;
    for (int i = 1; i <= samples && fits; ++i) {
      const double t = p.t0 + (p.t1 - p.t0) * i / (samples + 1);
      fits = distance_to_segment(lifted(t), p.a, p.b) <= tolerance_;
    }
    if (fits || p.depth >= kMaxDepth) {
      piece.start = p.a;
      piece.end = p.b;
      pending_.push_back(piece);
      continue;
    }
    const double tm = 0.5 * (p.t0 + p.t1);
    const Vec3 mid = lifted(tm);
    stack.push_back({tm, p.t1, mid, p.b, p.depth + 1});  // second half below the first
    stack.push_back({p.t0, tm, p.a, mid, p.depth + 1});
  }
  pending_.back().end = end;
  // The joints inside one programmed move are no corners: they flow (M21's rule, turns under
  // the contouring angle) even under M22/G61, which stops only where the program's move ends.
  for (std::size_t i = 0; i + 1 < pending_.size(); ++i) pending_[i].contouring = true;
  if (outside && !warned_outside_ && sink_) {
    warned_outside_ = true;
    sink_->warning(m.line, m.column, "surface-outside",
                   "this move leaves the measured surface's X/Y footprint; its correction is held at the surface's "
                   "edge there (probe a larger grid to cover the program)");
  }
}

}  // namespace pcnc
