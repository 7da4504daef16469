// biarc_program.hpp — the light modal reading `pcnc biarc` needs: each line of a G-code file
// with the state before it (units, G90/G91, G90.1/G91.1, plane, motion mode, feed, feed
// mode, cutter compensation side, the position and which axes of it are known) and what kind
// of line it is for the rewrite: a plain G1 move (a candidate for a smooth run), a line of a
// G5.2 ... G5.3 NURBS group, a G5/G5.1 spline, or anything else (passed through, its modal
// effects followed).
//
// A file tool, not the machine: nothing is refused for travel, spindle or feed reasons. Words
// come from the project's lexer and parser (host/gcode); control flow, parameters and
// expressions are not followed: from the first such line on, nothing is rewritten (`opaque`).
#pragma once

#include <array>
#include <string>
#include <vector>

#include "geometry/vec3.hpp"

namespace pcnc {

struct BiarcModal {
  double scale = 1.0;         // mm per program unit (G21 1, G20 25.4)
  bool incremental = false;   // G91
  bool arc_absolute = false;  // G90.1: I J K are absolute
  int normal = 2;             // plane normal axis: 2 G17, 1 G18, 0 G19
  int motion = -1;            // motion code x10 (0 G0, 10 G1, 20 G2, 30 G3, 50 G5, 51 G5.1, 52 G5.2), -1 none
  double feed = 0.0;          // F as written (program units per minute)
  bool inverse_time = false;  // G93
  int comp = 0;               // +1 G41, -1 G42, 0 G40
  Vec3 pos{};                 // mm; an unknown axis holds a value relative to an arbitrary origin
  std::array<bool, 3> known{};
};

enum class BiarcLineKind {
  kOther,       // passed through; its modal effects followed
  kG1,          // a plain G1 move in the plane: only G1, plane axes, F, N (and an unchanged normal axis)
  kNurbsStart,  // G5.2 [plane axes] [P] [L]
  kNurbsPoint,  // plane axes and P inside a group
  kNurbsEnd,    // G5.3
  kSpline,      // G5 or G5.1 in G17 (also by the modal motion mode): only the plane axes, I J P Q, F, N
  kOpaque,      // control flow, parameters or a line the lexer refused: rewriting stops here
};

struct BiarcLine {
  std::string text;      // as read, without its '\n' ('\r' kept)
  int number = 0;        // 1-based
  BiarcLineKind kind = BiarcLineKind::kOther;
  BiarcModal before;     // state before the line
  BiarcModal after;      // state after the line
  bool has_feed = false;
  bool explicit_motion = false;  // a G word of the motion group on the line
  bool uses_modal_motion = false;  // axis words moved by the modal motion mode (no motion G word)
  double weight = 1.0;   // NURBS: P
  int order = 3;         // G5.2: L
  bool has_plane_axes = false;  // NURBS: both plane axes given
  // G5/G5.1 (kSpline): the degree (3: G5, 2: G5.1) and the inner control points, mm in the
  // program's frame: the first as an offset from the start (G5 without I and J: the previous
  // G5's P Q reversed), the second (G5) as an offset from the end.
  int spline_degree = 0;
  Vec3 spline_c1{}, spline_c2{};
  // A G5 line without I and J (kSpline or not): it continues the G5 before it, so that one
  // stays a G5 when this one is not rewritten.
  bool spline_continuation = false;
};

/// Reads every line of `text`. Never fails: a line it cannot follow is kOther or kOpaque.
std::vector<BiarcLine> read_biarc_program(const std::string& text);

}  // namespace pcnc
