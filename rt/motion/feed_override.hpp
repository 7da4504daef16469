// feed_override.hpp — the operator's feed override (kFeedOverride, 0 .. 200 %).
//
// The override only scales the speed caps the executor plans with; the path speed itself
// still changes by at most the block's acceleration per cycle (executor.hpp), so any jump of
// the override — 0 % to 200 % at once — turns into a ramp, never a velocity step. Non-finite
// requests are ignored; the value is clamped to [0, 2]. Overridden speeds never exceed what
// the axes allow on the curve (PreparedBlock::v_machine).
#pragma once

#include <algorithm>
#include <cmath>

#include "geometry/arc_limits.hpp"

namespace pcnc {

class FeedOverride {
 public:
  static constexpr double kMax = 2.0;
  static_assert(kMax == kArcMaxFeedOverride, "arcs are planned for the largest override");
  /// Returns false (and keeps the old value) for a non-finite request.
  bool set(double fraction) {
    if (!std::isfinite(fraction)) return false;
    value_ = std::clamp(fraction, 0.0, kMax);
    return true;
  }
  double value() const { return value_; }

 private:
  double value_ = 1.0;
};

}  // namespace pcnc
