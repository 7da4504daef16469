// trace_format.hpp — the per-cycle trace, part of the contract between pcnc-rt (which writes
// it, --trace) and the host's run report (which reads it): one row type, the CSV header and
// the row's text, both ways. DESIGN.md "trace format":
//   t,line,state,cmd_x,cmd_y,cmd_z,act_x,act_y,act_z,ferr_x,ferr_y,ferr_z,speed
// in mm, s and mm/s, machine coordinates, the state by name (to_string(MachineState)).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <type_traits>

#include "geometry/vec3.hpp"
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
/// it is malformed.
bool parse_trace_row(std::string_view text, TraceSample& row);
/// The state's trace name back to the enum ("RUNNING" -> kRunning). False when unknown.
bool parse_state_name(std::string_view name, MachineState& state);

}  // namespace pcnc
