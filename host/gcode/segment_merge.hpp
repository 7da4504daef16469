// segment_merge.hpp — the host's naive-CAM detector, the pipeline stage between the
// preflight and the preprocessor (gcode/pipeline.hpp): a run of short feed moves that lie on
// one straight line within a tolerance becomes one line move. It packs more path into each
// ring slot; it comes after the preflight so that the program's figures and soft-limit
// messages speak of the moves as programmed (the rt's block check still sees the merged ones).
//
// CAM programs often write curves as thousands of tiny G1 segments (tiny.ngc: 0.031 mm). The
// rt sees only the 4 blocks in the ring and must always be able to stop within them, so 4
// tiny blocks cap the speed far below the feed. Merging keeps the path within the tolerance
// and puts more path into each slot. Rules:
//   * only G1 moves under M21 (contouring): under M22 every programmed point is an exact stop;
//   * consecutive moves with the same feed, contouring and frame;
//   * every dropped point stays within the moves' path tolerance of the merged line (LinuxCNC's
//     G64 Q, which defaults to the P blending tolerance; pcnc uses the one path tolerance:
//     G64 P, --tolerance or motion.path_tolerance_mm, carried by each move);
//   * at most kMaxRun moves per merged line.
// The merged move keeps the first move's start, column and feed and the last move's end and
// line. A tolerance of 0 turns merging off. With a tolerance the smoothing stage before the
// preflight has already made curves of the runs it could fit; the merger joins what it kept
// as lines.
#pragma once

#include <functional>
#include <vector>

#include "gcode/move.hpp"

namespace pcnc {

class SegmentMerger {
 public:
  static constexpr std::size_t kMaxRun = 256;

  SegmentMerger() = default;

  /// The next move of the merged stream: `pull(Move&)` yields the next input move (null moves
  /// already dropped) and returns false at the end. Returns false at the end of the stream.
  bool next(const std::function<bool(Move&)>& pull, Move& out);

  /// Whether every point of `points[1 .. n-1]` lies within `tolerance` of the segment from
  /// points[0] to `end` (pure; exposed for tests).
  static bool fits(const std::vector<Vec3>& points, const Vec3& end, double tolerance);

 private:
  static bool mergeable(const Move& m) {
    return m.path_tolerance_mm > 0.0 && m.kind == MoveKind::kLine && m.contouring && !m.tcp && m.rot_start == m.rot_end;
  }

  bool have_stash_ = false;  // a move read past the end of the last run
  Move stash_;
  std::vector<Vec3> points_;  // the run's start and the end of each move in it
};

}  // namespace pcnc
