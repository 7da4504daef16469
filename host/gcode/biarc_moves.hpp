// biarc_moves.hpp — arcs of a biarc fit (geometry/biarc.hpp, plane coordinates) as the
// pipeline's Moves: kArc with centre, radius and signed sweep (kLine for a straight piece),
// in the plane normal to `normal_axis`, at `level` along the normal. What cutter
// compensation hands on after it has fitted and offset a NURBS or a smooth G1 run.
#pragma once

#include <vector>

#include "geometry/arc2.hpp"
#include "gcode/move.hpp"

namespace pcnc {

/// One Move per arc. `like` gives what the moves inherit (line, column, feed, contouring,
/// known axes); start and end are the arc's ends at `level`. Consecutive moves share their
/// end points exactly.
std::vector<Move> arc_moves(const std::vector<Arc2>& arcs, int normal_axis, double level, const Move& like);

}  // namespace pcnc
