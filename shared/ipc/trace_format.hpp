// trace_format.hpp — the per-cycle trace, part of the contract between pcnc-rt (which writes
// it, --trace) and the host's run report (which reads it): one row type, the CSV header and
// the row's text, both ways. DESIGN.md "trace format":
//   t,line,state,cmd_x,cmd_y,cmd_z,act_x,act_y,act_z,ferr_x,ferr_y,ferr_z,speed
// in mm, s and mm/s, machine coordinates, the state by name (to_string(MachineState)).
// A machine with rotary joints appends, per declared joint in the order A, B, C,
// cmd_a,act_a,ferr_a (degrees); the 3-axis header and rows stay exactly as they are.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <type_traits>

#include "geometry/vec3.hpp"
#include "ipc/rotary_joints.hpp"
#include "ipc/status.hpp"

namespace pcnc {

/// One cycle's record: one row of the trace.
struct TraceSample {
  double t = 0.0;            // machine time, s
  std::uint32_t line = 0;    // source line of the block in execution
  MachineState state = MachineState::kIdle;
  Vec3 commanded{};          // setpoint, mm
  Vec3 actual{};             // encoder position, mm
  Vec3 following_error{};    // commanded - actual, mm
  double speed = 0.0;        // commanded path speed, mm/s
};
static_assert(std::is_trivially_copyable_v<TraceSample>);

/// One cycle's rotary joints (rad): the trace file's extra columns. Not in TraceSample, which
/// the scope ring holds in the segment at a fixed size.
struct TraceJoints {
  RotaryMask mask = 0;  // the machine's joints: the columns written
  Rot3 commanded{};
  Rot3 actual{};
};
static_assert(std::is_trivially_copyable_v<TraceJoints>);

/// What the rt's trace writer queues per cycle.
struct TraceEntry {
  TraceSample sample;
  TraceJoints joints;
};
static_assert(std::is_trivially_copyable_v<TraceEntry>);

/// The header with the columns of the joints in `mask` appended (none: kTraceCsvHeader).
std::string trace_csv_header(RotaryMask mask);
/// The row with the joints' columns appended (degrees), as format_trace_row.
int format_trace_row(char* buf, std::size_t n, const TraceSample& s, const TraceJoints& j);

/// The CSV header line (no newline).
inline constexpr const char* kTraceCsvHeader =
    "t,line,state,cmd_x,cmd_y,cmd_z,act_x,act_y,act_z,ferr_x,ferr_y,ferr_z,speed";
inline const char* trace_csv_header() { return kTraceCsvHeader; }

/// Writes one row (no newline) into `buf` without allocating, snprintf-style: returns the
/// length the row needs (>= n means it was cut short), negative on an encoding error.
int format_trace_row(char* buf, std::size_t n, const TraceSample& s);
/// One row (no newline) as a string. For tests and tools.
std::string trace_csv_row(const TraceSample& s);

/// Parses one CSV data row (a trailing '\r' is allowed). False (and `row` unspecified) when
/// it is malformed. Rotary joints' columns after `speed` (groups of cmd, act, ferr in degrees)
/// are accepted; with `joints` they are read into it (rad) for the joints of joints->mask, in order.
bool parse_trace_row(std::string_view text, TraceSample& row, TraceJoints* joints = nullptr);
/// The state's trace name back to the enum ("RUNNING" -> kRunning). False when unknown.
bool parse_state_name(std::string_view name, MachineState& state);

}  // namespace pcnc
