// nurbs_plan_memo.hpp — plan_nurbs_blocks remembered across the front end's passes in one
// process. `pcnc run` (pcnc-host) checks the whole program and then streams it through the same
// pipeline again, so every curve's feed schedule (with smoothing, most of the front end's time:
// LHchips4.ngc's 475 smoothed curves) was planned twice. A plan made in one pass is kept here
// and handed out to the next pass that asks for the same curve with the same limits, compared
// exactly (every control point, weight, knot and limit, not a hash alone), so a hit returns what
// planning would return: planning is a pure function of those inputs.
//
// An entry is handed out once and then dropped (the check's plans feed the stream's pass).
// Bounded: at most kNurbsPlanMemoBytes of blocks; an insertion that would pass it drops every
// entry first (a program larger than that plans its later curves twice, as before). Thread-safe:
// the service plans from more than one thread.
#pragma once

#include <cstddef>
#include <optional>

#include "gcode/hand_over_memo.hpp"
#include "gcode/nurbs_schedule.hpp"

namespace pcnc {

constexpr std::size_t kNurbsPlanMemoBytes = 24u << 20;

/// The plan of `curve` under `limits`: from the memo when a pass planned the same before (the
/// entry is then removed), else planned now and kept for the next pass. The dense schedule
/// (NurbsBlocks::schedule) is not kept: a plan from the memo has an empty one.
NurbsBlocks plan_nurbs_blocks_memo(const NurbsCurve& curve, const NurbsLimits& limits);

/// What the memo holds now (entries, bytes of blocks) and has done (hits, misses): for tests.
using NurbsPlanMemoStats = MemoStats;
NurbsPlanMemoStats nurbs_plan_memo_stats();
void nurbs_plan_memo_clear();

}  // namespace pcnc
