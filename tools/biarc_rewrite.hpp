// biarc_rewrite.hpp — the text transformation behind `pcnc biarc`: NURBS groups (G5.2 ...
// G5.3), G5/G5.1 splines (cubic and quadratic Béziers in G17, LinuxCNC's meaning, a G5
// without I J continuing the one before) and smooth runs of short G1 moves rewritten as G2/G3 biarcs within a tolerance
// (geometry/biarc.hpp), optionally with the loops a tool of a given radius would tangle on
// removed; every other line passes through byte for byte.
//
// A smooth run: at least `min_moves` consecutive plain G1 moves in the plane (G1, the two
// plane axes, F, N; the normal axis unchanged), each shorter than `max_segment_mm`, turning
// by less than `max_turn_deg` at each junction, at one feed. When a later line moves by the
// modal motion mode (axis words without G1), the run's last move is written as an explicit G1
// line so that G1 stays in force. A run whose biarcs would not be fewer blocks than its moves is left
// as it is (a note says so). A NURBS group is rewritten when the next move names its motion
// mode. Under G93 (inverse time) nothing is rewritten; from the first line with control flow,
// parameters or expressions on, nothing either (the position is no longer followed).
//
// Output: one move per line, "G2 X.. Y.. I.. J.." (G18: X Z I K, G19: Y Z J K), numbers in
// the program's units with at most 6 decimals (trailing zeros trimmed), F on the first line
// when the rewritten lines set it, the program's G90/G91 and G90.1/G91.1 respected. An arc
// flatter than 1e-6 mm, or too short to keep its ends apart after rounding, is written as G1.
#pragma once

#include <string>
#include <vector>

namespace pcnc {

struct BiarcRewriteOptions {
  double tolerance_mm = 0.001;
  double max_tool_radius_mm = 0.0;  // > 0: remove the loops of this tool radius
  int side = 0;                     // +1 left (G41), -1 right (G42), 0: the program's G41/G42, else both
  int min_moves = 8;
  double max_segment_mm = 0.5;
  double max_turn_deg = 10.0;
};

/// One rewritten NURBS group or G1 run.
struct BiarcRewriteItem {
  int first_line = 0, last_line = 0;  // the input lines replaced
  bool nurbs = false;  // a NURBS group or a G5/G5.1 spline
  int spline_degree = 0;  // a G5 (3) or G5.1 (2) spline; 0 otherwise
  int moves_in = 0;    // G1 moves (1 for a NURBS group or a spline)
  int moves_out = 0;   // G2/G3/G1 lines written
  double deviation_mm = 0.0;          // NURBS: curve <-> arcs (Newton); G1: points -> arcs
  double segment_deviation_mm = 0.0;  // G1: arcs -> programmed segments
  double sagitta_mm = 0.0;            // G1: the segments' own sagitta (allowance)
  bool within_tolerance = true;
  int loops_removed = 0;
  int unresolved = 0;           // pieces the tool still cannot follow (see LoopRemoval)
  double loop_change_mm = 0.0;  // how far the loop removal moved the contour
};

struct BiarcRewriteReport {
  std::vector<BiarcRewriteItem> items;
  int lines_in = 0, lines_out = 0;
  std::vector<std::string> notes;  // "line N: ..." why something was left as it was
};

/// The rewritten program. Pure: text in, text out.
std::string rewrite_biarcs(const std::string& text, const BiarcRewriteOptions& options, BiarcRewriteReport& report);

}  // namespace pcnc
