// ideal_planner.cpp — the junction-deviation planner with unlimited look-ahead (ideal_planner.hpp):
// moves -> straight segments -> junction speeds -> forward and backward passes -> trapezoids.

#include "report/ideal_planner.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "geometry/axis_caps.hpp"
#include "geometry/junction_deviation.hpp"
#include "geometry/nurbs.hpp"
#include "geometry/plane.hpp"

namespace pcnc {
namespace {

constexpr double kIdealInf = std::numeric_limits<double>::infinity();
const double kBendCos = std::cos(10.0 * 3.14159265358979323846 / 180.0);  // a bend turns by less than 10°

struct Segment {
  Vec3 u{};              // unit direction (an arc's: its tangent at the start)
  Vec3 u_end{};          // unit direction at the end (a line's: u; an arc's: its end tangent)
  bool arc = false;      // a whole arc: its junctions are not a polyline's bends
  double length = 0.0;   // mm
  double v_max = 0.0;    // mm/s: feed and axes
  double a_max = 0.0;    // mm/s²: the axes' acceleration along u
  bool stop_after = false;  // the move does not contour, or a dwell/pause follows
  int line = 0;             // the move's source line
  double time = 0.0;        // planned: s
};

class Cutter {
 public:
  Cutter(const MachineConfig& config, const IdealPlannerOptions& options) : options_(options) {
    for (std::size_t i = 0; i < static_cast<std::size_t>(kAxes); ++i) {
      velocity_[i] = config.axes[i].max_velocity_mm_s;
      accel_[i] = config.axes[i].max_accel_mm_s2;
    }
  }

  // A straight piece from `a` to `b` at most at `feed` (0: the axes' rapid).
  void piece(const Vec3& a, const Vec3& b, double feed) {
    const Vec3 d = b - a;
    const double l = norm(d);
    if (l <= 1e-12) return;
    Segment s;
    s.u = (1.0 / l) * d;
    s.length = l;
    s.v_max = axis_cap(s.u, velocity_);
    if (feed > 0.0) s.v_max = std::min(s.v_max, feed);
    s.a_max = axis_cap(s.u, accel_);
    s.u_end = s.u;
    s.line = line_;
    segments_.push_back(s);
  }

  void stop_here() {
    if (!segments_.empty()) segments_.back().stop_after = true;
  }

  void arc(const Move& m) {
    if (options_.arcs_as_chords) {
      chords(m);
    } else {
      whole_arc(m);
    }
  }

  // An arc as one segment: at most at sqrt(A·r), A the smaller plane axis's acceleration, and
  // within every axis's velocity and acceleration wherever its tangent points (in the plane the
  // tangent's share is at most r·|sweep| / L on each plane axis, on the normal axis |h| / L).
  void whole_arc(const Move& m) {
    const auto ax = plane_axes(m.normal_axis);
    const auto n = static_cast<std::size_t>(m.normal_axis);
    const auto i0 = static_cast<std::size_t>(ax[0]);
    const auto i1 = static_cast<std::size_t>(ax[1]);
    const double r = m.radius;
    const double h = m.end[n] - m.start[n];
    const double planar = r * std::fabs(m.sweep);
    Segment s;
    s.length = std::hypot(planar, h);
    if (s.length <= 1e-12) return;
    const double sign = m.sweep >= 0.0 ? 1.0 : -1.0;
    const auto tangent = [&](const Vec3& p) {
      Vec3 t{};
      t[i0] = -sign * (p[i1] - m.center[i1]) * std::fabs(m.sweep);
      t[i1] = sign * (p[i0] - m.center[i0]) * std::fabs(m.sweep);
      t[n] = h;
      return normalized(t);
    };
    s.u = tangent(m.start);
    s.u_end = tangent(m.end);
    s.arc = true;
    const double in_plane = planar / s.length, along_normal = std::fabs(h) / s.length;
    const auto cap = [&](const AxisLimits& lim) {
      double c = std::min(lim[i0], lim[i1]) / std::max(in_plane, 1e-12);
      if (along_normal > 1e-12) c = std::min(c, lim[n] / along_normal);
      return c;
    };
    const double plane_accel = std::min(accel_[i0], accel_[i1]);
    s.v_max = std::min(cap(velocity_), std::sqrt(plane_accel * r));
    if (m.feed_mm_s > 0.0) s.v_max = std::min(s.v_max, m.feed_mm_s);
    s.a_max = cap(accel_);
    s.line = line_;
    segments_.push_back(s);
  }

  // An arc as chords of at most the chord tolerance's sagitta (grbl's arc segments).
  void chords(const Move& m) {
    const auto ax = plane_axes(m.normal_axis);
    const auto n = static_cast<std::size_t>(m.normal_axis);
    const auto i0 = static_cast<std::size_t>(ax[0]);
    const auto i1 = static_cast<std::size_t>(ax[1]);
    const double a0 = std::atan2(m.start[i1] - m.center[i1], m.start[i0] - m.center[i0]);
    const double r = m.radius;
    const double tol = std::min(options_.chord_tolerance_mm, r);
    const double step = r > 0.0 ? 2.0 * std::acos(1.0 - tol / r) : kIdealInf;
    const int count = std::max(1, static_cast<int>(std::ceil(std::fabs(m.sweep) / step)));
    Vec3 prev = m.start;
    for (int k = 1; k <= count; ++k) {
      const double f = static_cast<double>(k) / count;
      Vec3 p = m.end;
      if (k < count) {
        const double a = a0 + f * m.sweep;
        p[i0] = m.center[i0] + r * std::cos(a);
        p[i1] = m.center[i1] + r * std::sin(a);
        p[n] = m.start[n] + f * (m.end[n] - m.start[n]);
      }
      piece(prev, p, m.feed_mm_s);
      prev = p;
    }
  }

  // A curve: chords by halving until each chord's midpoint is within the tolerance.
  void curve(const Move& m) {
    const NurbsView c = m.nurbs->view();
    const double u0 = c.u_min(), u1 = c.u_max();
    const int spans = std::max(1, c.count - c.degree);
    Vec3 prev = m.start;
    double u = u0;
    double h = (u1 - u0) / (8.0 * spans);
    while (u < u1) {
      double next = std::min(u1, u + h);
      for (;;) {
        const Vec3 p = nurbs_point(c, next);
        const Vec3 mid = nurbs_point(c, 0.5 * (u + next));
        const Vec3 chord = p - prev;
        const double l = norm(chord);
        const double sag = l > 1e-12 ? norm(cross(mid - prev, chord)) / l : norm(mid - prev);
        if (sag <= options_.chord_tolerance_mm || next - u < 1e-9 * (u1 - u0)) break;
        next = u + 0.5 * (next - u);
      }
      const Vec3 p = next >= u1 ? m.end : nurbs_point(c, next);
      piece(prev, p, m.feed_mm_s);
      h = 2.0 * (next - u);
      prev = p;
      u = next;
    }
  }

  void set_line(int line) { line_ = line; }
  std::vector<Segment>& segments() { return segments_; }
  const AxisLimits& accel() const { return accel_; }

 private:
  IdealPlannerOptions options_;
  AxisLimits velocity_{};
  AxisLimits accel_{};
  std::vector<Segment> segments_;
  int line_ = 0;
};

// The junction-deviation speed between two segments (geometry/junction_deviation.hpp), within
// both segments' speeds.
double junction_speed(const Segment& in, const Segment& out, const AxisLimits& accel, double tol) {
  return std::min({junction_deviation_speed(in.u_end, out.u, accel, tol), in.v_max, out.v_max});
}

// Time over a segment of length l from v0 to v1 with top speed vt and acceleration a.
double trapezoid_time(double l, double v0, double v1, double vt, double a) {
  const double vp = std::min(vt, std::sqrt((2.0 * a * l + v0 * v0 + v1 * v1) / 2.0));
  const double d_up = (vp * vp - v0 * v0) / (2.0 * a);
  const double d_down = (vp * vp - v1 * v1) / (2.0 * a);
  const double cruise = std::max(0.0, l - d_up - d_down);
  return (vp - v0) / a + (vp - v1) / a + (vp > 0.0 ? cruise / vp : 0.0);
}

// The acceleration a junction's speed v asks of the curve the programmed points draw there:
// v² over the circumradius of the junction and its neighbours' far ends (a bend of a fillet or
// an arc's chords), against the axes' acceleration along the change of direction.
double bend_radius(const Segment& in, const Segment& out) {
  const Vec3 b = in.length * in.u;
  const Vec3 c = b + out.length * out.u;
  const double area2 = norm(cross(b, c));
  if (area2 <= 1e-15) return kIdealInf;
  return norm(b) * norm(c - b) * norm(c) / (2.0 * area2);
}

double bend_ratio(const Segment& in, const Segment& out, double v, const AxisLimits& accel) {
  const double rho = bend_radius(in, out);
  if (!std::isfinite(rho)) return 0.0;
  return v * v / rho / axis_cap(normalized(out.u - in.u), accel);
}

// A bend: two straight segments (not a whole arc) that turn by less than 10°.
bool is_bend(const Segment& in, const Segment& out) {
  return !in.arc && !out.arc && dot(in.u, out.u) >= kBendCos;
}

// The time of one run of segments that starts and ends at rest.
double run_time(std::vector<Segment>& s, std::size_t first, std::size_t last,
                const AxisLimits& accel, double tol, bool keep_bends, std::uint64_t* stops,
                std::vector<double>* bends) {
  const std::size_t n = last - first;
  std::vector<double> v(n + 1, 0.0);  // speeds at the junctions; v[0], v[n] = 0
  for (std::size_t k = 1; k < n; ++k) {
    const Segment& in = s[first + k - 1];
    const Segment& out = s[first + k];
    v[k] = junction_speed(in, out, accel, tol);
    if (keep_bends && is_bend(in, out)) {
      v[k] = std::min(v[k], std::sqrt(axis_cap(normalized(out.u - in.u), accel) * bend_radius(in, out)));
    }
    if (v[k] <= 0.0) ++*stops;
  }
  for (std::size_t k = 0; k < n; ++k) {
    const Segment& g = s[first + k];
    v[k + 1] = std::min(v[k + 1], std::sqrt(v[k] * v[k] + 2.0 * g.a_max * g.length));
  }
  for (std::size_t k = n; k-- > 0;) {
    const Segment& g = s[first + k];
    v[k] = std::min(v[k], std::sqrt(v[k + 1] * v[k + 1] + 2.0 * g.a_max * g.length));
  }
  double t = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    Segment& g = s[first + k];
    g.time = trapezoid_time(g.length, v[k], v[k + 1], g.v_max, g.a_max);
    t += g.time;
  }
  for (std::size_t k = 1; k < n; ++k) {
    const Segment& in = s[first + k - 1];
    const Segment& out = s[first + k];
    if (is_bend(in, out)) bends->push_back(bend_ratio(in, out, v[k], accel));
  }
  return t;
}

}  // namespace

IdealPlan ideal_planner_time(const std::vector<Move>& moves, const MachineConfig& config,
                             const IdealPlannerOptions& options) {
  IdealPlan plan;
  Cutter cut(config, options);
  for (const Move& m : moves) {
    cut.set_line(m.line);
    const bool rotary = m.tcp || m.rot_start != m.rot_end;
    switch (m.kind) {
      case MoveKind::kRapid:
      case MoveKind::kLine:
        if (rotary) {
          ++plan.unmodelled_moves;
          cut.stop_here();
          break;
        }
        cut.piece(m.start, m.end, m.kind == MoveKind::kRapid ? 0.0 : m.feed_mm_s);
        break;
      case MoveKind::kArc: cut.arc(m); break;
      case MoveKind::kNurbs:
        if (m.nurbs) cut.curve(m);
        break;
      case MoveKind::kDwell:
        plan.time_s += m.dwell_s;
        cut.stop_here();
        break;
      case MoveKind::kPause: cut.stop_here(); break;
      case MoveKind::kRuled:
        ++plan.unmodelled_moves;
        cut.stop_here();
        break;
      case MoveKind::kEnd: break;
    }
    if (!m.contouring && (m.kind == MoveKind::kLine || m.kind == MoveKind::kArc || m.kind == MoveKind::kNurbs ||
                          m.kind == MoveKind::kRapid)) {
      cut.stop_here();
    }
  }
  std::vector<Segment>& s = cut.segments();
  plan.segments = s.size();
  std::size_t first = 0;
  std::vector<double> bends;
  for (std::size_t k = 0; k < s.size(); ++k) {
    plan.length_mm += s[k].length;
    if (s[k].stop_after || k + 1 == s.size()) {
      plan.time_s += run_time(s, first, k + 1, cut.accel(), options.tolerance_mm, options.keep_bend_limits, &plan.stops,
                              &bends);
      ++plan.stops;
      first = k + 1;
    }
  }
  for (const Segment& g : s) {
    if (plan.line_times.empty() || plan.line_times.back().line != g.line) plan.line_times.push_back({g.line, 0.0});
    plan.line_times.back().time_s += g.time;
  }
  plan.bends = bends.size();
  if (!bends.empty()) {
    std::sort(bends.begin(), bends.end());
    plan.bend_accel_median = bends[bends.size() / 2];
    plan.bend_accel_max = bends.back();
    plan.bends_over_limit = static_cast<std::uint64_t>(
        bends.end() - std::upper_bound(bends.begin(), bends.end(), 1.0 + 1e-9));
  }
  return plan;
}

}  // namespace pcnc
