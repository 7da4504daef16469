// resume.cpp — the remaining part of an interrupted block (see resume.hpp).
#include "service/resume.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "gcode/move.hpp"
#include "gcode/preprocessor.hpp"

namespace pcnc {
namespace {

std::optional<Continuation> fail(std::string* why, std::string text) {
  if (why) *why = std::move(text);
  return std::nullopt;
}

}  // namespace

std::optional<Continuation> continue_block(const Block& b, const Vec3& at, const MachineConfig& config, double tol,
                                           std::string* why) {
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
      return fail(why, "the program stopped inside a NURBS block, which cannot be cut for resuming");
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

  if (b.kind != BlockKind::kArc) {
    const Vec3 d = b.end - b.start;
    const double len = norm(d);
    const Vec3 rel = at - b.start;
    const double s = len > 0.0 ? dot(rel, d) / len : 0.0;
    const Vec3 foot = len > 0.0 ? b.start + (s / len) * d : b.start;
    if (norm(at - foot) > tol || s < -tol || s > len + tol) {
      return fail(why, "the machine is not on the interrupted block's line (off by " + std::to_string(norm(at - foot)) + " mm)");
    }
    if (norm(b.end - at) <= tol) {
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
      return fail(why, "the program stopped inside a flat arc of more than one turn, which cannot be cut for resuming");
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
  if ((1.0 - u) * b.length <= tol) {
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
