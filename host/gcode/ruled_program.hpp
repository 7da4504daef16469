// ruled_program.hpp — the ruled-surface G-code form (docs/ruled-surface.md, "The G-code form"):
// pieces of directrix points (the tool tip X Y Z, workpiece coordinates, mm) and unit tool
// vectors (I J K, tip to spindle, workpiece frame) written as G5.4 ... G5.5 groups, the 5-axis
// analogue of G5.2 ... G5.3, inside a tool-centre-point program (M428 ... M429); and the same
// pieces as a JSON file, and that file read back. Pure functions. `pcnc ruled` writes with them;
// the front end runs the file form as the G-code form these lines give (gcode/ruled_json_input.hpp).
#pragma once

#include <string>
#include <vector>

#include "gcode/diagnostics.hpp"
#include "geometry/vec3.hpp"

namespace pcnc {

/// One ruled-surface piece: at least two set points, one unit tool vector each.
struct RuledPiece {
  std::vector<Vec3> points;  // tool tip, mm
  std::vector<Vec3> axes;    // unit tool axis
  std::string comment;       // written on the G5.4 line as (comment); may be empty
};

struct RuledProgramOptions {
  double feed_mm_min = 600.0;         // F on every G5.4 line
  double clearance_z = 1.0;           // the first rapid goes to this Z, the last back to it
  std::vector<std::string> header;    // comment lines at the top (without parentheses)
  // On a 5-axis machine: the rotary joints' words at the first set point's axis (e.g.
  // "A4.5 C-90"), written as a G0 with TCP off before M428, so no TCP move leaves the pole of C;
  // and the words that turn them back after M429 (e.g. "A0 C0"). Empty: neither line.
  std::string turn_joints;
  std::string turn_back;
  // After the rapid over the first set point: a G0 Z down (or up) to its Z when that differs
  // from clearance_z as written (the JSON input's preamble, whose clearance is the higher of
  // the first and last set point).
  bool rapid_to_first_z = false;
};

/// The program, one string per line (no newlines): the header comments, G21 G90 G17 G94,
/// [G0 <turn_joints>], M428, G0 Z<clearance>, G0 X Y to the first piece's first point, [G0 Z to
/// it: rapid_to_first_z], every
/// piece as G5.4 F<feed> / X Y Z I J K lines / G5.5, G0 Z<clearance>, M429, [G0 <turn_back>],
/// M2. The first piece must start at (x, y, clearance) with the tool axis where the rapids
/// leave it: vertical (I0 J0 K1) without turn_joints, the axis those joints give with them.
std::vector<std::string> ruled_program_lines(const std::vector<RuledPiece>& pieces, const RuledProgramOptions& options);

/// One set point as written: X Y Z with 5 decimals, I J K with 7.
std::string ruled_point_line(const Vec3& point, const Vec3& axis);

/// The file form: {"format": "pcnc-ruled-program", "version": 1, "units": "mm", "feed_mm_min": F,
/// "pieces": [{"points": [[x, y, z], ...], "axes": [[i, j, k], ...]}, ...]} (17 significant digits).
std::string ruled_program_json(const std::vector<RuledPiece>& pieces, double feed_mm_min);

/// A place inside the file form: its key path ("pieces[2].points[5]", indices from 0; "the file"
/// for the top) and where that value starts in the text (line and column from 1).
struct JsonPlace {
  std::string path;
  int line = 0;
  int column = 0;
};

/// The file form read back: its pieces (axes normalised) and feed, where each piece, its set
/// points and its first tool vector stand in the text, or the refusal (`error` empty when read).
struct RuledJsonProgram {
  double feed_mm_min = 0.0;
  std::vector<RuledPiece> pieces;
  struct PiecePlaces {
    JsonPlace piece;               // the piece's object
    std::vector<JsonPlace> points;  // each set point's [x, y, z]
    JsonPlace first_axis;           // its first tool vector
  };
  std::vector<PiecePlaces> places;  // one per piece
  std::string error;                // "origin:line:col: error: path: why" (format_diagnostic)
  Diagnostic refusal;               // the same, in parts (file, line, column, "path: why")
  std::size_t text_lines = 0;       // lines in the text
};

/// Reads the file form, held to the G-code form's rules that need no machine state (2-5 of
/// docs/ruled-surface.md): the format, version 1 and units "mm"; feed_mm_min > 0; at least one
/// piece, each with "points" and "axes" of equal length >= 2, every entry three finite numbers,
/// every axis within 0.001 of unit length (normalised), consecutive points at least 1e-6 mm
/// apart; each piece starting where the one before ended (point and axis, 1e-9); unknown keys
/// refused, as the surface file does. A refusal names `origin`, the line and column of the
/// value at fault (of the parse error when the text is not JSON) and its key path.
RuledJsonProgram read_ruled_program_json(const std::string& text, const std::string& origin);

}  // namespace pcnc
