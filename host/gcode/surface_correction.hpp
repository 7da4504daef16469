// surface_correction.hpp — the pipeline's surface-correction stage (issue 15, item 5), between
// cutter compensation and smoothing (gcode/pipeline.hpp): every move is lifted by the measured
// surface, z += (surface height at the point's X/Y) - reference, what "autolevel" does in other
// senders, on the fitted B-spline surface of `pcnc surface fit` (geometry/surface_fit.hpp).
//
// Rules:
//   * the reference is a horizontal plane: by default the surface's height at the work
//     offset's X/Y origin (the program's zero then keeps its Z there);
//   * a move is followed as a curve C(t) = P(t) + (0, 0, h(P(t)) - reference) and replaced by
//     straight pieces whose every point stays within `tolerance_mm` of C (checked at samples
//     no farther apart than a quarter of the surface's control-point spacing; a piece that
//     misses is bisected); the last piece ends exactly at the corrected end point;
//   * lines and rapids stay lines and rapids; arcs (any plane, helices too) and NURBS moves
//     become lines at their feed: the corrected path is no longer an arc or the programmed
//     curve, and a chain of lines within the tolerance is what the rt can follow exactly;
//   * the joints between the pieces of one move are marked contouring (they flow at speed, as
//     the unsplit move did; the rt's contouring angle still applies), the last piece keeps the
//     move's own M21/M22 state: under M22 the machine stops only where the program's move ends;
//   * moves given in machine coordinates (G53, G28, G30) are not corrected: they go to the
//     machine position asked for (a safe height, a tool change place);
//   * every move starts where the last one ended (the first at the machine's start position);
//     one that does not start on the corrected path (the first move, a move after a G53 one)
//     follows it plus the start's difference, fading linearly to nothing at its end;
//   * outside the surface's X/Y footprint the height is held at the nearest edge, with one
//     warning per program naming the first line that leaves it.
#pragma once

#include <cstddef>
#include <functional>
#include <memory>
#include <vector>

#include "gcode/diagnostics.hpp"
#include "gcode/move.hpp"
#include "geometry/bspline_surface.hpp"

namespace pcnc {

class SurfaceCorrection {
 public:
  static constexpr int kMaxDepth = 30;  // bisections of one piece

  /// `sink` may be null (no warnings).
  SurfaceCorrection(std::shared_ptr<const BSplineSurface> surface, double reference_z, double tolerance_mm,
                    DiagnosticSink* sink);

  /// The default reference: the surface's height at the work offset's X/Y origin.
  static double reference_at(const BSplineSurface& surface, const Vec3& work_origin);

  /// The next corrected move; false at the end of the input.
  bool next(const std::function<bool(Move&)>& pull, Move& out);

  /// What is added to z at machine X/Y (pure; for tests and the dimensional evaluation).
  double offset_at(double x, double y) const;

 private:
  void correct(const Move& m);                       // fills pending_
  void split(const Move& m, const std::function<Vec3(double)>& path);

  std::shared_ptr<const BSplineSurface> surface_;
  double reference_;
  double tolerance_;
  DiagnosticSink* sink_;
  double sample_step_;  // mm in X/Y between deviation samples
  std::vector<Move> pending_;
  std::size_t next_ = 0;
  bool have_last_ = false;
  Vec3 last_end_{};
  bool warned_outside_ = false;
};

}  // namespace pcnc
