// nurbs_plan_key.hpp — what makes two curve plans the same (plan_nurbs_blocks is a pure
// function of its curve and limits): the exact comparison and the hash that the plan memo
// (nurbs_plan_memo.cpp) and the check pass's prefetch (nurbs_plan_prefetch.cpp) look plans up by.
#pragma once

#include <cstdint>

#include "gcode/hand_over_memo.hpp"
#include "gcode/nurbs_schedule.hpp"

namespace pcnc {

/// A plan's inputs, kept with it.
struct NurbsPlanKey {
  NurbsCurve curve;
  NurbsLimits limits;
};

inline bool same_nurbs_limits(const NurbsLimits& a, const NurbsLimits& b) {
  return a.feed_mm_s == b.feed_mm_s && a.period_s == b.period_s && a.chord_tolerance_mm == b.chord_tolerance_mm &&
         a.axis_velocity_mm_s == b.axis_velocity_mm_s && a.axis_accel_mm_s2 == b.axis_accel_mm_s2 &&
         a.normal_accel_share == b.normal_accel_share && a.samples_per_span == b.samples_per_span;
}

/// Every control point, weight, knot and limit equal.
inline bool same_plan_input(const NurbsPlanKey& k, const NurbsCurve& c, const NurbsLimits& l) {
  return k.curve.degree == c.degree && k.curve.points == c.points && k.curve.weights == c.weights &&
         k.curve.knots == c.knots && same_nurbs_limits(k.limits, l);
}

/// A sieve for same_plan_input (the curve and the feed).
inline std::uint64_t plan_input_hash(const NurbsCurve& c, const NurbsLimits& l) {
  std::uint64_t h = kFnv1aSeed;
  fnv1a_mix(h, &c.degree, sizeof c.degree);
  fnv1a_mix(h, c.points.data(), c.points.size() * sizeof(Vec3));
  fnv1a_mix(h, c.weights.data(), c.weights.size() * sizeof(double));
  fnv1a_mix(h, c.knots.data(), c.knots.size() * sizeof(double));
  fnv1a_mix(h, &l.feed_mm_s, sizeof l.feed_mm_s);
  return h;
}

}  // namespace pcnc
