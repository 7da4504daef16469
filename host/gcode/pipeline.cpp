// pipeline.cpp — the front-end chain, linked in its one order (see pipeline.hpp).
#include "gcode/pipeline.hpp"

#include <string>

#include "gcode/nurbs_move.hpp"
#include "gcode/preprocessor.hpp"

namespace pcnc {

Pipeline::Pipeline(std::unique_ptr<LineReader> reader, const MachineConfig& config, const JobFrame& frame,
                   DiagnosticSink& sink, bool soft_limits)
    : config_(config),
      sink_(sink),
      reader_(std::move(reader)),
      source_(*reader_, config_, frame, sink_),
      preflight_(config_, sink_, soft_limits),
      smoother_(config_),
      to_smoother_([this](Move& m) { return source_.next(m); }),
      validator_(config_, frame.start),
      to_merge_([this](Move& m) { return checked_move(m); }) {}

// The interpreter's moves through the geometry stages, in their order; each links as
// `<stage>_.next(<pull from the stage before>, m)`: cutter compensation, then surface
// correction (not yet), then smoothing.
bool Pipeline::geometry_move(Move& m) { return smoother_.next(to_smoother_, m); }

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
  if (v.fault == FaultCode::kNone) return true;
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
    nurbs_ = std::move(nb.blocks);
    nurbs_next_ = 1;
    out = nurbs_.front();
    return accept(out);
  }
  make_block_into(m, config_, out);
  return accept(out);
}

void Pipeline::drain() {
  Move m;
  while (checked_move(m)) {
  }
}

}  // namespace pcnc
