// ideal_planner.hpp — the yardstick issue 14 measures machine time against: a LinuxCNC/grbl-class
// planner with unlimited look-ahead that passes every junction at its junction-deviation speed
// for the path tolerance, as if that junction stood alone. It is a model of another controller's
// planner, not pcnc's: `bench_ideal_planner` and tools/bench_surfacing.sh print its time beside
// pcnc's machine time (docs/smoothing.md, "The ideal planner").
//
// The rules, grbl's (planner.c, junction deviation), with unlimited look-ahead:
//  * lines and rapids are straight segments as they are; an arc is one segment at most at
//    sqrt(A·r) (A the smaller plane axis's acceleration: LinuxCNC's tp runs an arc as an arc),
//    or with `arcs_as_chords` cut into chords whose sagitta is at most `chord_tolerance_mm`
//    (grbl's arc_tolerance, 0.002 mm); NURBS curves are cut into such chords;
//  * a segment runs at most at its feed (rapids: none) and at the axes' velocities projected on
//    it; it accelerates and brakes at the axes' accelerations projected on it (the smallest
//    a_i / |u_i|);
//  * at a junction turning by θ (between an arc's end tangent and the next start's) the speed is at most sqrt(a_j · δ · s / (1 − s)), with
//    s = sin((π − θ)/2), δ the path tolerance and a_j the axes' acceleration projected on the
//    change of direction; a reversal stops;
//  * the program starts and ends at rest, and stops where a move does not contour (G61/M22),
//    at a dwell and at a pause;
//  * each segment is a trapezoid (or triangle) between its junction speeds.
// What it leaves out, as the planners it models do: the acceleration a junction's turn asks
// within one cycle (on a densely drawn fillet the junctions together ask far more than the
// axes' limits: docs/smoothing.md), jerk, the cycle time and any queue length. Rotary moves
// and ruled pieces are not modelled (their moves are counted, not timed).
#pragma once

#include <cstdint>
#include <vector>

#include "config/config.hpp"
#include "gcode/move.hpp"

namespace pcnc {

struct IdealPlannerOptions {
  double tolerance_mm = 0.005;        // the junction deviation δ
  double chord_tolerance_mm = 0.002;  // curves (and arcs as chords) as chords of at most this sagitta
  // grbl's arcs: chords, each junction at the junction-deviation speed. On an arc of a few
  // tenths of a mm a chord turns by over 10°, and the junction-deviation circle of 5 µm is
  // larger than the arc: faster than the arc's own sqrt(A·r) (docs/smoothing.md).
  bool arcs_as_chords = false;
  // Not the ideal's rule but the floor a planner that keeps the axes' acceleration on the bends
  // could reach with the same junctions: a bend (a turn under 10°) also at most at sqrt(a_j·ρ),
  // ρ the circumradius of the junction and its neighbours' far ends.
  bool keep_bend_limits = false;
};

struct IdealLineTime {
  int line = 0;
  double time_s = 0.0;
};

struct IdealPlan {
  double time_s = 0.0;                // motion time, plus dwells
  double length_mm = 0.0;             // path length of the segments
  std::uint64_t segments = 0;         // straight segments planned
  std::uint64_t stops = 0;            // junctions (and ends) passed at rest
  std::uint64_t unmodelled_moves = 0; // rotary, angular or ruled moves left out
  // What the planned speeds ask of the programmed curve at its bends (junctions turning by less
  // than 10° between straight segments: a fillet's moves, an arc's chords): v² over the circumradius of the junction and
  // its neighbours' far ends, as a multiple of the axes' acceleration along the change of
  // direction. Above 1 (by more than 1e-9) the ideal's speed there exceeds what the axes are
  // configured to give.
  std::uint64_t bends = 0;
  std::uint64_t bends_over_limit = 0;
  double bend_accel_median = 0.0;
  double bend_accel_max = 0.0;
  // The time of each run of segments from one source line, in program order (dwells aside).
  std::vector<IdealLineTime> line_times;
};

/// The ideal planner's time for `moves` (machine coordinates, in program order, as the front
/// end hands them: gcode/pipeline.hpp front_end_move) on `config`'s axes. Pure.
IdealPlan ideal_planner_time(const std::vector<Move>& moves, const MachineConfig& config,
                             const IdealPlannerOptions& options = {});

}  // namespace pcnc
