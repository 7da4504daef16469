// block.hpp — the preprocessed move: what pcnc-host puts in a ring slot and pcnc-rt executes.
//
// A block is self-contained (DESIGN.md "What a block holds"): the rt needs nothing but the
// block and the machine config. All positions are machine coordinates in mm (work offset and
// any --fit scale already applied), speeds mm/s, accelerations mm/s², angles rad, times s.
// The struct is trivially copyable and fixed size so it can live in shared memory as is.
#pragma once

#include <cstdint>
#include <type_traits>

#include "geometry/nurbs_order.hpp"
#include "geometry/vec3.hpp"
#include "ipc/rotary_joints.hpp"
#include "ipc/ruled_geometry.hpp"

namespace pcnc {

enum class BlockKind : std::uint8_t {
  kRapid = 0,  // G00: straight line at the machine's rapid speed
  kLine = 1,   // G01: straight line at the programmed feed
  kArc = 2,    // G02/G03: circular arc or helix
  kNurbs = 3,  // G5.2/G06.2: NURBS curve
  kDwell = 4,  // G04: stand still for dwell_s
  kPause = 5,  // M00/M01: stop at rest and wait for resume
  kEnd = 6,    // M02/M30: program end
  kRuled = 7,  // G5.4 ... G5.5: ruled-surface piece under TCP (Block::ruled, layout version 9)
};

// How many axes a straight move uses (seed: myline / myplane / myspace).
enum class MotionClass : std::uint8_t { kNone = 0, kSingleAxis = 1, kPlane = 2, kSpace = 3 };

/// Arc geometry (kArc). The arc lies in the plane normal to `normal_axis` (2 = Z for G17,
/// 1 = Y for G18, 0 = X for G19); angles are measured in that plane from its first axis
/// (X for G17, Z for G18, Y for G19) toward its second (Y, X, Z), so that the right-hand
/// rule about the normal axis gives positive angles, as in RS274 G03.
struct ArcGeometry {
  Vec3 center{};             // on the start point's level along the normal axis
  double radius = 0.0;       // mm
  double start_angle = 0.0;  // rad
  double sweep = 0.0;        // rad, signed: > 0 counter-clockwise (G03), < 0 clockwise (G02)
  double helix = 0.0;        // mm travelled along the normal axis over the whole sweep
  double angular_speed = 0.0;       // rad/s, |sweep| direction, limited by every axis
  double angular_accel = 0.0;       // rad/s²
  double decel_start_angle = 0.0;   // rad from start (unsigned) where a stop at the end must begin
  std::uint8_t normal_axis = 2;
  std::uint8_t pad_[7]{};
};

/// NURBS curve (kNurbs). Curves with more control points than kMaxNurbsPoints are split
/// at knots by the host so that each piece fits one slot.
constexpr int kMaxNurbsPoints = 32;
constexpr int kMaxNurbsKnots = kMaxNurbsPoints + kMaxNurbsDegree + 1;
constexpr int kMaxFeedSchedule = 64;

struct NurbsGeometry {
  Vec3 points[kMaxNurbsPoints]{};
  double weights[kMaxNurbsPoints]{};
  double knots[kMaxNurbsKnots]{};
  // Feed schedule: the speed limit (mm/s) at parameter values u[i], increasing; linear in
  // between. It already holds the forward/backward acceleration passes.
  double schedule_u[kMaxFeedSchedule]{};
  double schedule_speed[kMaxFeedSchedule]{};
  // The tangential (path) acceleration, mm/s², allowed at u[i] at any speed up to speed[i]:
  // what the axes leave there after the normal (centripetal) part, less a margin. Between
  // two points the rt uses the smaller; the block check verifies every point against the
  // axes' limits (layout version 6).
  double schedule_accel[kMaxFeedSchedule]{};
  // Arc length from the block's start to u[i], mm (0 at the first point, the block's length at
  // the last): with schedule_accel, how much speed the rest of the block can shed.
  double schedule_s[kMaxFeedSchedule]{};
  std::uint16_t point_count = 0;
  std::uint16_t knot_count = 0;
  std::uint16_t schedule_count = 0;
  std::uint8_t degree = 0;
  std::uint8_t pad_[1]{};
};

/// The rotary joints of a straight move (kLine, kRapid) on a machine with rotary joints
/// (docs/kinematics.md, "The pipeline"). Angles rad, A B C by index; a joint the machine does
/// not declare stays 0.
///  * TCP off (tcp = 0): the joints run linearly with the path parameter, start to end.
///    start/end of the Block are the linear axes' machine coordinates as for any line.
///  * TCP on (tcp = 1): start/end of the Block are the tool tip in workpiece coordinates (a
///    straight line), the tool axis turns on the great circle from axis_start to axis_end at the
///    same fraction of the path; the rt converts each cycle through the inverse kinematics
///    (tool length `tool_length`) into the joints. joint_end is where the linear axes end (the
///    host's inverse kinematics), end the rotary joints' end values.
///  * angular = 1: the tip (TCP) or the linear axes (TCP off) stand still and only the tool turns:
///    the path parameter is an angle in rad (length, speed, accel in rad, rad/s, rad/s²): the
///    joints' Euclidean travel (TCP off) or the tool axis's turn (TCP on).
struct RotaryMotion {
  Rot3 start{};
  Rot3 end{};
  Vec3 axis_start{};   // TCP: unit tool axis, workpiece coordinates
  Vec3 axis_end{};
  Vec3 joint_end{};    // TCP: linear axes' machine coordinates at the end, mm
  double tool_length = 0.0;  // TCP: mm, from the spindle's gauge point along the tool axis
  std::uint8_t tcp = 0;
  std::uint8_t angular = 0;
  std::uint8_t pad_[6]{};
};

struct Block {
  std::uint64_t seq = 0;        // ring sequence number, 1, 2, 3, ... per program
  std::uint32_t line = 0;       // source line number (1-based) in the G-code file
  BlockKind kind = BlockKind::kLine;
  MotionClass motion_class = MotionClass::kNone;
  std::uint8_t contouring = 0;  // M21 in effect: may pass the end junction without stopping
  std::uint8_t optional_stop = 0;  // kPause from M01 rather than M00

  Vec3 start{};  // mm, machine coordinates
  Vec3 end{};    // mm

  // Path kinematics, for every motion kind: the programmed feed projected so that no axis
  // exceeds its velocity or acceleration limit anywhere on the move.
  double length = 0.0;  // mm of path
  double speed = 0.0;   // mm/s, path speed limit of this block
  double accel = 0.0;   // mm/s², path acceleration limit of this block

  // The seed's driving-axis plan for straight moves (and the helical axis of an arc):
  // the axis with the largest travel, its direction flag, its own speed and acceleration,
  // and the coordinate on it where deceleration must start to stop at `end`. The rt moves by
  // path length; its block check (block_check.hpp) recomputes this plan from length, speed
  // and accel and refuses a block that disagrees. NURBS: only the axis (widest extent of the
  // control polygon) and its flag; speed, accel and decel_start are 0 (the schedule plans).
  std::uint8_t driving_axis = 0;
  std::int8_t driving_dir = 1;  // +1: the driving coordinate increases toward end
  // A probing move (kLine only, docs/probe.md): its stop rule, ProbeRule; 0: an ordinary line.
  std::uint8_t probe_rule = 0;
  std::uint8_t pad0_[1]{};
  // The path tolerance this block was made with (G64 P, --tolerance or motion.path_tolerance_mm;
  // 0: the seed's contouring rule alone). Under M21 the rt passes the junction after this block
  // at least at the junction-deviation speed for it (rt/motion/junction.hpp).
  float path_tolerance_mm = 0.0f;
  double driving_speed = 0.0;   // mm/s
  double driving_accel = 0.0;   // mm/s²
  double decel_start = 0.0;     // mm, coordinate of the driving axis

  // Direction cosines of the path tangent at start and end (unit vectors), for the
  // contouring angle test between consecutive blocks. Zero for dwell/pause/end.
  Vec3 dir_start{};
  Vec3 dir_end{};

  double dwell_s = 0.0;  // kDwell

  ArcGeometry arc{};      // kArc only
  NurbsGeometry nurbs{};  // kNurbs only
  RotaryMotion rotary{};  // machines with rotary joints (layout version 8)
  // kRuled only (layout version 9): the piece the rt's RuledFollower runs. The block is a TCP
  // block: start/end are the tool tip at the directrix's ends (workpiece coordinates), length,
  // speed and accel restate ruled.length, the schedule's largest speed and ruled.accel,
  // dir_start/dir_end the directrix's unit tangents at its ends; rotary holds tcp = 1, the
  // joints at the start and end, the tool axis at the ends (the ruling's unit vectors there),
  // joint_end and the tool length. The driving-axis plan is the NURBS one: only the axis with
  // the widest extent of the set points and its flag, the rest 0.
  RuledGeometry ruled{};
};

/// Block::probe_rule: G38.2-G38.5 (LinuxCNC's semantics, docs/probe.md). Toward: stop when the
/// probe triggers; away: stop when it releases. "Error" rules make no contact an error.
enum ProbeRule : std::uint8_t {
  kProbeNone = 0,
  kProbeTowardError = 1,  // G38.2
  kProbeToward = 2,       // G38.3
  kProbeAwayError = 3,    // G38.4
  kProbeAway = 4,         // G38.5
};
inline bool probe_toward(std::uint8_t rule) { return rule == kProbeTowardError || rule == kProbeToward; }

static_assert(std::is_trivially_copyable_v<Block>, "Block lives in shared memory");
static_assert(std::is_standard_layout_v<Block>, "Block lives in shared memory");

const char* to_string(BlockKind kind);
const char* to_string(MotionClass motion_class);

}  // namespace pcnc
