// cutter_comp_fit.cpp — under G41/G42, free-form contours become biarcs before they are
// offset (the seed paper's cure for d = 2 r eps / s): a NURBS move is fitted with
// fit_biarcs, a smooth run of short G1 moves with fit_biarcs_polyline (geometry/biarc.hpp),
// within cutter_comp.fit_tolerance_mm; the arcs then go through LinuxCNC's rules one by one
// (cutter_comp.cpp), where tangent joins need no corner and each arc offsets exactly about its
// centre. Every other move is offset one by one, as LinuxCNC does.
#include <cmath>
#include <string>

#include "gcode/biarc_moves.hpp"
#include "gcode/cutter_comp.hpp"
#include "geometry/biarc.hpp"

namespace pcnc {

// A G1 move that may belong to a smooth run: in an active session after the entry, a feed move
// shorter than fit_segment_max_mm in the plane with no motion along the normal, at the run's
// feed, turning less than the contouring angle from the move before it in the run.
bool CutterComp::run_candidate(const Move& m) const {
  if (!active_ || first_move_ || m.kind != MoveKind::kLine || m.inverse_time_s > 0.0) return false;
  if (m.comp.side == 0 || m.comp.serial != serial_) return false;
  if (oop(m.start) != oop(m.end)) return false;
  const Vec2 a = in_plane(m.start), b = in_plane(m.end);
  const double len = norm(b - a);
  if (!(len > 0.0) || len >= options_.fit_segment_max_mm) return false;
  if (run_.empty()) return true;
  const Move& prev = run_.back();
  if (prev.feed_mm_s != m.feed_mm_s || prev.contouring != m.contouring || oop(prev.end) != oop(m.start)) return false;
  const Vec2 t0 = in_plane(prev.end) - in_plane(prev.start), t1 = b - a;
  return std::fabs(std::atan2(cross(t0, t1), dot(t0, t1))) < options_.contouring_angle_rad;
}

void CutterComp::flush_run() {
  std::vector<Move> run;
  run.swap(run_);
  if (run.size() >= CompOptions::kMinRun) {
    std::vector<Vec2> points;
    points.reserve(run.size() + 1);
    points.push_back(in_plane(run.front().start));
    for (const Move& m : run) points.push_back(in_plane(m.end));
    BiarcOptions o;
    o.tolerance_mm = options_.fit_tolerance_mm;
    const PolylineFit fit = fit_biarcs_polyline(points, o);
    if (fit.within_tolerance && !fit.arcs.empty()) {
      ++figures_.fitted_runs;
      figures_.moves_replaced += run.size();
      figures_.biarcs += fit.biarcs;
      figures_.fit_arcs += fit.arcs.size();
      figures_.max_fit_deviation_mm = std::max(figures_.max_fit_deviation_mm, fit.max_point_deviation_mm);
      for (Move& a : arc_moves(fit.arcs, normal_, oop(run.front().start), run.front())) {
        if (!active_) break;  // an error ended the session
        dispatch(a);
      }
      return;
    }
  }
  for (Move& m : run) {  // too short or not fitted: one by one, as LinuxCNC does
    if (!active_) {
      ready_.push_back(m);
      continue;
    }
    dispatch(m);
  }
}

void CutterComp::fit_nurbs(const Move& m) {
  if (first_move_) {
    fail(m, "a NURBS curve cannot be the entry move of cutter compensation; expected a G0, G1, G2 or G3 entry move "
            "after G41/G42");
    return;
  }
  const double level = oop(m.start);
  for (const Vec3& p : m.nurbs->points) {
    if (std::fabs(oop(p) - level) > 1e-9) {
      fail(m, std::string("a NURBS curve under cutter compensation must lie in the ") + plane_name(normal_) +
                  " plane (its control points all at one level along the normal); expected a planar curve");
      return;
    }
  }
  BiarcOptions o;
  o.tolerance_mm = options_.fit_tolerance_mm;
  const BiarcFit fit = fit_biarcs(*m.nurbs, normal_, o);
  if (!fit.within_tolerance || fit.arcs.empty()) {
    fail(m, "the NURBS curve could not be fitted with biarcs within " + std::to_string(options_.fit_tolerance_mm) +
                " mm for cutter compensation (deviation " + std::to_string(fit.max_deviation_mm) +
                " mm); expected a smoother curve or a larger cutter_comp.fit_tolerance_mm");
    return;
  }
  ++figures_.fitted_nurbs;
  ++figures_.moves_replaced;
  figures_.biarcs += fit.biarcs;
  figures_.fit_arcs += fit.arcs.size();
  figures_.max_fit_deviation_mm = std::max(figures_.max_fit_deviation_mm, fit.max_deviation_mm);
  for (Move& a : arc_moves(fit.arcs, normal_, level, m)) {
    if (!active_) break;
    dispatch(a);
  }
}

}  // namespace pcnc
