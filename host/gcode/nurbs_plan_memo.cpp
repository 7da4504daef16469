// nurbs_plan_memo.cpp — plans kept between passes (see nurbs_plan_memo.hpp).
#include "gcode/nurbs_plan_memo.hpp"

#include <cstdint>
#include <cstring>
#include <mutex>
#include <unordered_map>
#include <utility>

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

// FNV-1a over the bytes of the inputs (a first sieve; equality is checked in full)
void mix(std::uint64_t& h, const void* p, std::size_t n) {
  const auto* b = static_cast<const unsigned char*>(p);
  for (std::size_t i = 0; i < n; ++i) h = (h ^ b[i]) * 1099511628211ull;
}
std::uint64_t hash_of(const NurbsCurve& c, const NurbsLimits& l) {
  std::uint64_t h = 1469598103934665603ull;
  mix(h, &c.degree, sizeof c.degree);
  mix(h, c.points.data(), c.points.size() * sizeof(Vec3));
  mix(h, c.weights.data(), c.weights.size() * sizeof(double));
  mix(h, c.knots.data(), c.knots.size() * sizeof(double));
  mix(h, &l.feed_mm_s, sizeof l.feed_mm_s);
  return h;
}

struct Entry {
  Key key;
  NurbsBlocks plan;  // without the dense schedule
  std::size_t bytes = 0;
};

struct Memo {
  std::mutex mutex;
  std::unordered_multimap<std::uint64_t, Entry> entries;
  std::size_t bytes = 0, hits = 0, misses = 0;
};

Memo& memo() {
  static Memo m;
  return m;
}

}  // namespace

NurbsBlocks plan_nurbs_blocks_memo(const NurbsCurve& curve, const NurbsLimits& limits) {
  const std::uint64_t h = hash_of(curve, limits);
  Memo& m = memo();
  {
    std::lock_guard<std::mutex> lock(m.mutex);
    auto [lo, hi] = m.entries.equal_range(h);
    for (auto it = lo; it != hi; ++it) {
      if (same(it->second.key, curve, limits)) {
        NurbsBlocks plan = std::move(it->second.plan);
        m.bytes -= it->second.bytes;
        m.entries.erase(it);
        ++m.hits;
        return plan;
      }
    }
    ++m.misses;
  }
  NurbsBlocks plan = plan_nurbs_blocks(curve, limits);
  if (!plan.error.empty()) return plan;  // refused curves are not kept (the pass ends there)
  Entry e;
  e.key = Key{curve, limits};
  e.plan.blocks = plan.blocks;
  e.plan.corner_after = plan.corner_after;
  e.bytes = plan.blocks.size() * sizeof(Block) +
            (curve.points.size() * sizeof(Vec3) + (curve.weights.size() + curve.knots.size()) * sizeof(double));
  std::lock_guard<std::mutex> lock(m.mutex);
  if (e.bytes > kNurbsPlanMemoBytes) return plan;
  if (m.bytes + e.bytes > kNurbsPlanMemoBytes) {
    m.entries.clear();
    m.bytes = 0;
  }
  m.bytes += e.bytes;
  m.entries.emplace(h, std::move(e));
  return plan;
}

NurbsPlanMemoStats nurbs_plan_memo_stats() {
  Memo& m = memo();
  std::lock_guard<std::mutex> lock(m.mutex);
  return {m.entries.size(), m.bytes, m.hits, m.misses};
}

void nurbs_plan_memo_clear() {
  Memo& m = memo();
  std::lock_guard<std::mutex> lock(m.mutex);
  m.entries.clear();
  m.bytes = 0;
  m.hits = 0;
  m.misses = 0;
}

}  // namespace pcnc
