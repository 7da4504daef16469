// interpreter.hpp — third stage of the G-code front end: the modal state machine.
//
// Executes parsed lines in RS274 order (feed, spindle/coolant/tool words, dwell, plane, units,
// tool length, coordinate system, path control, distance mode, retract mode, G10/G28/G30/
// G52/G92, motion and canned cycles, stop) and emits Moves in machine millimetres. Every word
// is executed, accepted with a warning (no meaning on this machine) or rejected with an error
// naming the word; docs/gcode.md is the list. The offsets live where LinuxCNC keeps them, in
// the numbered parameters (#5161-#5390, always in mm): machine = program point + G5x offset +
// G92/G52 offset + tool length offset, then the job's --fit scale. The interpreter holds O(1)
// state, so it streams programs of any length; the one exception is an open NURBS group
// (G5.2 ... G5.3, G6.2 ... closing knots), whose control points it collects (at most
// kMaxNurbsCurvePoints) until the curve is complete and handed on as one Move.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <memory>
#include <optional>
#include <string_view>

#include "config/config.hpp"
#include "config/work_state.hpp"
#include "gcode/canned_cycle.hpp"
#include "gcode/diagnostics.hpp"
#include "gcode/move.hpp"
#include "gcode/parameters.hpp"
#include "gcode/parser.hpp"
#include "gcode/probe_results.hpp"
#include "gcode/ruled_reader.hpp"
#include "gcode/tool_table.hpp"
#include "geometry/bspline_surface.hpp"

namespace pcnc {

/// Where the program sits on the machine: machine = scale * q + offset, where q is the program
/// point in mm relative to the G54 frame (a point in work system k is shifted by the config's
/// work_offsets[k] - work_offsets[0]).
struct JobFrame {
  Vec3 offset{};
  double scale = 1.0;
  int work_offset_index = 0;  // initial G54..G59.3 selection (0..8)
  Vec3 start{};               // machine position before the first move
  std::optional<Rot3> rot_start;  // the rotary joints before the first move (rad); unset: their homes
  bool contouring = false;    // initial M21/M22 state
  // Offsets, G92 and the stored G28/G30 positions at the start (the state file's; g5x[0] is
  // the G54 that `offset` was made from). Unset: the config's defaults.
  std::optional<WorkState> work;
  std::shared_ptr<const ToolTable> tools;  // null: no tool table (tools have length 0)
  // --surface: the measured surface the pipeline corrects Z by (gcode/surface_correction.hpp);
  // null: none. The reference is its height at `offset`'s X/Y.
  std::shared_ptr<const BSplineSurface> surface;
  // The results of the program's probing moves known so far (docs/probe.md); null: none known,
  // each probing move assumed to touch at its commanded end (check).
  std::shared_ptr<const ProbeResults> probe;
};

/// The moves one line makes (a canned cycle with repeats makes many); reused line after line.
struct MoveList {
  static constexpr int kMaxPerLine = 100000;
  std::vector<Move> moves;
  int count = 0;
  void clear() { count = 0; }
  void push(const Move& m) {
    if (count < static_cast<int>(moves.size())) {
      moves[static_cast<std::size_t>(count)] = m;
    } else {
      moves.push_back(m);
    }
    ++count;
  }
};

class Interpreter : public SystemParameters {
 public:
  Interpreter(const MachineConfig& config, const JobFrame& frame, DiagnosticSink& sink, ParameterStore& params);

  /// Executes one line; appends its moves to `out`. On an error (reported to the sink) the line
  /// produces no moves. Returns false on error.
  bool execute(const ParsedLine& line, MoveList& out);

  /// The source line about to run (#<_line> reads it, also in the line's own messages).
  void set_line(int line) { last_line_ = line; }
  /// True once M2/M30 has been executed.
  bool ended() const { return ended_; }
  /// Subroutine call levels (M70-M73 keep a saved modal state per level; MoveSource follows the
  /// control flow's calls): 0 in the main program.
  std::size_t call_level() const { return modal_levels_.size() - 1; }
  void enter_call();
  /// Leaving a call: what an M73 saved at that level is restored (errors at `line`).
  void leave_call(int line);
  /// The input ended (end of file or closing '%') at `line`: reports a NURBS group left open.
  void end_of_input(int line);
  /// The End move used when the file ends without M2/M30.
  Move end_move(int line) const;
  /// The rotary joints now (rad) and whether TCP is on.
  const Rot3& rotary() const { return rot_; }
  bool tcp() const { return tcp_; }
  /// Current position, machine coordinates.
  Vec3 position() const { return to_machine(q_); }
  /// Machine maximum path feed, mm/s (config max_feed_mm_min, else the fastest axis).
  double max_feed_mm_s() const { return max_feed_mm_s_; }
  /// The work state now (offsets, G92, G28/G30 positions in mm), for the state file.
  WorkState work_state() const;
  /// A program's '#n=' (numbered parameters; the offsets' parameters included).
  bool write_parameter(int number, double value, std::string& why);

  // SystemParameters: #5400-#5428 and #<_x>, #<_metric>, ...
  bool numbered(int number, double& value) const override;
  bool named(std::string_view name, double& value) const override;

  // Probing (G38.2-G38.5, interpreter_probe.cpp; docs/probe.md).
  /// A probing move beyond the known results ran with ProbeResults::stop_at_unknown: nothing
  /// after it may be interpreted until its result is known.
  bool probe_sync() const { return probe_sync_; }
  /// Probing moves executed so far; the source lines of those assumed to touch at their end.
  int probes() const { return probes_; }
  const std::vector<int>& assumed_probe_lines() const { return assumed_probe_lines_; }
  /// (PROBEOPEN name) / (PROBECLOSE): the probe log in effect ("" none).
  void set_probe_log(std::string name) { probe_log_ = std::move(name); }
  const std::string& probe_log() const { return probe_log_; }
  // Ruled-surface groups (G5.4 ... G5.5, interpreter_ruled.cpp; read by gcode/ruled_reader.hpp).
  /// The machine has rotary joints and 5-axis kinematics (G5.4 needs them).
  bool ruled_machine() const;
  /// The modal state the group reader's rules need now.
  RuledModal ruled_modal(bool in_nurbs_group = false) const;
  /// A group closed without errors: placed, checked against the current pose, made a kRuled
  /// Move (the joints walked to its end). False on error (reported at the group's lines).
  bool ruled_group(const RuledGroup& group, MoveList& out);
  /// A machine point in the current work coordinates and units (what #5061-#5063 hold).
  Vec3 to_program(const Vec3& machine) const;

 private:
  bool check_words(const ParsedLine& l);
  bool nurbs_open(const ParsedLine& l, int motion, MoveList& out);
  bool nurbs_line(const ParsedLine& l, MoveList& out);
  bool nurbs_fail(const ParsedLine& l, int column, std::string message);
  bool nurbs_point_line(const ParsedLine& l);
  bool nurbs_knot(const ParsedLine& l);
  bool nurbs_close(const ParsedLine& l, MoveList& out);
  void nurbs_abandon();
  bool straight(const ParsedLine& l, int motion, bool g53, MoveList& out);
  bool arc(const ParsedLine& l, int motion, MoveList& out);
  bool spline(const ParsedLine& l, int motion, MoveList& out);  // G5, G5.1 (interpreter_spline.cpp)
  bool home(const ParsedLine& l, MoveList& out);  // G28/G30 and their .1 forms
  bool path_tolerance(const ParsedLine& l);       // G64 [P]
  bool probe(const ParsedLine& l, int motion, MoveList& out);  // G38.2-G38.5
  bool set_offsets(const ParsedLine& l);   // G10 L1/L2/L10/L11/L20
  bool axis_offset(const ParsedLine& l);   // G52, G92, G92.1-G92.3
  bool tool_words(const ParsedLine& l);    // T, M6, M61, G43/G43.1/G49
  // Rotary joints and TCP (interpreter_rotary.cpp)
  std::uint32_t rotary_bits() const;       // the A/B/C letters of the machine's joints
  Rot3 rotary_target(const ParsedLine& l) const;  // the joints the A/B/C words of `l` name (rad)
  bool tcp_words(const ParsedLine& l);     // M428/G43.4 on, M429/G49 off
  // M70-M73: save, invalidate, restore, save with restore on return (interpreter_modal_state.cpp)
  struct SavedModal {
    bool inches = false, incremental = false, inverse_time = false, arc_absolute = false, retract_r = false;
    bool contouring = false, tool_offset_on = false;
    int normal_axis = 2, work_index = 0;
    double feed = 0.0, path_tolerance = 0.0;
    Vec3 tlo{};
    std::uint8_t comp_side = 0, comp_plane = 2;
  };
  struct ModalLevel {
    std::optional<SavedModal> saved;
    bool autorestore = false;  // M73: restored when the call returns
  };
  SavedModal save_modal() const;
  bool restore_modal(const SavedModal& s, int line, int column, const char* by);
  bool modal_state_words(const ParsedLine& l);
  double tcp_tool_length(int tool) const;  // the length (mm) of `tool` from the tool table
  bool comp_forbids(const ParsedLine& l);  // what cannot happen with cutter compensation on
  bool comp_words(const ParsedLine& l);    // G40, G41/G42, G41.1/G42.1 (interpreter_comp.cpp)
  bool cycle(const ParsedLine& l, int motion, bool first_of_series, MoveList& out);
  void select_system(int index);           // makes g5x_ the offset of system index (0..8)
  void update_origin();                    // origin_ from g5x_, g92_, tlo_
  Vec3 program_point() const;              // the current point in program coordinates (mm)
  Vec3 param_vec(int base) const;          // #base..#base+2 (mm)
  void set_param_vec(int base, const Vec3& v_mm);
  bool feed_for_move(const ParsedLine& l, int column, double& feed_mm_s, int motion = 10);
  // G93/G94 (interpreter_feed_mode.cpp): the mode, and a G93 move's feed from its length
  void feed_mode(const ParsedLine& l);
  bool inverse_time_check(const ParsedLine& l, int column, int motion);
  bool inverse_time_feed(const ParsedLine& l, Move& m);
  Vec3 axis_target(const ParsedLine& l, const Vec3& from, std::uint8_t& known, int& first_col) const;
  Vec3 to_machine(const Vec3& q) const { return frame_.scale * q + frame_.offset; }
  Vec3 to_job(const Vec3& m) const { return (1.0 / frame_.scale) * (m - frame_.offset); }
  Move base_move(MoveKind kind, const ParsedLine& l, int column) const;
  bool axis_words(const ParsedLine& l) const { return (l.present & (kAxisBits | kPolarBits)) != 0; }
  bool polar_words_fit(const ParsedLine& l, int motion, int normal);  // interpreter_motion.cpp
  // G10, G28/G30, G52, G92, G43.1 and G43.2 take the line's axis words for themselves: no motion (LinuxCNC)
  static bool takes_axis_words(const ParsedLine& l) {
    const int n = l.g[kGNonModal];
    return n == 280 || n == 300 || n == 100 || n == 520 || n == 920 || l.g[kGToolLength] == 431 || l.g[kGToolLength] == 432;
  }
  // The message is built only for the first occurrence of its key (repeats are just counted).
  template <class MakeMessage>
  void warn(const ParsedLine& l, int column, std::string_view key, MakeMessage&& make) {
    if (sink_.repeat(key)) return;
    sink_.warning(l.line, column, key, make());
  }
  bool fail(const ParsedLine& l, int column, std::string message) {
    sink_.error(l.line, column, std::move(message));
    return false;
  }

  static constexpr std::uint32_t bit(char c) { return 1u << word_slot(c); }
  static constexpr std::uint32_t kAxisBits = (1u << ('X' - 'A')) | (1u << ('Y' - 'A')) | (1u << ('Z' - 'A'));
  static constexpr std::uint32_t kPolarBits = (1u << word_slot('@')) | (1u << word_slot('^'));

  const MachineConfig& config_;
  JobFrame frame_;
  DiagnosticSink& sink_;
  ParameterStore& params_;
  double max_feed_mm_s_ = 0.0;

  // offsets (mm): machine (before the --fit scale) = program point + g5x_ + g92_ + tlo_;
  // the job frame is relative to base_ (the G54 offset the frame was made from)
  Vec3 g5x_{};
  Vec3 g92_{};
  Vec3 tlo_{};
  Vec3 base_{};
  Vec3 origin_{};  // g5x_ + g92_ + tlo_ - base_
  ToolTable tools_;
  bool have_tools_ = false;
  int tool_ = 0;            // in the spindle (M6/M61)
  int selected_tool_ = -1;  // T, -1 = none
  bool tool_offset_on_ = false;
  bool retract_r_ = false;  // G99 (else G98)
  bool arc_absolute_ = false;  // G90.1 (else G91.1)
  CannedCycleModal cycle_{};
  int last_line_ = 0;

  // modal state
  Vec3 q_{};                  // current point, job frame (mm)
  std::uint8_t known_ = 0;    // axes set by the program since the start
  int motion_ = -1;           // G code x10 of the motion mode, -1 = none (G80)
  int normal_axis_ = 2;       // G17
  bool inches_ = false;       // G20
  bool incremental_ = false;  // G91
  int work_index_ = 0;
  double feed_ = 0.0;  // F as written, current units per minute (G94; G93 reads each line's F)
  bool inverse_time_ = false;  // G93: every G1/G2/G3 line's F is 1/(its time in minutes)
  int feed_cleared_line_ = 0;  // the G94 that set a nonzero feed to 0 (LinuxCNC), for the message
  bool contouring_ = false;
  double path_tolerance_ = 0.0;  // mm: G64 P, else the config's (an operator's --tolerance in it)
  bool ended_ = false;
  int probes_ = 0;             // probing moves executed
  bool probe_sync_ = false;
  std::vector<int> assumed_probe_lines_;
  std::string probe_log_;
  // G5 series: the last move was a G5, and the offset from its end to the next G5's first
  // control point when that one has no I and J (the previous -P, -Q; job frame mm)
  bool spline_series_ = false;
  Vec3 spline_next_{};
  MoveComp comp_{};  // cutter radius compensation, carried on every move
  std::vector<ModalLevel> modal_levels_{1};  // [0]: the main program; one more per call running
  Rot3 rot_{};                // rotary joints now, machine angles (rad)
  bool tcp_ = false;          // M428/G43.4 in effect: q_ is the tool tip
  double tcp_length_ = 0.0;   // the tool length applied along the tool axis under TCP, mm

  // An open NURBS group: LinuxCNC's G5.2 ... G5.3 or Fanuc's G6.2 ... closing knot-only lines.
  struct NurbsGroup {
    bool open = false;
    bool fanuc = false;    // G6.2 (explicit knots), else G5.2
    bool failed = false;   // an error was reported inside: read to its end without a move
    int line = 0;          // the opening line and the column of its G word
    int column = 0;
    int order = 3;
    int closing = 0;       // G6.2: knot-only lines read so far
    int normal_axis = 2;   // G5.2: plane at the opening line
    double feed_mm_s = 0.0;
    std::uint8_t known = 0;
    std::vector<Vec3> points;  // job frame, mm; the first is the position at the opening line
    std::vector<double> weights;
    std::vector<double> knots;  // G6.2 only
  };
  NurbsGroup nurbs_;
};

}  // namespace pcnc
