// arc_split.hpp — the pipeline's arc-splitting stage (gcode/pipeline.hpp: after smoothing,
// before the preflight): an arc under M21 in a plane whose two axes have different
// acceleration limits is cut into pieces of at most kArcPieceSweep of its sweep.
//
// An arc block's speed cap holds its centripetal part within what the plane axes allow along
// the angles it sweeps (shared/geometry/arc_limits.hpp arc_centripetal_limit): each axis carries
// the share of the radius direction that lies along it. A quarter circle from a Z-normal to a
// Y-normal on the desktop mill (Y 2000, Z 1000 mm/s²) is held to Z's limit over its whole sweep,
// although where its normal points along Y it could run 1.4 times as fast. Cut into pieces, each
// piece gets the cap of the angles it sweeps, and the rt's look-ahead runs the arc at a speed
// that follows the normal; the pieces join tangentially and flow (M21). The pieces lie on the
// arc the rt would run for the whole (the radius and the normal axis advance linearly with the
// angle), the last one ends exactly at the move's end. Arcs under M22/G61 (each piece would
// stop), arcs in a plane of equal limits, and pieces shorter than kArcPieceMinMm are left whole.
// Pure; no I/O.
#pragma once

#include <deque>
#include <functional>
#include <numbers>
#include <vector>

#include "config/config.hpp"
#include "gcode/move.hpp"

namespace pcnc {

/// The largest sweep of one piece (rad): 22.5°.
constexpr double kArcPieceSweep = std::numbers::pi / 8.0;
/// The shortest piece (mm along the arc): a shorter arc is cut into fewer pieces, or none.
constexpr double kArcPieceMinMm = 0.5;

/// The pieces of an arc move (`m.kind == kArc`): `n` equal parts of its sweep, each a whole arc
/// move of its own (start, end, center on its start's level along the normal, radius, sweep),
/// the first starting at m.start and the last ending at m.end exactly; n <= 1: the move itself.
std::vector<Move> split_arc(const Move& m, int n);

/// How many pieces the stage cuts `m` into under `config` (1: left whole).
int arc_pieces(const Move& m, const MachineConfig& config);

class ArcSplitter {
 public:
  explicit ArcSplitter(const MachineConfig& config) : config_(config) {}

  /// The next move of the stream with arcs cut: `pull(Move&)` yields the next input move and
  /// returns false at the end. Returns false at the end of the stream.
  bool next(const std::function<bool(Move&)>& pull, Move& out);

 private:
  const MachineConfig& config_;
  std::deque<Move> pending_;  // the pieces of the arc being handed out
};

}  // namespace pcnc
