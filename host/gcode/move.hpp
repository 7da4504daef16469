// move.hpp — the value the pipeline's move stages hand on (interpreter -> ... -> preprocessor):
// one move in machine coordinates (mm).
//
// The interpreter has already applied units (G20/G21), distance mode (G90/G91), the work offset
// (G54-G59 or --offset) and the --fit scale, and resolved arcs (I/J/K or R form) to a center,
// radius and signed sweep. The preprocessor turns a Move into a ring Block; a NURBS move
// (G5.2/G6.2) carries its whole curve and becomes one or more blocks (host/nurbs_move.hpp).
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "geometry/plane.hpp"
#include "geometry/vec3.hpp"
#include "ipc/rotary_joints.hpp"

namespace pcnc {

enum class MoveKind : std::uint8_t { kRapid, kLine, kArc, kDwell, kPause, kEnd, kNurbs, kRuled };

struct NurbsCurve;
struct RuledModel;

/// Cutter radius compensation in effect for a move (G41/G42/G41.1/G42.1 until G40), as the
/// interpreter hands it to the compensation stage (cutter_comp.hpp).
struct MoveComp {
  std::uint8_t side = 0;         // 0 off (G40), 1 left (G41), 2 right (G42); a negative D swapped it
  std::uint8_t normal_axis = 2;  // the plane compensation works in (G17 2, G18 1, G19 0)
  bool inch = false;             // G20 when it went on (LinuxCNC's arc tolerance is in program units)
  std::uint32_t serial = 0;      // counts the G41/G42 that turned it on: a new one is a new entry
  double radius_mm = 0.0;        // the real tool radius, never scaled by --fit
};

/// Where a smoothed curve passes from one programmed move to the next: from parameter u on,
/// the curve stands for source line `line`.
struct LineMark {
  double u = 0.0;
  int line = 0;
};

struct Move {
  MoveKind kind = MoveKind::kLine;
  int line = 0;                // source line (1-based)
  int column = 0;              // column of the word that caused it (motion G word or first axis word)
  Vec3 start{};                // mm, machine coordinates
  Vec3 end{};                  // mm, machine coordinates
  double feed_mm_s = 0.0;      // programmed feed (already clamped to the machine maximum); 0 for rapids
  double inverse_time_s = 0.0; // G93: the time the programmed move takes (s; feed_mm_s = length / it); 0 in G94
  bool contouring = false;     // M21 state (G64 on, G61 off) for this move
  bool optional_stop = false;  // kPause from M01
  bool machine_frame = false;  // G53 or G28: given in machine coordinates, not moved by --fit
  std::uint8_t known = 7;      // axes whose end coordinate the program has set so far (bit per axis)
  double dwell_s = 0.0;        // kDwell
  double path_tolerance_mm = 0.0;  // G64 P / --tolerance / motion.path_tolerance_mm when it was made (mm)
  bool smoothed = false;       // kNurbs made by the smoothing stage from a run of G1 moves
  bool packed_arcs = false;    // kNurbs made by the arc-packing stage from a chain of arcs (exact)
  std::uint8_t probe_rule = 0; // kLine: a probing move G38.2-G38.5 (ipc/block.hpp ProbeRule); 0: none

  // kArc: center on the start point's level along the normal axis, radius (start radius),
  // signed sweep (> 0 counter-clockwise seen from +normal), normal axis 2 = Z (G17),
  // 1 = Y (G18), 0 = X (G19). The helix is end[normal] - start[normal].
  Vec3 center{};
  double radius = 0.0;
  double sweep = 0.0;
  int normal_axis = 2;

  // kNurbs: the validated curve in machine coordinates (first control point = start, last =
  // end), shared so that copying a Move stays cheap; feed_mm_s is its programmed feed.
  std::shared_ptr<const NurbsCurve> nurbs;

  // Rotary joints (machines with [axis.a/b/c]; docs/kinematics.md "The pipeline"): their values
  // at the start and end of a straight move (rad, machine angles, A B C by index). Under TCP
  // (M428/G43.4) start and end above are the tool tip in workpiece coordinates, and
  // tool_length (mm) is applied along the tool axis by the kinematics. A move that only turns
  // the tool ("angular", rotary_move.hpp) has feed_mm_s in rad/s.
  Rot3 rot_start{};
  Rot3 rot_end{};
  bool tcp = false;
  double tool_length = 0.0;

  // kRuled (G5.4 ... G5.5, host/gcode/ruled_move.hpp): the piece in workpiece coordinates (the
  // tool tip after offsets and --fit; unit tool vectors), always under TCP: start/end are its
  // first and last tips, rot_start the joints at the G5.4, rot_end where the inverse kinematics
  // walked them to, feed_mm_s the tip's speed along the directrix.
  std::shared_ptr<const RuledModel> ruled;

  MoveComp comp;
  // kNurbs made by smoothing (`smoothed`) or packing (`packed_arcs`): the programmed moves'
  // lines along the curve.
  std::shared_ptr<const std::vector<LineMark>> line_marks;
};

/// A straight move without displacement: checked (it may move under another transform) but
/// never sent to the machine.
bool is_null_move(const Move& m);


}  // namespace pcnc
