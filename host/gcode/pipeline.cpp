// pipeline.cpp — the front-end chain, linked in its one order (see pipeline.hpp).
#include "gcode/pipeline.hpp"

#include <algorithm>
#include <string>

#include "gcode/nurbs_move.hpp"
#include "gcode/preprocessor.hpp"
#include "gcode/rotary_move.hpp"
#include "gcode/ruled_move.hpp"
#include "gcode/tcp_move.hpp"

namespace pcnc {

namespace {
CompOptions comp_options(const MachineConfig& c) {
  CompOptions o;
  o.gouge_check = c.cutter_comp.gouge_check;
  o.fit_segment_max_mm = c.cutter_comp.fit_segment_max_mm;
  o.fit_tolerance_mm = c.cutter_comp.fit_tolerance_mm;
  o.contouring_angle_rad = c.motion.contouring_angle_deg * 3.14159265358979323846 / 180.0;
  o.max_feed_mm_s = c.gcode.max_feed_mm_min > 0.0 ? c.gcode.max_feed_mm_min / 60.0 : 0.0;
  if (o.max_feed_mm_s <= 0.0) {
    for (const AxisConfig& a : c.axes) o.max_feed_mm_s = std::max(o.max_feed_mm_s, a.max_velocity_mm_s);
  }
  return o;
}
}  // namespace

Pipeline::Pipeline(std::unique_ptr<LineReader> reader, const MachineConfig& config, const JobFrame& frame,
                   DiagnosticSink& sink, bool soft_limits)
    : config_(config),
      sink_(sink),
      reader_(std::move(reader)),
      source_(*reader_, config_, frame, sink_),
      comp_(sink_, comp_options(config_)),
      from_source_([this](Move& m) { return source_.next(m); }),
      preflight_(config_, sink_, soft_limits),
      smoother_(config_),
      to_smoother_([this](Move& m) { return surface_ ? surface_->next(to_surface_, m) : comp_.next(from_source_, m); }),
      packer_(config_),
      to_packer_([this](Move& m) { return smoother_.next(to_smoother_, m); }),
      splitter_(config_),
      to_splitter_([this](Move& m) { return packer_.next(to_packer_, m); }),
      validator_(config_, frame.start, frame.rot_start),
      to_merge_([this](Move& m) { return checked_move(m); }),
      to_surface_([this](Move& m) { return comp_.next(from_source_, m); }) {
  // a program made from another file form: its diagnostics and blocks name that file's places
  if (reader_->source_places()) sink_.set_source_places(reader_->source_places());
  if (frame.surface) {
    // the path tolerance when there is one, else gcode.surface_tolerance_mm
    const double tol = config_.motion.path_tolerance_mm > 0.0 ? config_.motion.path_tolerance_mm
                                                              : config_.gcode.surface_tolerance_mm;
    surface_ = std::make_unique<SurfaceCorrection>(
        frame.surface, SurfaceCorrection::reference_at(*frame.surface, frame.offset), tol, &sink_);
  }
}

// The interpreter's moves through the geometry stages, in their order; each links as
// `<stage>.next(<pull from the stage before>, m)`: cutter compensation, then surface
// correction (with --surface), then smoothing, then arc packing, then arc splitting.
bool Pipeline::geometry_move(Move& m) { return splitter_.next(to_splitter_, m); }

// ... then the preflight, which sees every move; a move without displacement ends there.
bool Pipeline::checked_move(Move& m) {
  for (;;) {
    if (source_ended_ || !geometry_move(m)) {
      if (!source_ended_) {
        source_ended_ = true;
        source_.check_trailing();
        preflight_.finish();
      }
      return false;
    }
    preflight_.add(m);
    if (!is_null_move(m)) return true;  // checked, but never sent
  }
}

bool Pipeline::accept(Block& b) {
  const BlockVerdict v = validator_.check(b);
  if (v.fault == FaultCode::kNone) {
    b.line = static_cast<std::uint32_t>(sink_.file_line(static_cast<int>(b.line)));
    return true;
  }
  sink_.error(static_cast<int>(b.line), 0, describe_refusal(b, v));
  return false;
}

bool Pipeline::next(Block& out) {
  if (failed()) return false;
  if (nurbs_next_ < nurbs_.size()) {
    out = nurbs_[nurbs_next_++];
    return accept(out);
  }
  Move m;
  if (!merge_.next(to_merge_, m) || failed()) return false;
  if (m.kind == MoveKind::kNurbs) {
    NurbsMoveBlocks nb = plan_nurbs_move(m, config_);
    if (!nb.error.empty() || nb.blocks.empty()) {
      sink_.error(m.line, m.column,
                  "NURBS curve could not be planned: " + (nb.error.empty() ? std::string("no blocks") : nb.error));
      return false;
    }
    if (m.smoothed) smoothed_blocks_ += nb.blocks.size();
    if (m.packed_arcs) packed_blocks_ += nb.blocks.size();
    nurbs_ = std::move(nb.blocks);
    nurbs_next_ = 1;
    out = nurbs_.front();
    return accept(out);
  }
  if (m.kind == MoveKind::kRuled) {
    // a ruled piece: one block per part (ruled_move.hpp), handed out like a NURBS curve's
    RuledMoveBlocks rb = plan_ruled_move(m, config_);
    if (!rb.error.empty() || rb.blocks.empty()) {
      sink_.error(m.line, m.column,
                  "ruled piece could not be planned: " + (rb.error.empty() ? std::string("no blocks") : rb.error));
      return false;
    }
    nurbs_ = std::move(rb.blocks);
    nurbs_next_ = 1;
    out = nurbs_.front();
    return accept(out);
  }
  make_block_into(m, config_, out);
  if (m.tcp && (m.kind == MoveKind::kLine || m.kind == MoveKind::kRapid)) {
    const bool angular = angular_move(m);
    const double feed = angular ? (m.kind == MoveKind::kRapid ? 1e9 : m.feed_mm_s) : out.speed;
    const TcpMovePlan plan = plan_tcp_move(m, config_, feed);
    if (!plan.error.empty()) {
      sink_.error(m.line, m.column, plan.error);
      return false;
    }
    apply_tcp_plan(m, plan, out);
  }
  return accept(out);
}

void Pipeline::drain() {
  Move m;
  while (checked_move(m)) {
  }
}

}  // namespace pcnc
