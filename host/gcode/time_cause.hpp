// time_cause.hpp — why the machine moves as fast as it does, in the planner's own terms: the
// causes a run's time is attributed to (report's `time_by_cause`), and the per-line plan the
// check records from the blocks it makes (what the preprocessor and the rt's junction rules
// decided), so that the report can give each trace row one cause without a front end.
//
// A block's cruise cause: what caps its speed (the programmed feed, the feed clamped to the
// machine's maximum, an axis's velocity limit, the arc's centripetal limit, a NURBS curve's
// feed schedule, a rapid). Its acceleration cause: the axis whose acceleration limit sets the
// path acceleration (an arc or curve: its tangential share). Each junction between two
// blocks: passed straight, passed at a reduced corner speed, or a stop (turn over the
// contouring angle, contouring off, a block that only turns the tool, or a start, end, dwell
// or pause).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "config/config.hpp"
#include "ipc/block.hpp"

namespace pcnc {

enum class TimeCause : std::uint8_t {
  kFeed,             // cruising at the programmed F
  kFeedClamp,        // cruising at the machine's maximum feed (F was clamped to it)
  kRapid,            // cruising on a rapid (G0)
  kAxisVelocityX,    // cruising at the speed axis X allows on this move (then Y, Z)
  kAxisVelocityY,
  kAxisVelocityZ,
  kArcCentripetal,   // cruising at an arc's centripetal limit
  kCurveSchedule,    // a NURBS curve below its feed: the schedule's curvature or chord limit
  kAccelX,           // speeding up or slowing down between speeds, at X's acceleration (Y, Z)
  kAccelY,
  kAccelZ,
  kAccelArcCurve,    // the same on an arc or curve (tangential acceleration share)
  kJunctionStop,     // slowing to, or starting from, a junction stop (turn over the angle, M22, a turn-only block)
  kJunctionCorner,   // slowing for a corner passed without stopping (corner speed)
  kStartEndStop,     // slowing to, or starting from, rest at a program start or end, dwell or pause
  kOverride,         // steady below the block's limit (feed override under 100 %) or above it
  kDwell,            // G4
  kPaused,           // feed hold or M0/M1
  kOther,            // anything else in the program's window (a stop, an underrun, a fault)
  kCount
};
inline constexpr int kTimeCauseCount = static_cast<int>(TimeCause::kCount);

/// Stable JSON key ("feed", "axis_velocity_x", "junction_stop", ...).
const char* time_cause_key(TimeCause c);
/// Words for people ("axis X velocity limit", ...).
const char* time_cause_label(TimeCause c);
/// The key back to the cause; false when unknown.
bool parse_time_cause(const std::string& key, TimeCause& c);

enum class JunctionKind : std::uint8_t {
  kStraight = 0,     // flows without a speed cap worth naming (turn under 0.5°)
  kCorner = 1,       // flows at a corner speed
  kAngleStop = 2,    // stops: the turn is over the contouring angle and the block has no path tolerance
                     // (with one, the rt passes it at the junction-deviation speed: kCorner)
  kContouringOff = 3,// stops: M22
  kStartEnd = 4,     // stops: program start or end, dwell, pause
  kTurnStop = 5,     // stops: one of its blocks only turns the tool (an angular block, rotary.angular:
                     // its path parameter is an angle; the rt starts and ends it at rest)
};

/// One run of source lines whose blocks share their plan (one block's lines, or several
/// merged when nothing stops or turns between them).
struct LinePlan {
  std::uint32_t first = 0, last = 0;  // source lines
  TimeCause cruise = TimeCause::kFeed;
  TimeCause accel = TimeCause::kAccelX;
  double speed = 0.0;                 // mm/s: the block's speed limit (cruise)
  JunctionKind before = JunctionKind::kStartEnd, after = JunctionKind::kStartEnd;
  double angle_before_deg = 0.0, angle_after_deg = 0.0;  // the turns at its two junctions
};

/// The cruise and acceleration causes of one block, recomputed from its own geometry and the
/// config with the preprocessor's rules (gcode/preprocessor.hpp).
TimeCause cruise_cause(const Block& b, const MachineConfig& config);
TimeCause accel_cause(const Block& b, const MachineConfig& config);

/// Fed every block of a program in order (as check makes them), keeps the plan.
class PlanRecorder {
 public:
  explicit PlanRecorder(const MachineConfig& config);
  void add(const Block& b);
  /// Closes the last entry (its end junction is a stop) and returns the plan.
  std::vector<LinePlan> finish();

 private:
  void push(const LinePlan& p);
  const MachineConfig& config_;
  std::vector<LinePlan> plan_;
  bool has_prev_ = false;
  Block prev_{};  // only the fields used: kind, line, dirs, contouring, path tolerance, rotary.angular
  LinePlan pending_{};
  bool pending_set_ = false;
};

}  // namespace pcnc
