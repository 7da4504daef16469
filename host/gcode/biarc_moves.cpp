// biarc_moves.cpp — arcs as Moves. See biarc_moves.hpp.
#include "gcode/biarc_moves.hpp"

#include "geometry/vec2.hpp"

namespace pcnc {

std::vector<Move> arc_moves(const std::vector<Arc2>& arcs, int normal_axis, double level, const Move& like) {
  std::vector<Move> out;
  out.reserve(arcs.size());
  for (const Arc2& a : arcs) {
    Move m = like;
    m.nurbs.reset();
    m.start = out.empty() ? from_plane(a.start, normal_axis, level) : out.back().end;
    m.end = from_plane(a.end, normal_axis, level);
    if (a.line) {
      m.kind = MoveKind::kLine;
      m.center = {};
      m.radius = 0.0;
      m.sweep = 0.0;
    } else {
      m.kind = MoveKind::kArc;
      m.center = from_plane(a.centre, normal_axis, level);
      m.radius = a.radius;
      m.sweep = a.sweep;
      m.normal_axis = normal_axis;
    }
    out.push_back(m);
  }
  return out;
}

}  // namespace pcnc
