// nurbs_plan_memo.cpp — plans kept between passes (see nurbs_plan_memo.hpp).
#include "gcode/nurbs_plan_memo.hpp"

#include <cstdint>
#include <optional>
#include <utility>

#include "gcode/hand_over_memo.hpp"
#include "gcode/nurbs_plan_key.hpp"
#include "gcode/nurbs_plan_prefetch.hpp"

namespace pcnc {
namespace {

struct Entry {
  NurbsPlanKey key;
  NurbsBlocks plan;  // without the dense schedule
};

HandOverMemo<Entry>& memo() {
  static HandOverMemo<Entry> m(kNurbsPlanMemoBytes);
  return m;
}

}  // namespace

NurbsBlocks plan_nurbs_blocks_memo(const NurbsCurve& curve, const NurbsLimits& limits) {
  const std::uint64_t h = plan_input_hash(curve, limits);
  if (auto e = memo().take(h, [&](const Entry& x) { return same_plan_input(x.key, curve, limits); })) {
    return std::move(e->plan);
  }
  std::optional<NurbsBlocks> made = take_prefetched(curve, limits);  // the check pass's worker
  NurbsBlocks plan = made ? std::move(*made) : plan_nurbs_blocks(curve, limits);
  if (!plan.error.empty()) return plan;  // refused curves are not kept (the pass ends there)
  Entry e;
  e.key = NurbsPlanKey{curve, limits};
  e.plan.blocks = plan.blocks;
  e.plan.corner_after = plan.corner_after;
  const std::size_t bytes = plan.blocks.size() * sizeof(Block) +
                            (curve.points.size() * sizeof(Vec3) + (curve.weights.size() + curve.knots.size()) * sizeof(double));
  memo().put(h, std::move(e), bytes);
  return plan;
}

NurbsPlanMemoStats nurbs_plan_memo_stats() { return memo().stats(); }

void nurbs_plan_memo_clear() { memo().clear(); }

}  // namespace pcnc
