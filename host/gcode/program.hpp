// program.hpp — the entry points of the G-code front end: check a whole program, then stream
// its ring Blocks. Both run the one pipeline (gcode/pipeline.hpp: lexer -> parser ->
// interpreter -> [geometry stages] -> preflight -> segment merge -> preprocessor -> the rt's
// block check), reading the file line by line with O(1) memory. Check runs it to the blocks and
// validates each with the rt's own check_block, so what check accepts is exactly what is sent.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "gcode/time_cause.hpp"
#include "ipc/block.hpp"
#include "config/config.hpp"
#include "config/work_state.hpp"
#include "gcode/cutter_comp.hpp"
#include "gcode/diagnostics.hpp"
#include "gcode/line_feed.hpp"
#include "gcode/move.hpp"
#include "gcode/move_source.hpp"
#include "gcode/check_progress.hpp"
#include "gcode/probe_results.hpp"
#include "gcode/tool_table.hpp"
#include "geometry/bspline_surface.hpp"
#include "geometry/vec3.hpp"

namespace pcnc {

struct JobOptions {
  int work_offset_index = 0;       // 0 = G54 ... 5 = G59 default selection (program may select another)
  std::optional<Vec3> offset;      // --offset X,Y,Z: overrides the config's G54 value (program zero in machine coords)
  bool fit = false;                // --fit: scale uniformly (factor <= 1) so the program fits the travel; also recentre
  std::optional<bool> contouring;  // --contouring on|off, else config motion.contouring_default
  // Machine position before the first move (the launcher passes the rt's actual position).
  // Default: program zero (the G54 point after --offset/--fit) clamped into the travel.
  std::optional<Vec3> start_position;
  std::optional<Rot3> start_rotary;  // the rotary joints before the first move (rad); unset: their homes
  // The work offsets, G92 and G28/G30 positions at the start (the state file's); unset: the
  // config's. --offset replaces its G54.
  std::optional<WorkState> work;
  std::shared_ptr<const ToolTable> tools;  // --tool-table / gcode.tool_table; null: none
  std::shared_ptr<const BSplineSurface> surface;  // --surface S.json; null: no surface correction
  // Probing moves' results known so far, and whether a stream stops at the next (docs/probe.md);
  // null: none known, every probing move assumed to touch at its commanded end.
  std::shared_ptr<const ProbeResults> probe;
  // (MSG,...), (DEBUG,...), (PRINT,...) as their lines run (in check and in the stream).
  MessageHandler on_message;
  // check_program's progress on a long program (gcode/check_progress.hpp); may throw
  // CheckInterrupted to end the check. None: no progress is reported.
  CheckProgressHandler on_check_progress;
  double check_progress_interval_s = 0.1;  // the least wall time between two reports (and before the first)
};

/// Completes `options` for a job on this machine: the work state from the state file
/// (work_state_path; none: the config's offsets), the tool table (`tool_table_path`, else
/// the config's gcode.tool_table; empty: none) and, unless options.surface is set, the
/// measured surface of gcode.surface (--surface sets that key; empty: none). Returns why it cannot (a corrupt state file, a
/// bad tool table: the messages name the file), or an empty string.
std::string load_job_state(const MachineConfig& config, const std::string& tool_table_path, JobOptions& options);

struct Transform {
  Vec3 offset{};
  double scale = 1.0;
};  // machine = scale * program + offset, reported to the user

/// Source lines first..last (inclusive).
struct LineRange {
  std::uint32_t first = 0;
  std::uint32_t last = 0;
};

struct CheckResult {
  std::vector<Diagnostic> diagnostics;
  bool ok = false;
  std::uint64_t lines = 0;
  std::uint64_t moves = 0;
  Transform transform;
  Vec3 min_point{}, max_point{};  // program extents in machine coords
  Vec3 last_point{};
  double feed_length_time_s = 0.0;  // sum of length/F over feed moves
  std::uint64_t blocks = 0;         // blocks made and accepted by the rt's check (what a run sends)
  double planned_time_s = 0.0;      // sum of the blocks' planned times (gcode/planned_time.hpp): the ETA's base
  // The tool length (mm, from the spindle's gauge point along the tool axis) of the blocks run
  // under tool-centre-point control: the tool table's for the tool in the spindle or G43.4 H;
  // the last TCP block's when they differ; 0 without TCP blocks. The report's tool-axis view
  // draws the tip with it.
  double tcp_tool_length_mm = 0.0;
  // Smoothing (gcode/smoothing.hpp): G1 moves made into curves, the curves and the ring blocks
  // they became, and the largest measured distance of a curve from its programmed moves.
  std::uint64_t smoothed_moves = 0;
  std::uint64_t smoothed_curves = 0;
  std::uint64_t smoothed_blocks = 0;
  double max_path_deviation_mm = 0.0;
  double smoothing_min_tolerance_mm = 0.0;  // the tolerances the curves were fitted to (G64 P may change it)
  double smoothing_max_tolerance_mm = 0.0;
  // Arc packing (gcode/arc_packing.hpp): arcs packed into exact curves, the curves, their ring
  // blocks, and the largest measured distance of a curve from its arcs.
  std::uint64_t packed_arcs = 0;
  std::uint64_t packed_curves = 0;
  std::uint64_t packed_blocks = 0;
  double packed_max_deviation_mm = 0.0;
  std::vector<LineRange> rapid_lines;  // source lines holding a rapid block, ascending runs (ok only)
  // What caps each block's speed and how its junctions are passed, per run of lines (ok
  // only): the run report attributes the trace's time to these causes (gcode/time_cause.hpp).
  std::vector<LinePlan> plan;
  // What cutter radius compensation did (G41/G42), and the programmed contour it offset.
  CompFigures comp;
  // Probing moves (docs/probe.md) whose result was not known: checked as if each touched at
  // its commanded end; their source lines.
  std::vector<int> assumed_probe_lines;
  // Every error the check found, also those beyond DiagnosticSink::kMaxErrors that
  // `diagnostics` only counts in its last note.
  std::uint64_t error_count = 0;
  // The check was ended early by its progress handler (CheckInterrupted): ok is false, with
  // one error at the line reached.
  bool interrupted = false;
};

/// Pass 1: reads the whole file through the whole pipeline: parses, interprets, checks soft
/// limits (after offset/scale), feeds, everything, makes every block and validates it with the
/// rt's block check (seq 1, 2, 3, ..., each starting where the last ended, the first at the
/// job's start position). A refused block is an error at its source line. The blocks are not
/// kept: memory does not grow with file length (rapid_lines aside, one entry per run of rapids,
/// and the plan: one entry per block at most, runs of lines with one plan merged).
/// A file that cannot be read gives ok = false with one error diagnostic. A `path` (or, for the
/// _text forms, a `name`) ending in ".json" is a ruled-surface program in the JSON file form, run
/// as its G-code form (gcode/ruled_json_input.hpp); the same holds for BlockStream.
/// Why `path` cannot be a program although it opens: a directory, FIFO, device or socket (only
/// regular files are read). Empty for a regular file, and for one that cannot be opened at
/// all (check_program reports that). Never blocks and reads nothing.
std::string program_file_problem(const std::string& path);
CheckResult check_program(const std::string& path, const MachineConfig& config, const JobOptions& options);
/// The same over text in memory (tests, fuzzing); `name` is used in messages.
CheckResult check_program_text(std::string_view text, const std::string& name, const MachineConfig& config,
                               const JobOptions& options);
/// The same, handing every block check made and accepted to `on_block`, in order (for a
/// program check accepts: exactly the blocks BlockStream streams).
CheckResult check_program(const std::string& path, const MachineConfig& config, const JobOptions& options,
                          const std::function<void(const Block&)>& on_block);
CheckResult check_program_text(std::string_view text, const std::string& name, const MachineConfig& config,
                               const JobOptions& options, const std::function<void(const Block&)>& on_block);

/// Pass 2: streams Blocks in program order through the same pipeline, each numbered (seq 1, 2,
/// 3, ..., as the ring feeder numbers them) and accepted by the rt's block check. Construct only
/// after check_program(...).ok, with its transform. Throws std::runtime_error if the program
/// turns out to have an error after all (e.g. the file changed since it was checked). The
/// stream keeps its own copy of `config`.
class BlockStream {
 public:
  BlockStream(const std::string& path, const MachineConfig& config, const JobOptions& options,
              const Transform& transform);
  struct FromText {};
  BlockStream(FromText, std::string_view text, const std::string& name, const MachineConfig& config,
              const JobOptions& options, const Transform& transform);
  /// A streamed program (the grbl port): lines are read from `feed` as they arrive, each checked
  /// as it passes (words, modal state, soft limits of its moves, the rt's block check); there
  /// is no check of the whole program first, and an error ends the stream: next() returns
  /// false and error() holds it (it does not throw). The frame is the job's without --fit.
  struct FromFeed {};
  BlockStream(FromFeed, std::shared_ptr<LineFeed> feed, const std::string& name, const MachineConfig& config,
              const JobOptions& options);
  ~BlockStream();
  BlockStream(BlockStream&&) noexcept;
  BlockStream& operator=(BlockStream&&) noexcept;

  bool next(Block& out);             // false at end of program (after the End block was returned)
  /// An error has been found (no block is made from here on).
  bool failed() const;
  /// FromFeed: the error that ended the stream (next() returned false), if any.
  const std::optional<Diagnostic>& error() const;
  std::uint64_t lines_read() const;  // for progress
  std::uint64_t total_bytes() const;
  std::uint64_t bytes_read() const;
  /// The offsets and stored positions as the program has left them (G10, G92, G28.1...), for
  /// the state file once the program has run to its end.
  WorkState work_state() const;

  /// The stream ended at a probing move whose result is not known yet (JobOptions::probe with
  /// stop_at_unknown): its block was the last one; the rest needs a new stream with the result.
  bool probe_sync() const;
  /// At the sync point: the probe log the program has open ("" none), and a machine point in
  /// the work coordinates and units of the probing line (what #5061-#5063 hold).
  std::string probe_log() const;
  Vec3 to_program(const Vec3& machine) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// The stable one-line text form used by `pcnc check --print-blocks` and the golden tests.
std::string format_block(const Block& b);

/// `pcnc check --print-moves`: the program through the front end only (lexer, control flow,
/// interpreter and cutter compensation), each move handed to `on_move` and
/// each message comment to `on_message` in program order. The travel and the blocks are not
/// checked (that is check_program's), as LinuxCNC's interpreter does not: ok means the
/// program is valid G-code. The work state after the program (G10, G92, G28.1...) is returned
/// in `work` for a caller that keeps it.
struct MoveListing {
  std::vector<Diagnostic> diagnostics;
  bool ok = false;
  std::uint64_t lines = 0;
  std::uint64_t moves = 0;
  WorkState work;
};
MoveListing list_moves(const std::string& path, const MachineConfig& config, const JobOptions& options,
                       const std::function<void(const Move&)>& on_move, const MessageHandler& on_message);
/// The same moves in the frame of a checked job (`check_program(...).transform`: --fit's scale
/// and offset), as its stream makes them: what a model of another planner is fed
/// (report/ideal_planner.hpp).
MoveListing list_moves(const std::string& path, const MachineConfig& config, const JobOptions& options,
                       const Transform& transform, const std::function<void(const Move&)>& on_move);
MoveListing list_moves_text(std::string_view text, const std::string& name, const MachineConfig& config,
                            const JobOptions& options, const std::function<void(const Move&)>& on_move,
                            const MessageHandler& on_message);

/// The one-line form of a move for --print-moves: "L<line> <kind> (x,y,z)->(x,y,z)", machine
/// mm with six decimals. Kinds: rapid, line, arc, nurbs, dwell. Pauses and the end are not
/// moves (empty string).
std::string format_move(const Move& m);

}  // namespace pcnc
