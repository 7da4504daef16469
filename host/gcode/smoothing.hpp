// smoothing.hpp — the pipeline's smoothing stage (gcode/pipeline.hpp: after cutter
// compensation and surface correction, before the preflight): runs of short G1 moves between
// real corners become smooth curves within the path tolerance (docs/smoothing.md).
//
// CAM surfacing programs write curved surfaces as thousands of 0.01-0.5 mm G1 moves that turn by
// a few degrees each. Run as lines, every junction costs speed and 4 ring slots hold only 4
// tiny moves. Here each run is fitted with one C2 cubic B-spline (shared/geometry/spline_fit.hpp)
// whose measured distance to every programmed point and segment is at most the move's path
// tolerance (G64 P, --tolerance or motion.path_tolerance_mm), the run's end points exact. The
// curve goes on as one NURBS move; the preprocessor plans its feed schedule (curvature and
// axis limits) and splits it into blocks of up to 32 control points, so one ring slot holds
// dozens of the programmed moves.
//
// Rules:
//   * a run is consecutive G1 moves under M21 with a tolerance > 0, the same feed, tolerance
//     and frame; rapids, arcs (and compensation biarcs), NURBS, dwells and M22 pass unchanged;
//   * a junction turning more than motion.smoothing_angle_deg is a real corner: the run ends
//     there (the rt passes it at the junction-deviation speed for the tolerance);
//   * where the fit cannot stay within the tolerance, the run is cut at the worst programmed
//     point (a corner kept) and both parts are fitted again; a single move stays a line, and
//     so do two moves whose junction the rt passes slower than their feed as a corner (its
//     junction-deviation speed for the tolerance): a curve within the tolerance rounds that
//     junction about as tightly as the corner's circle (measured on spiral_lines.ngc's pairs),
//     the rt runs it at a share of the acceleration, and its end tangents leave the chords,
//     sharpening the corners at its ends;
//   * at most kMaxRun moves per curve;
//   * the fits of one run cost at most kFitWork times its points (a bound on the cut-and-refit
//     recursion, which a run that fails near one end again and again would make quadratic):
//     a range met with the work spent stays the programmed lines.
#pragma once

#include <cstdint>
#include <deque>
#include <functional>
#include <vector>

#include "config/config.hpp"
#include "geometry/axis_caps.hpp"
#include "gcode/move.hpp"

namespace pcnc {

/// What smoothing did to a program, for the run report and --summary.
struct SmoothingStats {
  std::uint64_t moves = 0;         // programmed G1 moves replaced by curves
  std::uint64_t curves = 0;        // curves made of them
  double max_deviation_mm = 0.0;   // largest measured distance of a curve from its programmed moves
  // The path tolerances the curves were fitted to (G64 P, --tolerance or the config's): the
  // least and the largest; 0 without curves.
  double min_tolerance_mm = 0.0;
  double max_tolerance_mm = 0.0;
};

class Smoother {
 public:
  static constexpr std::size_t kMaxRun = 2000;
  static constexpr std::size_t kFitWork = 24;  // points fitted per point of a run, at most

  explicit Smoother(const MachineConfig& config);

  /// The next move of the smoothed stream: `pull(Move&)` yields the next input move and
  /// returns false at the end. Returns false at the end of the stream.
  bool next(const std::function<bool(Move&)>& pull, Move& out);

  const SmoothingStats& stats() const { return stats_; }

 private:
  bool smoothable(const Move& m) const;
  bool continues(const Move& last, const Move& m) const;
  void flush_run();
  void fit_range(std::size_t first, std::size_t last);  // points first..last of the run
  bool within_travel(const NurbsCurve& c) const;
  bool corner_binds(std::size_t k) const;  // moves k and k + 1's junction, as a corner, below their feed

  double cos_corner_;
  Vec3 travel_min_{}, travel_max_{};  // the axes' travel: a curve never leaves it
  AxisLimits accel_{};                // the axes' accelerations (the junction-deviation speed)
  std::size_t fit_work_left_ = 0;  // points the run's remaining fits may still take
  std::vector<Move> run_;      // the run's moves (null moves dropped)
  std::vector<Vec3> points_;   // the run's start and each move's end
  std::deque<Move> out_;       // moves ready to hand on
  SmoothingStats stats_;
};

}  // namespace pcnc
