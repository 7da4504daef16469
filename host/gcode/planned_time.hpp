// planned_time.hpp — the time the plan gives one block: what the progress bars' ETA is made
// of (pcnc run's and `pcnc ctl status --watch`'s). A motion block is timed as a move from rest
// to rest at its own path speed and acceleration limits (a trapezoid, or a triangle when it
// is too short to reach its speed); a dwell is its time; a pause or the end take none.
// Junctions that flow under M21 make the real time shorter than the sum, and the feed
// override changes it: the ETA therefore scales the planned time that remains by the ratio
// of the time taken so far to the planned time of the blocks already done (docs/replay.md).
//
// May include: shared/ipc (the block).
#pragma once

#include "ipc/block.hpp"

namespace pcnc {

/// Seconds the plan gives `b` (>= 0; 0 for pause and end).
double planned_time_s(const Block& b);

}  // namespace pcnc
