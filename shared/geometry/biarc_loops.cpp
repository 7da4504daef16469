// biarc_loops.cpp — exact offsets of arc chains and the seed's twice-offset loop removal
// (offset by the largest tool radius, cut the loops at the offset's self-intersections,
// offset back). See offset_chain and remove_loops in biarc.hpp.
#include <algorithm>
#include <cmath>
#include <limits>

#include "geometry/arc_intersect.hpp"
#include "geometry/biarc.hpp"

namespace pcnc {
namespace {

constexpr double kGap = 1e-9;    // mm: offsets closer than this meet
constexpr double kFrac = 1e-9;   // fraction slack along a piece

double turning(Vec2 t_in, Vec2 t_out) { return std::atan2(cross(t_in, t_out), dot(t_in, t_out)); }

bool is_point(const Arc2& a) { return arc_length(a) <= 1e-12; }

// The angle the tangent turns along a closed chain: sweeps and corners, closing corner too.
double total_turning(const std::vector<Arc2>& chain) {
  double t = 0.0;
  for (std::size_t i = 0; i < chain.size(); ++i) {
    t += chain[i].line ? 0.0 : chain[i].sweep;
    t += turning(end_tangent(chain[i]), start_tangent(chain[(i + 1) % chain.size()]));
  }
  return t;
}

struct Box {
  double x0, y0, x1, y1;
};

Box box_of(const Arc2& a) {
  Box b{std::min(a.start.x, a.end.x), std::min(a.start.y, a.end.y), std::max(a.start.x, a.end.x),
        std::max(a.start.y, a.end.y)};
  if (!a.line) {  // the whole circle: a loose box is enough for a pre-filter
    b = {std::min(b.x0, a.centre.x - a.radius), std::min(b.y0, a.centre.y - a.radius),
         std::max(b.x1, a.centre.x + a.radius), std::max(b.y1, a.centre.y + a.radius)};
  }
  return b;
}

bool overlap(const Box& a, const Box& b) {
  constexpr double e = 1e-9;
  return a.x0 <= b.x1 + e && b.x0 <= a.x1 + e && a.y0 <= b.y1 + e && b.y0 <= a.y1 + e;
}

// The offset chain, for each piece whether it runs against the contour (a collapsed piece,
// or the corner arc of a corner turning toward the offset side), and the chain piece it is
// the offset of (-1: a corner arc).
std::vector<Arc2> offset_pieces(const std::vector<Arc2>& chain, double d, std::vector<bool>* backwards,
                                std::vector<int>* origin = nullptr) {
  std::vector<Arc2> out;
  for (std::size_t i = 0; i < chain.size(); ++i) {
    const ArcOffset o = offset_arc(chain[i], d);
    if (!out.empty() && distance(out.back().end, o.arc.start) > kGap) {
      // a corner of the chain: an arc of radius |d| about it joins the two offsets
      const double phi = turning(end_tangent(chain[i - 1]), start_tangent(chain[i]));
      Arc2 corner = make_arc_about(chain[i].start, out.back().end, phi);
      corner.end = o.arc.start;
      out.push_back(corner);
      if (backwards) backwards->push_back(phi * d > 0.0);
      if (origin) origin->push_back(-1);
    }
    out.push_back(o.arc);
    if (backwards) backwards->push_back(o.collapsed);
    if (origin) origin->push_back(static_cast<int>(i));
  }
  return out;
}

}  // namespace

std::vector<Arc2> offset_chain(const std::vector<Arc2>& chain, double d) { return offset_pieces(chain, d, nullptr); }

namespace {

// A part of the offset the walk keeps: fractions f0..f1 of offset piece `piece`; `cut` when
// it ends at a crossing (a loop cut after it).
struct Kept {
  std::size_t piece;
  double f0, f1;
  bool cut;
};

// Walks the offset from its start. On piece i from fraction f, the first crossing ahead with
// a later piece ends the part kept; the walk resumes on that piece after the crossing (the
// loop between is cut). Of crossings at the same place, the furthest wins; pieces more than
// `reach` ahead are not looked at (a closed contour walked round several times: one round).
std::vector<Kept> walk(const std::vector<Arc2>& off, std::size_t reach) {
  std::vector<Box> boxes;
  for (const Arc2& a : off) boxes.push_back(box_of(a));
  std::vector<Kept> kept;
  std::size_t i = 0;
  double f = 0.0;
  const std::size_t n = off.size();
  while (i < n) {
    double best_fa = std::numeric_limits<double>::infinity(), best_fb = 0.0;
    std::size_t best_j = 0;
    if (!is_point(off[i])) {
      for (std::size_t j = i + 1; j < n && j - i < reach; ++j) {
        if (is_point(off[j]) || !overlap(boxes[i], boxes[j])) continue;
        for (const ArcCrossing& x : intersect(off[i], off[j])) {
          if (x.fa <= f + kFrac) continue;
          // the joint two neighbours share (directly, or across points between them) is no loop
          bool joint = x.fa >= 1.0 - kFrac && x.fb <= kFrac;
          for (std::size_t k = i + 1; joint && k < j; ++k) joint = is_point(off[k]);
          if (joint) continue;
          if (x.fa < best_fa - kFrac || (x.fa <= best_fa + kFrac && (j > best_j || (j == best_j && x.fb > best_fb)))) {
            best_fa = x.fa, best_fb = x.fb, best_j = j;
          }
        }
      }
    }
    if (std::isfinite(best_fa)) {
      kept.push_back({i, f, best_fa, true});
      i = best_j;
      f = best_fb;
    } else {
      kept.push_back({i, f, 1.0, false});
      ++i;
      f = 0.0;
    }
  }
  return kept;
}

}  // namespace

LoopRemoval remove_loops(const std::vector<Arc2>& chain, double tool_radius, int side) {
  LoopRemoval r;
  if (chain.empty() || !(tool_radius > 0.0)) {
    r.arcs = chain;
    return r;
  }
  const double d = side >= 0 ? tool_radius : -tool_radius;
  const std::size_t n_chain = chain.size();
  // A closed contour is walked three times round and its second round is the result: a loop
  // across the closing point is then cut like any other.
  const bool closed = n_chain >= 2 && distance(chain.front().start, chain.back().end) <= kGap;
  std::vector<Arc2> work = chain;
  if (closed)
    for (int lap = 0; lap < 2; ++lap) work.insert(work.end(), chain.begin(), chain.end());
  std::vector<bool> backwards;
  std::vector<int> origin;
  const std::vector<Arc2> off = offset_pieces(work, d, &backwards, &origin);
  std::size_t reach = off.size();
  if (closed)  // the offset pieces of one round: up to the first of the second
    for (std::size_t q = 0; q < off.size(); ++q)
      if (origin[q] == static_cast<int>(n_chain)) {
        reach = q;
        break;
      }
  const std::vector<Kept> kept = walk(off, reach);
  std::size_t first = 0, last = kept.size();
  if (closed) {
    // the second round from the chain's start to the third's: both must be kept as they are
    // (a start inside a loop, or at a concave corner that gets rounded, cannot stay the start)
    auto round_start = [&](std::size_t round) {
      for (std::size_t q = 0; q < kept.size(); ++q)
        if (origin[kept[q].piece] == static_cast<int>(round * n_chain) && kept[q].f0 <= kFrac) return q;
      return kept.size();
    };
    first = round_start(1);
    last = round_start(2);
    if (first >= last || last >= kept.size()) {
      r.arcs = chain;
      r.unresolved = 1;
      return r;
    }
  }
  // what is kept must be a path the tool can follow: its offset points at least R from the
  // contour (a walk that began inside a loop keeps the loop and cuts the rest): else unchanged
  for (std::size_t q = first; q < last; ++q) {
    const Kept& k = kept[q];
    if (origin[k.piece] < 0 || backwards[k.piece] || !(k.f1 - k.f0 > kFrac)) continue;
    for (int m = 1; m < 8; ++m) {
      const Vec2 p = arc_point(off[k.piece], k.f0 + (k.f1 - k.f0) * m / 8.0);
      if (nearest_on_arcs(chain, p) < tool_radius * (1.0 - 1e-6) - 1e-9) {
        r.arcs = chain;
        r.loops_removed = 0;
        r.unresolved = std::max(r.unresolved, 1);
        return r;
      }
    }
  }
  for (std::size_t q = first; q < last; ++q) {
    const Kept& k = kept[q];
    if (k.cut) ++r.loops_removed;
    if (backwards[k.piece] && !is_point(off[k.piece]) && k.f1 - k.f0 > kFrac) ++r.unresolved;
  }
  if (r.loops_removed == 0) {
    r.arcs = chain;
    return r;
  }
  // back: an offset keeps the fractions of its piece, so the part of a chain piece whose offset
  // was kept is the same fraction range of the chain piece (exact, collapsed pieces too);
  // corner arcs of the offset shrink to their corners and go; where a cut joins two parts, an
  // arc of radius R about the crossing (the largest tool's own rounding) joins their originals
  Kept prev{};               // the previous part, in offset space
  bool has_prev = false;
  Vec2 back_end{};           // where the result ends so far
  // at a cut the offset turns by phi at the crossing x; its back offset is an arc of radius
  // R about x turning the same way (the rule of a corner in offset_chain)
  auto join = [&](const Kept& k, Vec2 start) {
    if (!has_prev || distance(back_end, start) <= kGap) return;
    const Vec2 x = arc_point(off[k.piece], k.f0);
    const double phi = turning(arc_tangent(off[prev.piece], prev.f1), arc_tangent(off[k.piece], k.f0));
    Arc2 corner = make_arc_about(x, back_end, phi);
    corner.end = start;
    r.arcs.push_back(corner);
  };
  auto add = [&](const Kept& k, double f1) {
    if (!(f1 - k.f0 > kFrac) && origin[k.piece] >= 0) return;
    // a corner arc's part goes back to its corner, a point; a piece's part to the same
    // fraction range of the chain piece
    const bool corner_part = origin[k.piece] < 0;
    Arc2 part;
    if (!corner_part) part = sub_arc(chain[static_cast<std::size_t>(origin[k.piece]) % n_chain], k.f0, f1);
    const Vec2 start = corner_part ? off[k.piece].centre : part.start;
    join(k, start);
    if (!corner_part) r.arcs.push_back(part);
    back_end = corner_part ? start : part.end;
    prev = Kept{k.piece, k.f0, f1, k.cut};
    has_prev = true;
  };
  for (std::size_t q = first; q < last; ++q) add(kept[q], kept[q].f1);
  if (closed && !r.arcs.empty()) {  // the round closes at the start
    join(kept[last], r.arcs.front().start);
    r.arcs.back().end = r.arcs.front().start;
    // a closed contour turns by the same total angle before and after (a round that went
    // wrong, e.g. from a start the offset's loops surround, does not): else unchanged
    if (std::abs(total_turning(r.arcs) - total_turning(chain)) > 1e-6) {
      r.arcs = chain;
      r.loops_removed = 0;
      r.unresolved = std::max(r.unresolved, 1);
      return r;
    }
  }
  for (const Arc2& a : r.arcs)
    for (int s = 0; s <= 16; ++s) r.max_change_mm = std::max(r.max_change_mm, nearest_on_arcs(chain, arc_point(a, s / 16.0)));
  return r;
}

}  // namespace pcnc
