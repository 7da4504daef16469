// preflight.cpp — soft limits, extents and feed time of a whole program, streaming.
#include "gcode/preflight.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "geometry/nurbs.hpp"
#include "gcode/nurbs_move.hpp"
#include "geometry/ruled_model.hpp"
#include "ipc/block_ruled.hpp"

namespace pcnc {
namespace {
constexpr double kLimitEps = 1e-6;  // mm: rounding of the program's own numbers

std::string mm_text(double v) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.4f", v);
  return buf;
}
}  // namespace

double move_length(const Move& m) {
  if (m.kind == MoveKind::kArc) {
    const auto nk = static_cast<std::size_t>(m.normal_axis);
    const double helix = m.end[nk] - m.start[nk];
    return std::hypot(m.radius * m.sweep, helix);
  }
  if (m.kind == MoveKind::kRapid || m.kind == MoveKind::kLine) return norm(m.end - m.start);
  if (m.kind == MoveKind::kNurbs && m.nurbs) {
    const NurbsView v = m.nurbs->view();
    return nurbs_arc_length(v, v.u_min(), v.u_max());
  }
  if (m.kind == MoveKind::kRuled && m.ruled) {
    return hermite_arc_length(HermiteView{m.ruled->directrix.data(), static_cast<int>(m.ruled->directrix.size())});
  }
  return 0.0;
}

Preflight::Preflight(const MachineConfig& config, DiagnosticSink& sink, bool check_limits)
    : config_(config), sink_(sink), check_limits_(check_limits) {}

void Preflight::check_point(const Move& m, const Vec3& p) {
  all_.add(p);
  if (!m.machine_frame) fit_.add(p, m.known);
  if (!check_limits_) return;
  for (int i = 0; i < kAxes; ++i) {
    const auto k = static_cast<std::size_t>(i);
    const AxisConfig& a = config_.axes[k];
    const bool below = p[k] < a.travel_min_mm - kLimitEps;
    const bool above = p[k] > a.travel_max_mm + kLimitEps;
    if (!below && !above) continue;
    std::uint64_t& count = violations_[static_cast<std::size_t>(2 * i + (above ? 1 : 0))];
    if (count++ == 0) {
      std::string what = std::string(1, axis_name(i)) + " " + mm_text(p[k]) + " mm (machine) is " +
                         (above ? "above the travel maximum " + mm_text(a.travel_max_mm)
                                : "below the travel minimum " + mm_text(a.travel_min_mm)) +
                         " mm";
      if (m.kind == MoveKind::kArc && p != m.end) what += " (arc extreme point)";
      if (m.kind == MoveKind::kNurbs && p != m.end) what += " (a point of the NURBS curve)";
      what +=
          m.machine_frame
              ? "; expected a machine coordinate inside the travel"
              : "; expected the program to fit the travel after the work offset (use --offset, or --fit to scale it)";
      sink_.error(m.line, m.column, what);
    }
  }
}

// A curve lies within its control points' box (positive weights: the convex hull property).
// When that box, with the end point, is inside the travel and inside what the extents already
// hold, the curve can neither leave the travel nor move the extents, nor does its polygon need
// refining: finding its extreme points would change nothing. Gates_combined_R12.nc: most of its
// curves, 8 % of the check's instructions; LHchips4.ngc, whose passes step outwards, about a
// fifth of them.
bool Preflight::within_seen(const Move& m) const {
  const NurbsCurve& c = *m.nurbs;
  if (c.points.empty() || std::any_of(c.weights.begin(), c.weights.end(), [](double w) { return !(w > 0.0); })) return false;
  Vec3 lo = m.end, hi = m.end;
  for (const Vec3& p : c.points) {
    for (std::size_t k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], p[k]);
      hi[k] = std::max(hi[k], p[k]);
    }
  }
  for (int i = 0; i < kAxes; ++i) {
    const auto k = static_cast<std::size_t>(i);
    if (lo[k] < all_.min[k] || hi[k] > all_.max[k]) return false;
    if (!m.machine_frame && ((m.known >> i) & 1u) && (lo[k] < fit_.min[k] || hi[k] > fit_.max[k])) return false;
    if (check_limits_ && (lo[k] < config_.axes[k].travel_min_mm || hi[k] > config_.axes[k].travel_max_mm)) return false;
  }
  return true;
}

// A NURBS move: the curve itself (its extreme points) against the travel, and, as the block
// stream will need it, its control polygon brought inside the travel by knot insertion.
void Preflight::add_nurbs(const Move& m) {
  ++moves_;
  if (within_seen(m)) {
    if (m.feed_mm_s > 0.0) feed_time_s_ += move_length(m) / m.feed_mm_s;
    last_ = m.end;
    return;
  }
  nurbs_extreme_points(*m.nurbs, points_);
  // The curve's lowest and highest coordinate per axis (two corners of its bounding box):
  // one soft-limit report per axis and side per curve, naming the true extreme.
  Vec3 lo = m.end, hi = m.end;
  for (const Vec3& p : points_) {
    for (std::size_t i = 0; i < 3; ++i) {
      lo[i] = std::min(lo[i], p[i]);
      hi[i] = std::max(hi[i], p[i]);
    }
  }
  std::uint64_t before = 0;
  for (const std::uint64_t v : violations_) before += v;
  check_point(m, m.end);
  check_point(m, lo);
  check_point(m, hi);
  std::uint64_t after = 0;
  for (const std::uint64_t v : violations_) after += v;
  if (check_limits_ && after == before) {
    const double margin = nurbs_travel_margin(config_);
    bool polygon_out = false;
    for (const Vec3& p : m.nurbs->points) {
      for (int i = 0; i < kAxes; ++i) {
        const auto k = static_cast<std::size_t>(i);
        if (p[k] < config_.axes[k].travel_min_mm - margin || p[k] > config_.axes[k].travel_max_mm + margin)
          polygon_out = true;
      }
    }
    if (polygon_out) {
      NurbsCurve c = *m.nurbs;
      if (std::string why = refine_into_travel(c, config_, margin); !why.empty()) sink_.error(m.line, m.column, why);
    }
  }
  if (m.feed_mm_s > 0.0) feed_time_s_ += move_length(m) / m.feed_mm_s;
  last_ = m.end;
}

void Preflight::add(const Move& m) {
  if (m.kind == MoveKind::kNurbs && m.nurbs) {
    add_nurbs(m);
    return;
  }
  if (m.kind == MoveKind::kRuled && m.ruled) {
    add_ruled(m);
    return;
  }
  if (m.kind != MoveKind::kRapid && m.kind != MoveKind::kLine && m.kind != MoveKind::kArc) {
    last_ = m.end;
    return;
  }
  const double length = move_length(m);
  if (length > 1e-12 || m.kind == MoveKind::kArc) ++moves_;
  if (fit_poses_) add_fit_pose(m);
  if (m.tcp || m.rot_start != m.rot_end) {
    add_rotary(m);  // under TCP the tip's points are not the axes': the joints are checked there
    if (m.tcp) {
      all_.add(m.end);
      if (!m.machine_frame) fit_.add(m.end, m.known);
      if (m.kind != MoveKind::kRapid && m.feed_mm_s > 0.0) feed_time_s_ += length / m.feed_mm_s;
      last_ = m.end;
      return;
    }
  }
  for_each_extreme(m, [&](const Vec3& p) { check_point(m, p); });
  if (m.kind != MoveKind::kRapid && m.feed_mm_s > 0.0) feed_time_s_ += length / m.feed_mm_s;
  last_ = m.end;
}

void Preflight::finish() {
  for (int i = 0; i < kAxes; ++i) {
    for (int side = 0; side < 2; ++side) {
      const std::uint64_t n = violations_[static_cast<std::size_t>(2 * i + side)];
      if (n > 1) {
        sink_.error(0, 0,
                    std::to_string(n) + " points leave the travel " +
                        (side ? "above the maximum" : "below the minimum") + " of axis " + axis_name(i) +
                        " (the first is reported above)");
      }
    }
  }
}

FitResult fit_to_travel(const Box& box, const Vec3& offset, const MachineConfig& config, double tool_radius_mm) {
  FitResult r;
  r.offset = offset;
  double scale = 1.0;
  for (int i = 0; i < kAxes; ++i) {
    if (!box.has(i)) continue;
    const auto k = static_cast<std::size_t>(i);
    const double ext = box.max[k] - box.min[k];
    const double travel = config.axes[k].travel_max_mm - config.axes[k].travel_min_mm;
    const double m = 2.0 * tool_radius_mm;
    if (ext > travel) scale = std::min(scale, m > 0.0 && travel > m && ext > m ? (travel - m) / (ext - m) : travel / ext);
  }
  r.scale = scale;
  // box is in machine coordinates under (offset, scale 1): program q = p - offset.
  for (int i = 0; i < kAxes; ++i) {
    if (!box.has(i)) continue;
    const auto k = static_cast<std::size_t>(i);
    const double qmid = 0.5 * (box.min[k] + box.max[k]) - offset[k];
    const double tmid = 0.5 * (config.axes[k].travel_min_mm + config.axes[k].travel_max_mm);
    r.offset[k] = tmid - scale * qmid;
  }
  return r;
}

}  // namespace pcnc
