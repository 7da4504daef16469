// nurbs_reader.hpp — a minimal reader of the NURBS groups in a G-code file, for the offline
// `pcnc nurbs` tool only (pcnc run/check use the full front end in host/).
//
// It follows just enough modal state to place the curves: G17/G18/G19, G20/G21, G90/G91, F,
// and the current point from the X/Y/Z words of any line. A group is LinuxCNC's
// `G5.2 [X Y] P<weight> L<order>`, control-point lines `X Y P<weight>` (the two axes of the
// plane: XY for G17, ZX for G18, YZ for G19), closed by `G5.3`. The first control point is
// the current point, with the G5.2 line's P as its weight when that line has no coordinates.
// Knots: LinuxCNC's open uniform vector (or the seed's chord length when asked).
#pragma once

#include <map>
#include <string>
#include <vector>

#include "geometry/nurbs.hpp"

namespace pcnc {

struct ProgramCurve {
  int line = 0;            // line of the G5.2 word
  double feed_mm_s = 0.0;  // F in effect (mm/s)
  NurbsCurve curve;
};

struct NurbsProgram {
  std::vector<ProgramCurve> curves;
  std::string error;  // "line N: ..." when the file could not be read; curves read so far stay
};

/// The words of one line as this reader sees them: G numbers in order, every other letter's
/// value (upper case), comments in () and after ; removed; plain decimal numbers only.
struct GcodeWords {
  std::vector<double> g;
  std::map<char, double> value;
  bool has(char c) const { return value.count(c) != 0; }
};
/// False with `err` set on a letter without a number or a stray character.
bool split_gcode_words(const std::string& raw, GcodeWords& w, std::string& err);

NurbsProgram read_nurbs_program(const std::string& path, KnotRule rule = KnotRule::kOpenUniform);
NurbsProgram parse_nurbs_program(const std::string& text, KnotRule rule = KnotRule::kOpenUniform);

}  // namespace pcnc
