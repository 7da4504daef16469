// nurbs_plan_prefetch.hpp — the check pass's curve plans made on a second thread.
//
// Planning a curve's feed schedule (plan_nurbs_blocks) is most of the front end's time on a
// smoothed surfacing program (LHchips4.ngc: 59 % of `pcnc check`), and the check must finish
// before anything moves. A plan is a pure function of its curve and limits, so it can be made
// ahead: the smoothing stage, in the check pass, hands each curve it makes to prefetch_plan()
// as soon as it has fitted it, and keeps one run of look-ahead (gcode/smoothing.hpp), so that a
// worker thread plans run k while the pipeline's thread reads and fits run k + 1. When the
// pipeline then asks for the plan (plan_nurbs_blocks_memo), take_prefetched() gives it the
// worker's plan, waits for one the worker is making, or hands back one the worker has not
// started (the caller plans it itself: both threads plan, neither waits for a queue).
//
// The plans are the ones planning would make (the same function on the same inputs), so the
// blocks are the same bit for bit; only the thread that made them differs. Bounded: at most
// kPrefetchEntries plans wait at once (beyond that prefetch_plan() does nothing), and an entry
// never asked for is dropped, oldest first, when a new one needs its place. Thread-safe; one
// worker per process, started on first use.
#pragma once

#include <cstddef>
#include <optional>

#include "gcode/nurbs_schedule.hpp"

namespace pcnc {

constexpr std::size_t kPrefetchEntries = 64;

/// Plans `curve` under `limits` on the worker thread, for a later take_prefetched().
void prefetch_plan(const NurbsCurve& curve, const NurbsLimits& limits);

/// The worker's plan of exactly this curve and these limits (waiting while it makes it), or
/// nothing: not prefetched, or prefetched but not started yet (then no longer queued: the
/// caller plans it).
std::optional<NurbsBlocks> take_prefetched(const NurbsCurve& curve, const NurbsLimits& limits);

/// For tests: plans the worker made and plans taken from it since the process started.
struct PrefetchStats {
  std::size_t planned = 0, taken = 0, reclaimed = 0;  // reclaimed: queued, then planned by the caller
};
PrefetchStats prefetch_stats();

}  // namespace pcnc
