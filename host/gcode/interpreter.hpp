// interpreter.hpp — third stage of the G-code front end: the modal state machine.
//
// Executes parsed lines in RS274 order (feed, spindle/coolant/tool words, dwell, plane, units,
// offsets, path control, distance mode, motion, stop) and emits Moves in machine millimetres.
// Every word is executed, accepted with a warning (no meaning on this machine) or rejected with
// an error naming the word; docs/gcode.md is the list. The interpreter holds O(1) state, so it
// streams programs of any length; the one exception is an open NURBS group (G5.2 ... G5.3,
// G6.2 ... closing knots), whose control points it collects (at most kMaxNurbsCurvePoints)
// until the curve is complete and handed on as one Move.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "config/config.hpp"
#include "gcode/diagnostics.hpp"
#include "gcode/move.hpp"
#include "gcode/parser.hpp"

namespace pcnc {

/// Where the program sits on the machine: machine = scale * q + offset, where q is the program
/// point in mm relative to the G54 frame (a point in work system k is shifted by the config's
/// work_offsets[k] - work_offsets[0]).
struct JobFrame {
  Vec3 offset{};
  double scale = 1.0;
  int work_offset_index = 0;  // initial G54..G59 selection
  Vec3 start{};               // machine position before the first move
  bool contouring = false;    // initial M21/M22 state
};

struct MoveList {
  static constexpr int kCapacity = 4;  // dwell, motion, stop
  Move moves[kCapacity];
  int count = 0;
  void clear() { count = 0; }
  void push(const Move& m) {
    if (count < kCapacity) moves[count++] = m;
  }
};

class Interpreter {
 public:
  Interpreter(const MachineConfig& config, const JobFrame& frame, DiagnosticSink& sink);

  /// Executes one line; appends its moves to `out`. On an error (reported to the sink) the line
  /// produces no moves. Returns false on error.
  bool execute(const ParsedLine& line, MoveList& out);

  /// True once M2/M30 has been executed.
  bool ended() const { return ended_; }
  /// The input ended (end of file or closing '%') at `line`: reports a NURBS group left open.
  void end_of_input(int line);
  /// The End move used when the file ends without M2/M30.
  Move end_move(int line) const;
  /// Current position, machine coordinates.
  Vec3 position() const { return to_machine(q_); }
  /// Machine maximum path feed, mm/s (config max_feed_mm_min, else the fastest axis).
  double max_feed_mm_s() const { return max_feed_mm_s_; }
  /// The home position G28 moves to (machine coordinates): X and Y at their travel minimum,
  /// Z at the top of its travel.
  Vec3 home_position() const;

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
  bool home(const ParsedLine& l, MoveList& out);
  bool feed_for_move(const ParsedLine& l, int column, double& feed_mm_s);
  Vec3 axis_target(const ParsedLine& l, const Vec3& from, std::uint8_t& known, int& first_col) const;
  Vec3 to_machine(const Vec3& q) const { return frame_.scale * q + frame_.offset; }
  Vec3 to_job(const Vec3& m) const { return (1.0 / frame_.scale) * (m - frame_.offset); }
  Move base_move(MoveKind kind, const ParsedLine& l, int column) const;
  bool axis_words(const ParsedLine& l) const { return (l.present & kAxisBits) != 0; }
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

  static constexpr std::uint32_t bit(char c) { return 1u << (c - 'A'); }
  static constexpr std::uint32_t kAxisBits = (1u << ('X' - 'A')) | (1u << ('Y' - 'A')) | (1u << ('Z' - 'A'));

  const MachineConfig& config_;
  JobFrame frame_;
  DiagnosticSink& sink_;
  double max_feed_mm_s_ = 0.0;

  // modal state
  Vec3 q_{};                  // current point, job frame (mm)
  std::uint8_t known_ = 0;    // axes set by the program since the start
  int motion_ = -1;           // G code x10 of the motion mode, -1 = none (G80)
  int normal_axis_ = 2;       // G17
  bool inches_ = false;       // G20
  bool incremental_ = false;  // G91
  int work_index_ = 0;
  double feed_ = 0.0;  // F as written, current units per minute
  bool contouring_ = false;
  bool ended_ = false;

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
