// cutter_gouge.cpp — the windowed exact gouge test (see cutter_gouge.hpp).
#include "gcode/cutter_gouge.hpp"

#include <cmath>
#include <algorithm>
#include <cstdio>
#include <numbers>

#include "geometry/intersect.hpp"

namespace pcnc {

void GougeCheck::start(double radius_mm) {
  radius_ = radius_mm;
  tolerance_ = 1e-6 + 2.0 * radius_mm * (1.0 - std::cos(0.05));
  crossings_ = 0;
  programmed_.clear();
  tools_.clear();
}

namespace {
// A box around a piece (an arc's whole circle): pieces whose boxes are farther apart than the
// radius cannot be closer, and need no exact distance.
struct Bounds {
  double x0, y0, x1, y1;
};
Bounds bounds(const Piece& p) {
  if (p.arc) return {p.c.x - p.r, p.c.y - p.r, p.c.x + p.r, p.c.y + p.r};
  return {std::min(p.a.x, p.b.x), std::min(p.a.y, p.b.y), std::max(p.a.x, p.b.x), std::max(p.a.y, p.b.y)};
}
double gap(const Bounds& a, const Bounds& b) {
  const double dx = std::max({0.0, a.x0 - b.x1, b.x0 - a.x1});
  const double dy = std::max({0.0, a.y0 - b.y1, b.y0 - a.y1});
  return std::hypot(dx, dy);
}
}  // namespace

bool GougeCheck::measure(const Item& tool, const Item& prog, Gouge& g) const {
  // Look-ahead: a tool move must not cut into the contour still to be cut after it. A move
  // and its next one meet at a corner LinuxCNC's own rules decide (cutter_comp.cpp); an
  // earlier contour may be material a later pass removes (roughing passes under G41/G42).
  const int ahead = prog.index - tool.index;
  if (ahead < 2 || ahead > kGougeWindow) return true;
  if (gap(bounds(tool.p), bounds(prog.p)) >= radius_) return true;
  Vec2 at;
  const double d = distance(tool.p, prog.p, &at);
  const double depth = radius_ - d;
  if (depth <= tolerance_) return true;
  if (laps(tool.index, prog.index)) return true;
  if (crosses_itself(std::min(tool.index, prog.index), std::max(tool.index, prog.index))) {
    ++crossings_;  // no side of a self-crossing contour is the material's: nothing to gouge
    return true;
  }
  g.line = tool.line;
  g.column = tool.column;
  g.into_line = prog.line;
  g.depth_mm = depth;
  g.at = at;
  return false;
}

bool GougeCheck::laps(int from, int to) const {
  // The contour's signed turning (arcs' sweeps and corners) from the start of `from`: a lap
  // when it reaches a full turn either way at any point up to the end of `to`.
  const Item* a = nullptr;
  for (const Item& p : programmed_) {
    if (p.index == from) a = &p;
  }
  if (a == nullptr) return false;
  const auto sweep = [](const Item& p) { return p.p.arc ? p.p.sweep : 0.0; };
  const double base = a->turned - sweep(*a);
  const double full = 2.0 * std::numbers::pi - 1e-9;
  for (const Item& p : programmed_) {
    if (p.index < from || p.index > to) continue;
    if (std::fabs(p.turned - base) >= full || std::fabs(p.turned - sweep(p) - base) >= full) return true;
  }
  return false;
}

bool GougeCheck::crosses_itself(int from, int to) const {
  for (std::size_t k = 0; k < programmed_.size(); ++k) {
    const Item& a = programmed_[k];
    if (a.index < from || a.index > to) continue;
    for (std::size_t l = k + 1; l < programmed_.size(); ++l) {
      const Item& b = programmed_[l];
      if (b.index > to || b.index - a.index < 2) continue;
      if (distance(a.p, b.p) <= 1e-9) return true;
    }
  }
  return false;
}

void GougeCheck::trim(int index) {
  while (!programmed_.empty() && programmed_.front().index < index - kGougeWindow) programmed_.pop_front();
  while (!tools_.empty() && tools_.front().index < index - kGougeWindow) tools_.pop_front();
}

bool GougeCheck::programmed(const Piece& p, int index, int line, Gouge& g) {
  trim(index);
  Item item{p, index, line, 0};
  item.turned = p.arc ? p.sweep : 0.0;
  if (!programmed_.empty()) {
    const Item& prev = programmed_.back();
    const Vec2 t0 = tangent(prev.p, true), t1 = tangent(p, false);
    item.turned += prev.turned + std::atan2(cross(t0, t1), dot(t0, t1));
  }
  programmed_.push_back(item);
  for (const Item& t : tools_) {
    if (!measure(t, item, g)) return false;
  }
  return true;
}

bool GougeCheck::tool(const Piece& t, int index, int line, int column, Gouge& g) {
  const Item item{t, index, line, column};
  tools_.push_back(item);
  for (const Item& p : programmed_) {
    if (!measure(item, p, g)) return false;
  }
  return true;
}

std::string describe_gouge(const Gouge& g, double radius_mm) {
  char buf[320];
  std::snprintf(buf, sizeof buf,
                "cutter compensation would gouge: the tool path of this move comes %.4f mm into the contour of "
                "line %d (tool radius %.4f mm; the tool centre passes %.4f mm from it); expected a contour the "
                "tool fits in, or a smaller tool",
                g.depth_mm, g.into_line, radius_mm, radius_mm - g.depth_mm);
  return buf;
}

}  // namespace pcnc
