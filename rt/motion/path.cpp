// path.cpp — evaluation and machine caps of lines, arcs and helices (see path.hpp).
#include "motion/path.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "config/joint_map.hpp"
#include "geometry/arc_limits.hpp"
#include "geometry/axis_slerp.hpp"
#include "geometry/kinematics_rates.hpp"
#include "geometry/axis_caps.hpp"
#include "geometry/plane.hpp"
#include "geometry/tangential_budget.hpp"
#include "motion/nurbs_follower.hpp"

namespace pcnc {

namespace {

double wrap_pi(double a) {
  constexpr double two_pi = 2.0 * std::numbers::pi;
  a = std::fmod(a, two_pi);
  if (a > std::numbers::pi) a -= two_pi;
  if (a <= -std::numbers::pi) a += two_pi;
  return a;
}

void line_caps(PreparedBlock& pb, const MachineConfig& cfg) {
  AxisLimits v{}, a{};
  for (int i = 0; i < kAxes; ++i) {
    v[i] = cfg.axes[i].max_velocity_mm_s;
    a[i] = cfg.axes[i].max_accel_mm_s2;
  }
  pb.v_machine = axis_cap(pb.dir_start, v);
  pb.accel = std::min(pb.accel, axis_cap(pb.dir_start, a));
}

// Arcs: the in-plane axes see the tangential acceleration plus the centripetal v²/r: the
// centripetal part gets at most kArcCentripetalShare of the smaller plane axis's
// acceleration, the tangential part what is left of its magnitude (geometry/arc_limits.hpp).
// The in-plane axes' velocity is bounded along the angles the arc sweeps, as the host plans it
// (the first plane axis carries at most max|sin θ| of the in-plane speed, the second max|cos θ|),
// plus the share a spiral's change of radius adds: a flat G18 arc that runs almost along X is
// not held to Z's velocity.
void arc_caps(PreparedBlock& pb, const MachineConfig& cfg) {
  const double r_min = std::min(pb.r0, pb.r1);
  const double r_max = std::max(pb.r0, pb.r1);
  const double q = r_max * std::abs(pb.sweep) / pb.length;                // in-plane share of speed
  const double h = std::abs(pb.end[pb.an] - pb.start[pb.an]) / pb.length;  // normal share
  const auto& A = cfg.axes;
  const double a_plane = std::min(A[pb.a1].max_accel_mm_s2, A[pb.a2].max_accel_mm_s2);
  const double spiral = r_min > 0.0 && std::abs(pb.sweep) > 0.0 ? std::abs(pb.r1 - pb.r0) / (std::abs(pb.sweep) * r_min) : 1.0;
  const double f1 = std::min(1.0, max_abs_sin(pb.theta0, pb.sweep) + spiral);
  const double f2 = std::min(1.0, max_abs_cos(pb.theta0, pb.sweep) + spiral);
  double v_plane = std::numeric_limits<double>::infinity();
  if (f1 > 0.0) v_plane = std::min(v_plane, A[pb.a1].max_velocity_mm_s / f1);
  if (f2 > 0.0) v_plane = std::min(v_plane, A[pb.a2].max_velocity_mm_s / f2);
  const ArcPlane plane = arc_plane(A[pb.a1].max_accel_mm_s2, A[pb.a2].max_accel_mm_s2, pb.theta0, pb.sweep);
  const ArcCaps c = pcnc::arc_caps(r_min, q, h, q > 1e-12 ? v_plane / q : 0.0, plane, A[pb.an].max_velocity_mm_s,
                                   A[pb.an].max_accel_mm_s2, pb.speed);
  pb.v_machine = c.speed;
  pb.accel = std::min(pb.accel, c.accel);
  pb.arc_a_plane = a_plane;
  pb.arc_q = q;
  pb.arc_r = r_min;
  pb.arc_a_normal = h > 1e-12 ? A[pb.an].max_accel_mm_s2 / h : std::numeric_limits<double>::infinity();
}

// A block that turns no joint: its joint rates are its tangents (the curvature of a plain arc is
// left to the arc's own caps, as the 3-axis junction rule leaves it).
void plain_joint_rates(PreparedBlock& pb) {
  for (int i = 0; i < kAxes; ++i) {
    pb.jrate_start[static_cast<std::size_t>(i)] = pb.dir_start[i];
    pb.jrate_end[static_cast<std::size_t>(i)] = pb.dir_end[i];
  }
}

}  // namespace

PreparedBlock prepare_block(const Block& b, const MachineConfig& cfg) {
  PreparedBlock pb;
  pb.kind = b.kind;
  pb.contouring = b.contouring != 0;
  pb.path_tolerance = std::isfinite(b.path_tolerance_mm) && b.path_tolerance_mm > 0.0f ? b.path_tolerance_mm : 0.0;
  pb.start = b.start;
  pb.end = b.end;
  pb.length = b.length;
  pb.speed = b.speed;
  pb.accel = b.accel;
  const bool moving = (b.kind == BlockKind::kLine || b.kind == BlockKind::kRapid || b.kind == BlockKind::kArc ||
                       b.kind == BlockKind::kNurbs || b.kind == BlockKind::kRuled);
  pb.motion = moving && b.length > 0.0;
  pb.v_first = pb.v_last = std::numeric_limits<double>::infinity();
  pb.brake_accel = pb.accel;
  pb.land = b.end;
  const bool straight = b.kind == BlockKind::kLine || b.kind == BlockKind::kRapid;
  if (straight) {
    const RotaryMotion& r = b.rotary;
    pb.tcp = r.tcp != 0;
    pb.angular = r.angular != 0;
    pb.rot_start = r.start;
    pb.rot_end = r.end;
    pb.rotary = pb.tcp || r.start != r.end;
    if (pb.tcp) pb.land = r.joint_end;
  }
  if (b.kind == BlockKind::kRuled) {
    // the RuledFollower runs it (executor.cpp): its schedule is the cap, the TCP joints its path
    const RotaryMotion& r = b.rotary;
    pb.tcp = pb.rotary = true;
    pb.contouring = false;
    pb.rot_start = r.start;
    pb.rot_end = r.end;
    pb.land = r.joint_end;
    pb.v_machine = pb.speed;
    pb.dir_start = normalized(b.dir_start);
    pb.dir_end = normalized(b.dir_end);
    pb.v_first = b.ruled.schedule_speed[0];
    pb.v_last = b.ruled.schedule_speed[std::clamp(b.ruled.schedule_count, 1, kMaxRuledSchedule) - 1];
    return pb;
  }
  if (!pb.motion) return pb;
  if (pb.rotary) {
    if (pb.angular) {
      pb.v_machine = std::numeric_limits<double>::infinity();
    } else {
      pb.dir_start = normalized(b.end - b.start);
      pb.dir_end = pb.dir_start;
      line_caps(pb, cfg);
    }
    if (pb.tcp) {
      pb.v_machine = pb.speed;
      pb.accel = b.accel;
    } else {
      for (int i = 0; i < kRotaryJoints; ++i) {
        const auto k = static_cast<std::size_t>(i);
        const double share = std::abs(pb.rot_end[k] - pb.rot_start[k]) / pb.length;  // rad per path unit
        if (!(share > 0.0) || !cfg.rotary[k]) continue;
        pb.v_machine = std::min(pb.v_machine, cfg.rotary[k]->max_velocity_rad_s / share);
        pb.accel = std::min(pb.accel, cfg.rotary[k]->max_accel_rad_s2 / share);
      }
      if (!pb.angular) {  // the joints run linearly with s: constant rates, no curvature
        for (int i = 0; i < kAxes; ++i) pb.jrate_start[static_cast<std::size_t>(i)] = (b.end[i] - b.start[i]) / pb.length;
        for (int i = 0; i < kRotaryJoints; ++i) {
          const auto k = static_cast<std::size_t>(i);
          pb.jrate_start[static_cast<std::size_t>(kAxes + i)] = (pb.rot_end[k] - pb.rot_start[k]) / pb.length;
        }
        pb.jrate_end = pb.jrate_start;
      }
    }
    pb.brake_accel = pb.accel;
    return pb;
  }
  if (b.kind == BlockKind::kNurbs) {
    // The host's feed schedule already holds every axis and curvature limit: it is the cap.
    const NurbsGeometry& g = b.nurbs;
    double vmax = 0.0;
    for (int i = 0; i < g.schedule_count; ++i) vmax = std::max(vmax, g.schedule_speed[i]);
    pb.v_machine = vmax;
    pb.v_first = g.schedule_speed[0];
    pb.v_last = g.schedule_speed[g.schedule_count - 1];
    pb.brake_accel = std::max(pb.accel, block_brake_capacity(g, 0.0) / pb.length);
    pb.ramp_accel = pb.accel;
    for (int i = 0; i < g.schedule_count; ++i) pb.ramp_accel = std::max(pb.ramp_accel, g.schedule_accel[i]);
    {
      const NurbsView view = view_of(g);
      pb.curv_start = nurbs_frame(view, view.u_min()).k;  // curvature vectors at the ends
      pb.curv_end = nurbs_frame(view, view.u_max()).k;
    }
    pb.dir_start = normalized(b.dir_start);
    pb.dir_end = normalized(b.dir_end);
    plain_joint_rates(pb);
    return pb;
  }
  if (b.kind == BlockKind::kArc) {
    pb.an = b.arc.normal_axis;
    pb.a1 = plane_axes(pb.an)[0];
    pb.a2 = plane_axes(pb.an)[1];
    pb.c1 = b.arc.center[pb.a1];
    pb.c2 = b.arc.center[pb.a2];
    const double s1 = b.start[pb.a1] - pb.c1, s2 = b.start[pb.a2] - pb.c2;
    const double e1 = b.end[pb.a1] - pb.c1, e2 = b.end[pb.a2] - pb.c2;
    pb.r0 = std::hypot(s1, s2);
    pb.r1 = std::hypot(e1, e2);
    pb.theta0 = std::atan2(s2, s1);
    // The block's sweep, corrected by the small difference between its stated end angle and
    // the end point's actual angle (checked to be within tolerance by check_block).
    const double theta_end = std::atan2(e2, e1);
    pb.sweep = b.arc.sweep + wrap_pi(theta_end - (pb.theta0 + b.arc.sweep));
    // The length of the curve actually run (a spiral when r1 != r0 within the tolerance), so
    // that the path speed is the true speed along it.
    pb.length = std::hypot(0.5 * (pb.r0 + pb.r1) * std::abs(pb.sweep), b.end[pb.an] - b.start[pb.an]);
    pb.dir_start = evaluate(pb, 0.0).tangent;
    pb.dir_end = evaluate(pb, pb.length).tangent;
    arc_caps(pb, cfg);
    pb.curv_start = evaluate(pb, 0.0).curvature;
    pb.curv_end = evaluate(pb, pb.length).curvature;
    // s runs uniformly in angle, so on a spiral the true speed is up to r_max/r_mean times the
    // parameter speed: scale the caps so the true speed never exceeds them.
    const double r_mean = 0.5 * (pb.r0 + pb.r1), r_max = std::max(pb.r0, pb.r1);
    if (r_max > r_mean) {
      const double f = r_mean / r_max;
      pb.speed *= f;
      pb.v_machine *= f;
      pb.accel *= f;
      pb.arc_f = f;
    }
  } else {
    pb.dir_start = normalized(b.end - b.start);
    pb.dir_end = pb.dir_start;
    line_caps(pb, cfg);
  }
  pb.brake_accel = pb.accel;
  pb.ramp_accel = pb.accel;
  plain_joint_rates(pb);
  return pb;
}

double arc_path_accel(const PreparedBlock& b, double v) {
  if (b.kind != BlockKind::kArc) return 0.0;
  const double f = b.arc_f;
  return f * arc_accel_at(b.arc_a_plane, b.arc_r, b.arc_q, b.arc_a_normal, kArcAccelMargin, v / f);
}

double arc_stretch_accel(const PreparedBlock& b, const ArcStretch& st, const MachineConfig& cfg, double v) {
  const double f = b.arc_f;  // the parameter speed over the true speed on a spiral
  const double by_axis = f * std::min(point_tangential_accel(st.here.tangent, st.here.curvature, cfg, v / f),
                                      point_tangential_accel(st.land.tangent, st.land.curvature, cfg, v / f));
  return std::max(arc_path_accel(b, v), by_axis);
}

ArcSweep arc_sweep(const PreparedBlock& b, const MachineConfig& cfg, double from) {
  ArcSweep w;
  const double u = b.length > 0.0 ? std::clamp(from / b.length, 0.0, 1.0) : 0.0;
  w.plane = arc_plane(kArcAccelMargin * cfg.axes[b.a1].max_accel_mm_s2, kArcAccelMargin * cfg.axes[b.a2].max_accel_mm_s2,
                      b.theta0 + b.sweep * u, b.sweep * (1.0 - u));
  // evaluate(): dp/du = (dr·cos θ − r·sin θ·sweep, dr·sin θ + r·cos θ·sweep, dn), curvature
  // r·sweep²/|dp/du|² along −(cos θ, sin θ), with r between r0 and r1
  const double sw = std::abs(b.sweep), dr = std::abs(b.r1 - b.r0), dn = std::abs(b.end[b.an] - b.start[b.an]);
  const double r_min = std::min(b.r0, b.r1), r_max = std::max(b.r0, b.r1);
  const double in_max = dr * dr + r_max * r_max * sw * sw;
  w.q = in_max > 0.0 ? std::sqrt(in_max / (in_max + dn * dn)) : 0.0;
  w.phi = r_min * sw > 0.0 ? dr / (r_min * sw) : std::numeric_limits<double>::infinity();
  const double low = r_min * r_min * sw * sw + dn * dn;
  w.curvature = low > 0.0 ? r_max * sw * sw / low : std::numeric_limits<double>::infinity();
  if (dn > 0.0) w.normal = kArcAccelMargin * cfg.axes[b.an].max_accel_mm_s2 * std::sqrt(low) / dn;
  return w;
}

double arc_sweep_accel(const PreparedBlock& b, const ArcSweep& w, double v) {
  if (!std::isfinite(w.phi) || !std::isfinite(w.curvature)) return 0.0;
  const double f = b.arc_f;  // the parameter speed over the true speed on a spiral
  const double c = (v / f) * (v / f) * w.curvature;
  double a = w.normal;
  const ArcPlane& p = w.plane;
  a = std::min({a, plane_axis_tangential_room(p.a1, c, w.q, w.phi, p.n1_lo, p.n1_hi),
                plane_axis_tangential_room(p.a2, c, w.q, w.phi, p.n2_lo, p.n2_hi)});
  return std::isfinite(a) ? f * a : 0.0;
}

double arc_stop_rule(const PreparedBlock& b, const ArcSweep& sweep, double distance, double v_exit, bool exact,
                     double dt, double k, double v) {
  const double acc = std::max({b.accel, arc_path_accel(b, v), arc_sweep_accel(b, sweep, v)});
  return exact ? stop_speed_exact(distance, acc, dt) : stop_speed(distance, v_exit, acc, dt, k);
}

double arc_stop_speed(const PreparedBlock& b, const MachineConfig& cfg, double distance, double v_exit, bool exact,
                      double cap, double dt, double k) {
  const ArcSweep sweep = arc_sweep(b, cfg, b.length - distance);
  auto rule = [&](double v) { return arc_stop_rule(b, sweep, distance, v_exit, exact, dt, k, v); };
  if (!std::isfinite(cap)) cap = b.v_machine;
  const double g_cap = rule(cap) - cap;
  if (g_cap >= 0.0) return cap;
  // The largest V with rule(V) >= V: g(V) = rule(V) − V falls from g(lo) >= 0 to g(cap) < 0
  // (the acceleration falls with V and the rule rises with it, so g falls at least as fast as
  // −V: the root lies within g(lo) of lo; at the last cycles of a flowing exit the rule falls
  // with the acceleration instead, g may not fall, and the bracket still closes on a V with
  // rule(V) >= V). It starts from rule(cap): where the rule falls with V, it is at least that
  // speed there (rule(cap) <= the root), and close below it as the rule changes slowly with V;
  // else from 0. Regula falsi with the Illinois step (the end that stays is halved in weight),
  // to 1e-8 of the cap: a few evaluations. `lo` always keeps rule(lo) >= lo: the speed returned
  // brakes in time.
  const double width = 1e-8 * cap;
  double lo = 0.0, hi = cap, g_lo = -1.0, g_hi = g_cap;
  const double v0 = g_cap + cap;
  if (v0 > 0.0) {
    const double g = rule(v0) - v0;
    (g >= 0.0 ? lo : hi) = v0;
    (g >= 0.0 ? g_lo : g_hi) = g;
  }
  if (lo == 0.0) g_lo = rule(0.0);
  if (!(g_lo > 0.0)) return lo;
  int kept = 0;  // which end stayed last: +1 hi, −1 lo
  for (int i = 0; i < 64 && hi - lo > width && g_lo > width; ++i) {
    double mid = lo + (hi - lo) * (g_lo / (g_lo - g_hi));
    // a step too close to an end brings the bracket in by no more than itself: keep steps
    // inside by a quarter of the target width (and bisect if the weights go astray)
    mid = std::clamp(mid, lo + 0.25 * width, hi - 0.25 * width);
    if (!(mid > lo && mid < hi)) mid = 0.5 * (lo + hi);
    const double g = rule(mid) - mid;
    if (g >= 0.0) {
      lo = mid;
      g_lo = g;
      if (kept == 1) g_hi *= 0.5;
      kept = 1;
    } else {
      hi = mid;
      g_hi = g;
      if (kept == -1) g_lo *= 0.5;
      kept = -1;
    }
  }
  return lo;
}

double curve_tangential_accel(const NurbsEval& e, const MachineConfig& cfg, double v) {
  const double d1 = norm(e.d1);
  if (!(d1 > 0.0)) return 0.0;
  const Vec3 t = (1.0 / d1) * e.d1;
  const Vec3 k = (1.0 / (d1 * d1)) * (e.d2 - dot(e.d2, t) * t);
  return point_tangential_accel(t, k, cfg, v);
}

double point_tangential_accel(const Vec3& t, const Vec3& k, const MachineConfig& cfg, double v) {
  AxisLimits room{};  // what each axis keeps beside the normal part
  for (std::size_t i = 0; i < static_cast<std::size_t>(kAxes); ++i) {
    room[i] = kArcAccelMargin * cfg.axes[i].max_accel_mm_s2 - v * v * std::abs(k[i]);
    if (room[i] <= 0.0) return 0.0;
  }
  return axis_cap(t, room);
}

void tcp_end_rates(PreparedBlock& pb, const Block& b, const MachineConfig& cfg, const Vec3& start_xyz) {
  if (!pb.tcp || pb.angular || !pb.motion) return;
  const Kinematics kin = kinematics_with_tool(cfg, b.rotary.tool_length);
  const AxisSlerp arc = make_axis_slerp(b.rotary.axis_start, b.rotary.axis_end);
  const double inv = 1.0 / pb.length;  // u = s/length
  auto at = [&](double u, const Joints& q, JointRate& rate, JointRate& curv) {
    const PoseRate d1{inv * (b.end - b.start), inv * slerp_axis_d1(arc, u)};
    const PoseRate d2{{0.0, 0.0, 0.0}, (inv * inv) * slerp_axis_d2(arc, u)};
    const Joints dq = joint_rates(kin, q, d1);
    const Joints ddq = joint_accels(kin, q, dq, d2);
    Vec3 x{};
    Rot3 r{};
    from_joints(cfg, dq, x, r);
    for (int i = 0; i < kAxes; ++i) rate[static_cast<std::size_t>(i)] = x[i];
    for (int i = 0; i < kRotaryJoints; ++i) rate[static_cast<std::size_t>(kAxes + i)] = r[static_cast<std::size_t>(i)];
    x = {};
    r = {};
    from_joints(cfg, ddq, x, r);
    for (int i = 0; i < kAxes; ++i) curv[static_cast<std::size_t>(i)] = x[i];
    for (int i = 0; i < kRotaryJoints; ++i) curv[static_cast<std::size_t>(kAxes + i)] = r[static_cast<std::size_t>(i)];
  };
  at(0.0, to_joints(cfg, start_xyz, b.rotary.start), pb.jrate_start, pb.jcurv_start);
  at(1.0, to_joints(cfg, b.rotary.joint_end, b.rotary.end), pb.jrate_end, pb.jcurv_end);
}

PathPoint evaluate(const PreparedBlock& b, double s) {
  PathPoint out;
  if (!b.motion) {
    out.p = b.end;
    return out;
  }
  const double u = std::clamp(s / b.length, 0.0, 1.0);
  if (b.kind != BlockKind::kArc) {
    out.p = u >= 1.0 ? b.end : b.start + u * (b.end - b.start);
    out.tangent = b.dir_start;
    return out;
  }
  const double th = b.theta0 + b.sweep * u;
  const double r = b.r0 + (b.r1 - b.r0) * u;
  const double c = std::cos(th), sn = std::sin(th);
  const double dn = b.end[b.an] - b.start[b.an];
  if (u >= 1.0) {
    out.p = b.end;
  } else {
    out.p[b.a1] = b.c1 + r * c;
    out.p[b.a2] = b.c2 + r * sn;
    out.p[b.an] = b.start[b.an] + dn * u;
  }
  // dp/du, then unit tangent; curvature from the circular part (r' terms are tiny).
  Vec3 d{};
  const double dr = b.r1 - b.r0;
  d[b.a1] = dr * c - r * sn * b.sweep;
  d[b.a2] = dr * sn + r * c * b.sweep;
  d[b.an] = dn;
  const double speed_u = norm(d);  // |dp/du|
  out.tangent = (1.0 / speed_u) * d;
  const double k = r * b.sweep * b.sweep / (speed_u * speed_u);
  out.curvature[b.a1] = -k * c;
  out.curvature[b.a2] = -k * sn;
  return out;
}

}  // namespace pcnc
