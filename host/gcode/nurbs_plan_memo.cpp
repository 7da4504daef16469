// nurbs_plan_memo.cpp — plans kept between passes (see nurbs_plan_memo.hpp).
#include "gcode/nurbs_plan_memo.hpp"

#include <cstdint>
#include <utility>

#include "gcode/hand_over_memo.hpp"

namespace pcnc {
namespace {

struct Key {
  NurbsCurve curve;
  NurbsLimits limits;
};

bool same_limits(const NurbsLimits& a, const NurbsLimits& b) {
  return a.feed_mm_s == b.feed_mm_s && a.period_s == b.period_s && a.chord_tolerance_mm == b.chord_tolerance_mm &&
         a.axis_velocity_mm_s == b.axis_velocity_mm_s && a.axis_accel_mm_s2 == b.axis_accel_mm_s2 &&
         a.normal_accel_share == b.normal_accel_share && a.samples_per_span == b.samples_per_span;
}

bool same(const Key& k, const NurbsCurve& c, const NurbsLimits& l) {
  return k.curve.degree == c.degree && k.curve.points == c.points && k.curve.weights == c.weights &&
         k.curve.knots == c.knots && same_limits(k.limits, l);
}

std::uint64_t hash_of(const NurbsCurve& c, const NurbsLimits& l) {
  std::uint64_t h = kFnv1aSeed;
  fnv1a_mix(h, &c.degree, sizeof c.degree);
  fnv1a_mix(h, c.points.data(), c.points.size() * sizeof(Vec3));
  fnv1a_mix(h, c.weights.data(), c.weights.size() * sizeof(double));
  fnv1a_mix(h, c.knots.data(), c.knots.size() * sizeof(double));
  fnv1a_mix(h, &l.feed_mm_s, sizeof l.feed_mm_s);
  return h;
}

struct Entry {
  Key key;
  NurbsBlocks plan;  // without the dense schedule
};

HandOverMemo<Entry>& memo() {
  static HandOverMemo<Entry> m(kNurbsPlanMemoBytes);
  return m;
}

}  // namespace

NurbsBlocks plan_nurbs_blocks_memo(const NurbsCurve& curve, const NurbsLimits& limits) {
  const std::uint64_t h = hash_of(curve, limits);
  if (auto e = memo().take(h, [&](const Entry& x) { return same(x.key, curve, limits); })) return std::move(e->plan);
  NurbsBlocks plan = plan_nurbs_blocks(curve, limits);
  if (!plan.error.empty()) return plan;  // refused curves are not kept (the pass ends there)
  Entry e;
  e.key = Key{curve, limits};
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
