// ruled_geometry.hpp — the ruled-surface piece of a block (BlockKind::kRuled, issue 17): fixed
// size data in a ring slot (layout version 9). The directrix (tool tip, workpiece coordinates
// after the work offsets, mm) and the ruling (the tool axis, tip to spindle: vectors normalised
// at evaluation, or (theta, phi, 0)) are Ferguson chains over u in [0, segment_count]; the feed
// schedule caps the tip's speed along the directrix at parameter values, linear in between.
// Functions on it: ipc/block_ruled.hpp (host and rt), rt/motion/ruled_follower.hpp (the cycle).
#pragma once

#include <cstdint>
#include <type_traits>

#include "geometry/hermite_curve.hpp"
#include "geometry/ruled_surface.hpp"

namespace pcnc {

/// Ferguson segments per block; a longer piece is split at set points by the host, each part
/// keeping the piece's own segments (not re-fitted). 32 segments: 6 KiB of curve data.
constexpr int kMaxRuledSegments = 32;
/// Feed schedule points per block (one per set point and one more).
constexpr int kMaxRuledSchedule = kMaxRuledSegments + 1;

struct RuledGeometry {
  std::int32_t segment_count = 0;
  std::int32_t ruling_form = static_cast<std::int32_t>(RulingForm::kVector);  // a RulingForm
  HermiteSegment directrix[kMaxRuledSegments]{};
  HermiteSegment ruling[kMaxRuledSegments]{};
  double length = 0.0;       // arc length of the directrix, mm
  double accel = 0.0;        // tangential acceleration for speed changes and braking, mm/s^2 (> 0)
  double start_speed = 0.0;  // tip speed the piece starts with, mm/s
  double end_speed = 0.0;    // tip speed it must end with (0: stop at its end), mm/s
  // Feed schedule: the speed cap (mm/s) at increasing parameter values, linear in between;
  // constant beyond the ends. At least one point.
  std::int32_t schedule_count = 0;
  std::int32_t reserved = 0;  // explicit: no padding bytes, so equal blocks are equal bytes
  double schedule_u[kMaxRuledSchedule]{};
  double schedule_speed[kMaxRuledSchedule]{};
};
static_assert(std::is_trivially_copyable_v<RuledGeometry>, "RuledGeometry lives in shared memory");
static_assert(std::is_standard_layout_v<RuledGeometry>, "RuledGeometry lives in shared memory");

}  // namespace pcnc
