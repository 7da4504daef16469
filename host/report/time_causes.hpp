// time_causes.hpp — where a run's machine time went: each trace row of the program's window
// gets one cause (gcode/time_cause.hpp) from the plan the check recorded (what capped the
// block's speed, how its junctions pass) and what the row shows (cruising at the block's limit,
// speeding up, slowing down, steady below it, paused); the causes' times add up to the
// program time. Also the "slowest stretches": the source lines that lost most time against
// cruising at their programmed speed, with the cause.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "gcode/time_cause.hpp"
#include "ipc/trace_format.hpp"
#include "report/trace_reader.hpp"

namespace pcnc {

/// Gives a trace row its cause from the plan (the summary's, as check recorded it).
class CauseClassifier {
 public:
  explicit CauseClassifier(std::vector<LinePlan> plan);
  /// `prev_speed`: the previous row's commanded path speed (mm/s).
  RowCause classify(const TraceSample& row, double prev_speed) const;
  /// The plan entries that hold `line` (empty when none), in program order.
  std::vector<const LinePlan*> entries(std::uint32_t line) const;

 private:
  std::vector<LinePlan> plan_;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> index_;  // (line, entry), sorted
};

/// Seconds per cause key from rows per cause, scaled so that they add up to `program_time_s`
/// (the rt's own count of the program's cycles); causes with no row are left out.
std::map<std::string, double> time_by_cause(const std::array<std::uint64_t, kTimeCauseCount>& rows, double program_time_s);

/// One line of the "slowest stretches" table.
struct SlowStretch {
  std::uint32_t line = 0;
  double time_s = 0.0;       // on this line
  double lost_s = 0.0;       // not cruising at the programmed feed or rapid speed
  TimeCause cause = TimeCause::kOther;  // the cause of most of the lost time
  double cause_s = 0.0;
  double angle_deg = -1.0;   // the junction's turn, for a junction stop or corner (-1: none)
};

/// The `n` lines that lost the most time, most first. `seconds_per_row`: program time / rows.
std::vector<SlowStretch> slowest_stretches(const TraceDigest& d, const CauseClassifier& plan, double seconds_per_row,
                                           std::size_t n);

/// A colour per cause, for the plot band and the table.
const char* time_cause_colour(TimeCause c);

}  // namespace pcnc
