// arc_packing.hpp — the pipeline's arc-packing stage (gcode/pipeline.hpp: after smoothing,
// before arc splitting): chains of short tangent arcs become one exact NURBS curve.
//
// The rt never runs faster than it can stop within the blocks in its 4-slot ring. A chain of
// arcs a few tenths of a millimetre long (LinuxCNC's spiral_circular_segments.ngc: 1,000 arcs
// of 0.51 mm, tangent to 0.006°) puts only about 2 mm of path in the ring, and that, not the
// arcs' own centripetal limit, caps the speed. Smoothing leaves arcs alone; here a chain of
// them becomes one rational quadratic NURBS (shared/geometry/arc_nurbs.hpp), which is the same
// circles to rounding, so a ring slot holds about 15 of them and the speed is the arcs' own.
//
// Rules (docs/smoothing.md, "Chains of short arcs"):
//   * a chain is consecutive arcs under M21 with a path tolerance > 0, in one plane at one
//     level (no helix), the same feed, tolerance and frame, each joining the one before within
//     kTangentKinkTurn (geometry/nurbs.hpp: the curve's feed schedule passes such
//     a kink without stopping, at a speed whose velocity step stays within a share of a cycle's
//     acceleration);
//   * only arcs the ring would slow: packed, an arc runs at most at its curve's centripetal cap
//     sqrt(kPackedArcNormalShare·a·r), a little below an arc block's sqrt(0.95·a·r); an arc is
//     packed only where that cap (or its feed) is above the speed at which the machine stops
//     within three arcs of its length, sqrt(2·a·3·L);
//   * at least two arcs, at most kMaxChain; where the curve turns at a join by more than a
//     kink after all (an end point a rounding off its radius tilts the end tangent), the
//     chain is cut there;
//   * the curve's distance from the programmed arcs (as the rt runs them: the radius changing
//     linearly with the angle when the end radius differs from the start's) is measured; a
//     chain farther than a tenth of its tolerance stays arcs.
#pragma once

#include <cstdint>
#include <deque>
#include <functional>
#include <vector>

#include "config/config.hpp"
#include "gcode/move.hpp"

namespace pcnc {

/// The share of an axis's acceleration a packed curve's centripetal part may take (its feed
/// schedule's NurbsLimits::normal_accel_share). Above a fitted curve's 0.7: the curvature is
/// constant between knots. Below an arc block's 0.95 (geometry/arc_limits.hpp): the NURBS
/// follower's parameter steps put a few tens of nanometres of noise on the setpoints, which at
/// 0.95 raised an axis's second difference to 1.09 of its limit at block joins
/// (spiral_circular_segments.ngc), at 0.9 to 1.075, within what flowing junctions take.
constexpr double kPackedArcNormalShare = 0.9;

/// What packing did to a program, for the run report and --summary.
struct ArcPackingStats {
  std::uint64_t arcs = 0;         // programmed arcs packed into curves
  std::uint64_t curves = 0;       // curves made of them
  double max_deviation_mm = 0.0;  // largest measured distance of a curve from its arcs
};

class ArcPacker {
 public:
  static constexpr std::size_t kMaxChain = 2000;

  explicit ArcPacker(const MachineConfig& config);

  /// The next move of the stream with chains packed: `pull(Move&)` yields the next input move
  /// and returns false at the end. Returns false at the end of the stream.
  bool next(const std::function<bool(Move&)>& pull, Move& out);

  const ArcPackingStats& stats() const { return stats_; }

 private:
  bool packable(const Move& m) const;
  bool continues(const Move& last, const Move& m) const;
  void flush();
  void pack(std::size_t first, std::size_t last);  // chain_[first..last) into out_

  double plane_accel_[3]{};  // per normal axis: the smaller acceleration of its plane's axes
  std::vector<Move> chain_;
  std::deque<Move> out_;
  ArcPackingStats stats_;
};

}  // namespace pcnc
