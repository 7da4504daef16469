// ruled_reader.hpp — the reader of the ruled-surface G-code form (docs/ruled-surface.md, "The
// G-code form"): the lines from G5.4 to G5.5 turned into one ruled piece (set points X Y Z, the
// tool tip, and unit tool vectors I J K), the data `pcnc ruled` wrote them from. A pure parser
// stage between the lexer (lexer.hpp: words with their columns) and the interpreter: it
// checks the group's own rules and reports through the DiagnosticSink (file:line:col);
// the modal state it needs (tool-centre-point control, G90/G91, G93/G94, F) is handed in by
// the caller. Placing the points (units, work offsets), the first point against the current
// pose and building the block are the interpreter's (not wired yet: docs/ruled-surface.md).
#pragma once

#include <string_view>
#include <vector>

#include "gcode/diagnostics.hpp"
#include "gcode/lexer.hpp"
#include "geometry/vec3.hpp"

namespace pcnc {

/// One G5.4 ... G5.5 group as read.
struct RuledGroup {
  int line = 0;                  // line of the G5.4
  double feed = 0.0;             // F in effect for the group (program units per minute)
  std::vector<Vec3> points;      // X Y Z as written (program units, before offsets)
  std::vector<Vec3> axes;        // I J K, normalised (dimensionless)
  std::vector<int> point_lines;  // the line of each set point
};

/// The modal state the group's rules depend on (the interpreter's, at the G5.4 line).
struct RuledModal {
  bool tcp = false;           // M428 or G43.4 in effect: the points are tool tips
  bool incremental = false;   // G91
  bool inverse_time = false;  // G93 (G95 too: anything but G94)
  double feed = 0.0;          // F in effect before the G5.4 line
  bool spline_group = false;  // inside a G5.2 (or G6.2) group
};

/// An I J K whose length is off 1 by more than this is refused (the reader normalises the rest).
constexpr double kRuledAxisTolerance = 0.001;
/// Consecutive set points closer than this (mm) are refused (the model needs distinct points).
constexpr double kRuledMinPointDistance = 1e-6;

/// Line by line: each lexed line is offered to take(); it returns true when the line belongs to
/// a group (opened, continued or closed one), which the caller then leaves alone. A closed group
/// without errors is handed out by take_group().
class RuledGroupReader {
 public:
  bool take(const LexedLine& line, int line_no, const RuledModal& modal, DiagnosticSink& sink);
  /// A group is open (between G5.4 and G5.5).
  bool open() const { return open_; }
  /// The last group closed without errors, once (false when there is none).
  bool take_group(RuledGroup& out);
  /// At the end of the program: a group still open is an error at its G5.4 line.
  void finish(DiagnosticSink& sink);

 private:
  void open_group(const LexedLine& line, int line_no, const RuledModal& modal, DiagnosticSink& sink);
  void set_point(const LexedLine& line, int line_no, DiagnosticSink& sink);
  void close_group(const LexedLine& line, int line_no, DiagnosticSink& sink);

  RuledGroup group_;
  bool open_ = false;
  bool failed_ = false;  // the open group had an error: dropped at its G5.5
  bool ready_ = false;   // group_ holds a closed group not yet taken
};

/// The whole text: every G5.4 ... G5.5 group, in order, following just the modal state the
/// rules need from the other lines (M428/M429, G43.4/G49, G90/G91, G93/G94/G95, F, G5.2 ... G5.3
/// groups; Fanuc's G6.2 is left to the interpreter). Errors go
/// to `sink`; groups with errors are left out.
std::vector<RuledGroup> read_ruled_groups(std::string_view text, DiagnosticSink& sink);

}  // namespace pcnc
