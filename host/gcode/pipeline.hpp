// pipeline.hpp — the one definition of the G-code front end, from source text to ring blocks.
// `pcnc check`, `pcnc run` and the service's jobs run this chain through program.hpp's
// check_program and BlockStream, its two thin users (MDI is to use them too: a line of text is
// a program); the run report draws on what the run's check recorded, not on a chain of its own.
//
// The stages, in their one fixed order; each hands plain values (Move, Block) to the next:
//
//   LineReader   source text, line by line, in fixed memory            (line_reader.hpp;
//                a .json ruled-surface program: its G-code form, ruled_json_input.hpp)
//   MoveSource   lexer -> parser -> interpreter: Moves in machine mm   (move_source.hpp)
//   CutterComp   G41/G42: the tool centre's path (LinuxCNC's moves)   (cutter_comp.hpp)
//   SurfaceCorrection  --surface: Z by a measured surface, optional    (surface_correction.hpp)
//   Smoother     runs of G1 moves -> curves within the path tolerance  (smoothing.hpp)
//   ArcPacker    chains of short tangent arcs -> one exact NURBS curve  (arc_packing.hpp)
//   ArcSplitter  M21 arcs in a plane of unequal axis limits -> pieces   (arc_split.hpp)
//                whose speed caps follow the angles each sweeps
//   Preflight    the whole program: soft limits, extents, feed time    (preflight.hpp)
//                (sees every programmed move; moves without displacement end here)
//   SegmentMerger  packing for the ring: collinear G1 runs -> one line  (segment_merge.hpp)
//   preprocessor one Move -> one Block; a NURBS move -> its pieces      (preprocessor.hpp,
//                                                                        nurbs_move.hpp)
//   BlockValidator the rt's own block check, seq 1, 2, 3, ...          (block_validator.hpp)
//
// A new geometry stage is a class with `bool next(const MovePull& pull, Move& out)` (the shape
// of SegmentMerger), a member of Pipeline, linked in Pipeline::geometry_move in its place in
// the order: the preflight then checks the path that will be cut, and the rt's check its blocks.
//
// Errors: every stage reports to the DiagnosticSink. From the first error on, no block is
// made: next() returns false and failed() is true; drain() then runs the front end to the end
// of the program for the rest of its diagnostics and figures.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "config/config.hpp"
#include "gcode/arc_packing.hpp"
#include "gcode/arc_split.hpp"
#include "gcode/block_validator.hpp"
#include "gcode/cutter_comp.hpp"
#include "gcode/diagnostics.hpp"
#include "gcode/interpreter.hpp"
#include "gcode/line_reader.hpp"
#include "gcode/move_source.hpp"
#include "gcode/preflight.hpp"
#include "gcode/segment_merge.hpp"
#include "gcode/surface_correction.hpp"
#include "gcode/smoothing.hpp"
#include "ipc/block.hpp"

namespace pcnc {

/// One stage's input: yields the next Move and returns true, or returns false at the end.
using MovePull = std::function<bool(Move&)>;

class Pipeline {
 public:
  /// `soft_limits`: the preflight reports points outside the travel (off only while --fit
  /// measures the program). The pipeline keeps its own copy of `config`.
  Pipeline(std::unique_ptr<LineReader> reader, const MachineConfig& config, const JobFrame& frame,
           DiagnosticSink& sink, bool soft_limits = true);
  Pipeline(const Pipeline&) = delete;
  Pipeline& operator=(const Pipeline&) = delete;

  /// The next block, numbered (seq) and accepted by the rt's block check. False at the end of
  /// the program, or once an error has been reported (then failed()).
  bool next(Block& out);
  /// Runs the front end (up to and including the preflight) to the end of the program
  /// without making blocks: the --fit measuring pass, or the rest of a failed program.
  void drain();

  /// The moves as the program defines them: the interpreter's, through cutter compensation
  /// and surface correction (what LinuxCNC's interpreter would hand its motion planner), not
  /// yet smoothed: `pcnc check --print-moves`. False after the End move.
  /// Not to be mixed with next()/drain() on one pipeline.
  bool front_end_move(Move& m) {
    const bool more = to_smoother_(m);
    m.line = sink_.file_line(m.line);  // a made program's line as its file's
    return more;
  }
  /// Message comments ((MSG,...), (DEBUG,...), (PRINT,...)) as their lines run.
  void set_message_handler(MessageHandler handler) { source_.set_message_handler(std::move(handler)); }
  /// Called every MoveSource::kLineHookEvery lines the program runs (the progress of a long
  /// check, program.cpp); the hook may throw to end the pipeline's work.
  void set_progress_hook(std::function<void()> hook) { source_.set_line_hook(std::move(hook)); }
  /// The offsets and stored positions as the program has left them so far.
  WorkState work_state() const { return source_.interpreter().work_state(); }
  /// The interpreter as it stands (probing: the sync point, the assumed probes, the probe log).
  const Interpreter& interpreter() const { return source_.interpreter(); }

  bool failed() const { return sink_.has_errors(); }
  const Preflight& preflight() const { return preflight_; }
  /// --fit's measuring pass on a machine with rotary joints: collect the moves' poses.
  void collect_fit_poses(std::vector<FitPose>* out, double* tool_length) { preflight_.collect_fit_poses(out, tool_length); }
  const CompFigures& comp_figures() const { return comp_.figures(); }
  /// What smoothing did so far; `blocks` counts the ring blocks its curves became.
  const SmoothingStats& smoothing() const { return smoother_.stats(); }
  std::uint64_t smoothed_blocks() const { return smoothed_blocks_; }
  /// What arc packing did so far; `packed_blocks` counts the ring blocks its curves became.
  const ArcPackingStats& arc_packing() const { return packer_.stats(); }
  std::uint64_t packed_blocks() const { return packed_blocks_; }
  const LineReader& reader() const { return *reader_; }
  std::uint64_t lines() const { return source_.lines(); }

 private:
  bool geometry_move(Move& m);  // the source through the geometry stages
  bool checked_move(Move& m);   // ... through the preflight (null moves end there)
  bool accept(Block& b);       // the block check; false (and an error) when refused

  MachineConfig config_;
  DiagnosticSink& sink_;
  std::unique_ptr<LineReader> reader_;
  MoveSource source_;
  CutterComp comp_;
  MovePull from_source_;        // the interpreter's output, the compensation's input
  Preflight preflight_;
  Smoother smoother_;
  MovePull to_smoother_;        // the source's output, the smoother's input
  ArcPacker packer_;
  MovePull to_packer_;          // the smoother's output, the arc packer's input
  ArcSplitter splitter_;
  MovePull to_splitter_;        // the arc packer's output, the arc splitter's input
  SegmentMerger merge_;
  BlockValidator validator_;
  MovePull to_merge_;           // the preflight's output, the merge's input
  std::unique_ptr<SurfaceCorrection> surface_;  // --surface; null: none
  MovePull to_surface_;         // the stage before surface correction
  bool source_ended_ = false;   // the End move has passed and the program's end was checked
  std::vector<Block> nurbs_;    // the blocks of the NURBS (or ruled) move being handed out (one move at a time)
  std::size_t nurbs_next_ = 0;
  std::uint64_t smoothed_blocks_ = 0;
  std::uint64_t packed_blocks_ = 0;
};

}  // namespace pcnc
