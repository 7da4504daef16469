// canned_cycle.hpp — the drilling canned cycles (G73, G81, G82, G83, G85, G89) expanded into
// primitive steps (rapid, feed, dwell), with the semantics of LinuxCNC's rs274ngc interpreter
// (interp_cycles.cc: convert_cycle, convert_cycle_xy/yz/zx, CYCLE_MACRO, convert_cycle_g8x).
//
// A pure function: the caller (the interpreter) hands in one cycle line's words already in mm,
// the modal state that matters (plane, G90/G91, G98/G99, whether the previous motion mode was
// this same cycle) and the current point; it gets back the steps in program coordinates. The
// few values LinuxCNC keeps between cycle lines live in CannedCycleModal, which the caller owns.
// docs/gcode.md ("Canned cycles") describes the semantics.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "geometry/vec3.hpp"

namespace pcnc {

/// The small rapid clearance of G73 (after each peck, up) and G83 (down to just above the last
/// peck's depth): LinuxCNC 2.9's G83_RAPID_DELTA, 0.010 inch (0.254 mm in G21 as in G20).
constexpr double kPeckClearanceMm = 0.254;
/// A cycle line that would expand into more steps than this is refused (tiny Q, huge L).
constexpr std::size_t kMaxCycleSteps = 100000;

enum class CycleStepKind : std::uint8_t { kRapid, kFeed, kDwell };

struct CycleStep {
  CycleStepKind kind = CycleStepKind::kRapid;
  Vec3 target{};         // program coordinates (current work system), mm; kDwell: where it dwells
  double dwell_s = 0.0;  // kDwell
};

/// What LinuxCNC keeps between the lines of a series of cycles. The sticky words (R, the
/// drill-axis level, P, Q) are reused only on a later line of the same cycle; the initial level
/// (the G98 return level) lasts while one cycle follows another, G81 to G83 included.
/// The caller calls end_series() whenever a motion that is not a canned cycle executes
/// (G0, G1, G2, G3, G80, ...), as LinuxCNC clears its cycle_il_flag in convert_motion.
struct CannedCycleModal {
  bool have_r = false, have_z = false, have_p = false, have_q = false;
  double r = 0.0;  // R as last written, mm (G91: relative to the initial level)
  double z = 0.0;  // the drill-axis word as last written, mm (G91: relative to R)
  double p = 0.0;  // dwell, s
  double q = 0.0;  // peck depth, mm
  bool have_initial_level = false;
  double initial_level = 0.0;  // drill-axis level when the series started, mm

  void end_series() { *this = CannedCycleModal{}; }
};

struct CycleInput {
  int code10 = 810;          // 730 (G73), 810, 820, 830, 850, 890 (G81/G82/G83/G85/G89)
  int normal_axis = 2;       // the drill axis: 2 = Z (G17), 1 = Y (G18), 0 = X (G19)
  bool retract_r = false;    // true: G99 (retract to R); false: G98 (to the initial level)
  bool incremental = false;  // G91
  bool first_of_series = true;  // the previous motion mode was not this same cycle code
  Vec3 position{};           // current point, program coordinates, mm

  // The words on the line, in mm (G20 already applied) and seconds.
  std::array<bool, 3> has{};  // X Y Z present
  Vec3 axis{};                // X Y Z values
  bool has_r = false, has_p = false, has_q = false, has_l = false;
  double r = 0.0, p = 0.0, q = 0.0;
  long l = 1;  // repeats; the reader has already refused a non-integer L
  // LinuxCNC's polar coordinates for the hole (G17 only, X and Y absent: the interpreter
  // refuses the rest): @ the distance from the origin (mm), ^ the angle from +X (degrees). In
  // G90 they place the hole (the one not written keeps the current point's); in G91 each repeat
  // adds them to the previous hole's, turning about the origin.
  bool has_radius = false, has_angle = false;
  double radius = 0.0, angle_deg = 0.0;

  double peck_clearance = kPeckClearanceMm;  // G73/G83 small rapid, mm
};

struct CycleResult {
  bool ok = true;
  std::string error;      // "what is wrong; expected what" (empty when ok)
  char error_letter = 0;  // the word the error is about ('R', 'L', 'Z', ...); 0: the G word
  Vec3 end{};             // the point after the cycle (program coordinates, mm) when ok
};

/// Expands one canned-cycle line. On success appends the steps to `out` (null moves left out),
/// updates `modal` and returns ok with the end point. On error leaves `out` and `modal` as they
/// were. Steps are bounded by kMaxCycleSteps; nothing is allocated except `out` and, on an
/// error, its message.
CycleResult expand_canned_cycle(const CycleInput& in, CannedCycleModal& modal, std::vector<CycleStep>& out);

/// True for the motion codes (x10) expand_canned_cycle handles: 730, 810, 820, 830, 850, 890.
bool is_drilling_cycle(int code10);

}  // namespace pcnc
