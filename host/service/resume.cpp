// resume.cpp — the remaining part of an interrupted block (see resume.hpp).
#include "service/resume.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "gcode/move.hpp"
#include "gcode/nurbs_schedule.hpp"
#include "gcode/preprocessor.hpp"
#include "gcode/ruled_move.hpp"
#include "config/joint_map.hpp"
#include "geometry/kinematics.hpp"
#include "ipc/block_ruled.hpp"
#include "geometry/nurbs.hpp"
#include "geometry/tangential_budget.hpp"
#include "ipc/block_nurbs.hpp"

namespace pcnc {
namespace {

std::optional<Continuation> fail(std::string* why, std::string text) {
  if (why) *why = std::move(text);
  return std::nullopt;
}

// A NURBS block from the parameter u* whose point is `at`: the curve cut there (knot
// insertion to multiplicity p, then the part [u*, u_end] kept, same parametrisation), and
// the block's own feed schedule cut at u* (its value at u* read as the rt reads it, linear
// between points; nothing raised). The schedule holds the geometric limits only: the rt's
// follower ramps from the speed it enters with, which is rest for the first block of the
// resumed program, and to the end speed the next block allows, as in the original. The new
// first point's acceleration is the smaller of its two neighbours' (as the rt reads it), and
// its speed and acceleration are checked against the axes at u* itself (as the block check
// does): lowered where the curve between the two points asks for less.
std::optional<Continuation> continue_nurbs(const Block& b, const Vec3& at, double tol, double skip_tol,
                                           const MachineConfig& config, std::string* why) {
  Continuation c;
  const NurbsCurve curve = from_geometry(b.nurbs);
  if (std::string err = validate(curve); !err.empty()) return fail(why, "the interrupted NURBS block is invalid: " + err);
  const NurbsView v = curve.view();
  double dist = 0.0;
  double u = nurbs_project(v, at, &dist, 64);
  if (!(dist <= tol)) {
    return fail(why, "the machine is not on the interrupted NURBS curve (off by " + std::to_string(dist) + " mm)");
  }
  if (nurbs_arc_length(v, u, v.u_max()) <= skip_tol) {
    c.skip = true;
    return c;
  }
  // A parameter a rounding error away from a knot is that knot (no sliver spans).
  const double snap = 1e-12 * (v.u_max() - v.u_min());
  for (const double k : curve.knots) {
    if (std::abs(u - k) <= snap) u = k;
  }
  NurbsCurve tail = u > v.u_min() ? nurbs_segment(curve, u, v.u_max()) : curve;
  // The machine may stand off the curve by the rt's corner blend (docs/rt-executor.md, "Corner
  // blending": at most 40 % of the block's path tolerance): the curve begins where it stands (its
  // first control point moved there, which bends only its first span, by at most that much), as
  // the rt's block check asks of a block's start.
  tail.points.front() = at;
  Block n{};
  n.line = b.line;
  n.kind = BlockKind::kNurbs;
  n.contouring = b.contouring;
  n.path_tolerance_mm = b.path_tolerance_mm;
  if (std::string err = to_geometry(tail, n.nurbs); !err.empty()) {
    return fail(why, "the rest of the interrupted NURBS block cannot be made a block: " + err);
  }
  const NurbsGeometry& g = b.nurbs;
  int m = 0;
  if (g.schedule_count > 0) {
    int hint = 0;
    double first = g.schedule_speed[0];
    double first_accel = g.schedule_accel[0];
    if (g.schedule_count > 1 && u > g.schedule_u[0]) {
      while (hint + 2 < g.schedule_count && u >= g.schedule_u[hint + 1]) ++hint;
      const double a = g.schedule_u[hint], z = g.schedule_u[hint + 1];
      const double f = std::clamp((u - a) / (z - a), 0.0, 1.0);
      first = g.schedule_speed[hint] + f * (g.schedule_speed[hint + 1] - g.schedule_speed[hint]);
      first_accel = std::min(g.schedule_accel[hint], g.schedule_accel[hint + 1]);
    }
    if (u >= g.schedule_u[g.schedule_count - 1]) {
      first = g.schedule_speed[g.schedule_count - 1];
      first_accel = g.schedule_accel[g.schedule_count - 1];
    }
    if (const CurveFrame fr = nurbs_frame(view_of(n.nurbs), u); fr.ok) {
      AxisLimits vmax{}, amax{};
      for (std::size_t i = 0; i < static_cast<std::size_t>(kAxes); ++i) {
        vmax[i] = config.axes[i].max_velocity_mm_s;
        amax[i] = config.axes[i].max_accel_mm_s2;
      }
      first = std::min(first, axis_cap(fr.t, vmax));
      if (!(tangential_budget(fr.t, fr.k, first * first, amax) > 0.0)) first = 0.0;
      first_accel = std::min(first_accel, tangential_budget(fr.t, fr.k, first * first, amax));
    }
    n.nurbs.schedule_u[m] = u;
    n.nurbs.schedule_accel[m] = first_accel;
    n.nurbs.schedule_speed[m++] = first;
    for (int i = 0; i < g.schedule_count && m < kMaxFeedSchedule; ++i) {
      if (g.schedule_u[i] > u) {
        n.nurbs.schedule_u[m] = g.schedule_u[i];
        n.nurbs.schedule_accel[m] = g.schedule_accel[i];
        n.nurbs.schedule_speed[m++] = g.schedule_speed[i];
      }
    }
  }
  n.nurbs.schedule_count = static_cast<std::uint16_t>(m);
  {
    const NurbsView nv = view_of(n.nurbs);
    for (int k = 0; k < m; ++k) n.nurbs.schedule_s[k] = k == 0 ? 0.0 : nurbs_arc_length(nv, nv.u_min(), n.nurbs.schedule_u[k]);
  }
  set_nurbs_block_geometry(n);
  double vmax = 0.0;
  for (int k = 0; k < m; ++k) vmax = std::max(vmax, n.nurbs.schedule_speed[k]);
  n.speed = std::min(b.speed, vmax);
  n.accel = b.accel;
  for (int k = 0; k < m; ++k) n.accel = std::min(n.accel, n.nurbs.schedule_accel[k]);
  c.block = n;
  return c;
}

// The schedule's speed at u as the rt reads it: linear between points, constant beyond the ends.
double schedule_at(const RuledGeometry& g, double u) {
  const int m = std::clamp(g.schedule_count, 1, kMaxRuledSchedule);
  if (u <= g.schedule_u[0]) return g.schedule_speed[0];
  for (int k = 1; k < m; ++k) {
    if (u <= g.schedule_u[k]) {
      const double w = (u - g.schedule_u[k - 1]) / (g.schedule_u[k] - g.schedule_u[k - 1]);
      return g.schedule_speed[k - 1] + w * (g.schedule_speed[k] - g.schedule_speed[k - 1]);
    }
  }
  return g.schedule_speed[m - 1];
}

// A Ferguson segment cut at t: the same cubic on [t, 1], reparametrised over [0, 1].
HermiteSegment cut_segment(const HermiteSegment& s, double t) {
  const CurveJet j = hermite_jet(s, t);
  return HermiteSegment{j.p, s.p1, (1.0 - t) * j.d1, (1.0 - t) * s.t1};
}

// A ruled block from the parameter u* nearest the tip the joints give (see resume.hpp).
std::optional<Continuation> continue_ruled(const Block& b, const Vec3& at, const std::optional<Rot3>& rot, double tol,
                                           double skip_tol, const MachineConfig& config, std::string* why) {
  if (!rot) return fail(why, "resuming inside a ruled-surface block (G5.4) needs the rotary joints where the machine stands");
  Continuation c;
  const RuledGeometry& g = b.ruled;
  const int n = g.segment_count;
  if (n < 1 || n > kMaxRuledSegments) return fail(why, "the interrupted ruled block is invalid");
  const ToolPose pose = forward(kinematics_with_tool(config, b.rotary.tool_length), to_joints(config, at, *rot));
  const RuledCurves curves = curves_of(g);
  auto dist = [&](double u) { return norm(ruled_jet(curves, u).c.p - pose.tip); };
  // the nearest directrix point: a dense search, then golden sections around the best
  double u = 0.0, best = dist(0.0);
  for (int k = 1; k <= 64 * n; ++k) {
    const double v = static_cast<double>(k) / 64.0;
    if (const double d = dist(v); d < best) best = d, u = v;
  }
  double lo = std::max(0.0, u - 1.0 / 64.0), hi = std::min(static_cast<double>(n), u + 1.0 / 64.0);
  for (int k = 0; k < 80; ++k) {
    const double a = hi - 0.618 * (hi - lo), d = lo + 0.618 * (hi - lo);
    if (dist(a) < dist(d)) hi = d; else lo = a;
  }
  u = 0.5 * (lo + hi);
  const RuledJet here = ruled_jet(curves, u);
  if (!(norm(here.c.p - pose.tip) <= tol)) {
    return fail(why, "the tool tip is not on the interrupted ruled piece (off by " + std::to_string(norm(here.c.p - pose.tip)) + " mm)");
  }
  if (!(norm(here.e.p - pose.axis) <= 1e-3)) {
    return fail(why, "the tool axis is not the interrupted ruled piece's there (off by " + std::to_string(norm(here.e.p - pose.axis)) + ")");
  }
  // the rest: segment i cut at t, the later ones as they are
  int i = std::min(static_cast<int>(std::floor(u)), n - 1);
  double t = u - i;
  if (t >= 1.0 - 1e-9 && i + 1 < n) ++i, t = 0.0;  // on a set point: the segment starting there
  RuledModel rest;
  rest.form = static_cast<RulingForm>(g.ruling_form);
  rest.directrix.push_back(cut_segment(g.directrix[i], t));
  rest.ruling.push_back(cut_segment(g.ruling[i], t));
  for (int k = i + 1; k < n; ++k) {
    rest.directrix.push_back(g.directrix[k]);
    rest.ruling.push_back(g.ruling[k]);
  }
  if (hermite_arc_length(HermiteView{rest.directrix.data(), static_cast<int>(rest.directrix.size())}) <= skip_tol) {
    c.skip = true;
    return c;
  }
  Block r{};
  r.line = b.line;
  r.contouring = b.contouring;
  r.path_tolerance_mm = b.path_tolerance_mm;
  if (std::string e = to_geometry(rest, g.schedule_speed[0], g.accel, 0.0, g.end_speed, r.ruled); !e.empty()) {
    return fail(why, "the rest of the interrupted ruled block cannot be made a block: " + e);
  }
  // the schedule at u* as the rt reads it (linear between points), then the later points
  const int m = r.ruled.segment_count + 1;
  if (r.ruled.schedule_count != m) return fail(why, "the rest of the interrupted ruled block has an unexpected schedule");
  r.ruled.schedule_speed[0] = schedule_at(g, u);
  for (int k = 1; k < m; ++k) r.ruled.schedule_speed[k] = schedule_at(g, static_cast<double>(i + k));
  set_ruled_block_fields(r);
  r.accel = g.accel;
  r.rotary.tool_length = b.rotary.tool_length;
  r.rotary.start = *rot;
  r.rotary.end = b.rotary.end;
  r.rotary.joint_end = b.rotary.joint_end;
  c.block = r;
  return c;
}

}  // namespace

std::optional<Continuation> continue_block(const Block& b, const Vec3& at, const MachineConfig& config, double tol,
                                           std::string* why, const std::optional<Rot3>& rot) {
  // Nothing is left only when the next block may start where the machine stands: the rt
  // checks that a block starts where the previous one ended within its block tolerance.
  // (A machine 8 um short of a line's end, with the line skipped, made the next block fail
  // that check: found by the soak, docs/reliability.md.)
  const double skip_tol = std::min(tol, 0.5 * config.motion.block_tolerance_mm);
  Continuation c;
  switch (b.kind) {
    case BlockKind::kPause:
    case BlockKind::kEnd:
      c.skip = b.kind == BlockKind::kPause;
      if (b.kind == BlockKind::kEnd) c.block = b;
      return c;
    case BlockKind::kDwell:
      c.block = b;
      c.block.seq = 0;
      return c;
    case BlockKind::kNurbs:
      return continue_nurbs(b, at, tol, skip_tol, config, why);
    case BlockKind::kRuled:
      return continue_ruled(b, at, rot, tol, skip_tol, config, why);
    case BlockKind::kRapid:
    case BlockKind::kLine:
    case BlockKind::kArc:
      break;
  }
  Move m;
  m.line = static_cast<int>(b.line);
  m.start = at;
  m.end = b.end;
  m.feed_mm_s = b.speed;  // the block's own limit: re-planning a part of it never raises it
  m.contouring = b.contouring != 0;
  m.path_tolerance_mm = b.path_tolerance_mm;

  if (b.kind != BlockKind::kArc) {
    const Vec3 d = b.end - b.start;
    const double len = norm(d);
    const Vec3 rel = at - b.start;
    const double s = len > 0.0 ? dot(rel, d) / len : 0.0;
    const Vec3 foot = len > 0.0 ? b.start + (s / len) * d : b.start;
    if (norm(at - foot) > tol || s < -tol || s > len + tol) {
      return fail(why, "the machine is not on the interrupted block's line (off by " + std::to_string(norm(at - foot)) + " mm)");
    }
    if (norm(b.end - at) <= skip_tol) {
      c.skip = true;
      return c;
    }
    m.kind = b.kind == BlockKind::kRapid ? MoveKind::kRapid : MoveKind::kLine;
    c.block = make_block(m, config);
    return c;
  }

  const ArcGeometry& g = b.arc;
  const auto pa = plane_axes(g.normal_axis);
  const int a0 = pa[0], a1 = pa[1], an = g.normal_axis;
  const double two_pi = 2.0 * std::numbers::pi;
  double u = 0.0;  // fraction of the block done
  if (std::abs(g.helix) > tol) {
    u = (at[an] - b.start[an]) / g.helix;
  } else {
    if (std::abs(g.sweep) > two_pi + 1e-9) {
      // The point gives the angle but not the turn: the rt's status says which block it is in,
      // not how far along it, so the turns already done cannot be known from the host.
      return fail(why,
                  "the program stopped inside a flat arc of more than one turn: the standing point gives the angle "
                  "reached but not how many turns were done (the rt's status holds no progress along a block)");
    }
    const double th = std::atan2(at[a1] - g.center[a1], at[a0] - g.center[a0]);
    double travelled = std::remainder((th - g.start_angle) * (g.sweep < 0.0 ? -1.0 : 1.0), two_pi);
    if (travelled < 0.0) travelled += two_pi;
    // Within the tolerance of the start, a full circle's start and end look alike: at the start.
    if (travelled * g.radius > std::abs(g.sweep) * g.radius + tol) travelled = 0.0;
    u = travelled / std::abs(g.sweep);
  }
  if (u < -1e-9 || u > 1.0 + 1e-9) return fail(why, "the machine is not within the interrupted arc");
  u = std::clamp(u, 0.0, 1.0);
  // Check the point is on the path as the rt executes it (angle and radius linear in u).
  const double theta = g.start_angle + g.sweep * u;
  const double r1 = std::hypot(b.end[a0] - g.center[a0], b.end[a1] - g.center[a1]);
  const double r = g.radius + (r1 - g.radius) * u;
  Vec3 expect = b.start;
  expect[a0] = g.center[a0] + r * std::cos(theta);
  expect[a1] = g.center[a1] + r * std::sin(theta);
  expect[an] = b.start[an] + g.helix * u;
  if (norm(expect - at) > tol) {
    return fail(why, "the machine is not on the interrupted arc (off by " + std::to_string(norm(expect - at)) + " mm)");
  }
  if ((1.0 - u) * b.length <= skip_tol) {
    c.skip = true;
    return c;
  }
  m.kind = MoveKind::kArc;
  m.center = g.center;
  m.center[an] = at[an];
  m.radius = std::hypot(at[a0] - g.center[a0], at[a1] - g.center[a1]);
  m.sweep = g.sweep * (1.0 - u);
  m.normal_axis = an;
  c.block = make_block(m, config);
  return c;
}

}  // namespace pcnc
