// block_ruled.hpp — a ruled-surface piece as fixed-size data for a ring slot (issue 17): what
// the host sends and the rt's RuledFollower (rt/motion/ruled_follower.hpp) evaluates every
// cycle. The directrix (tool tip, workpiece coordinates after the work offsets, mm) and the
// ruling (the tool axis, tip to spindle: vectors normalised at evaluation, or (theta, phi, 0))
// are Ferguson chains over u in [0, segment_count]; the feed schedule caps the tip's speed
// along the directrix at parameter values, linear in between.
//
// Its place in the segment layout (a `ruled` block kind beside kLine/kArc/kNurbs in
// ipc/block.hpp) comes with the 5-axis block wiring: this header defines the data only and
// touches no existing layout. Trivially copyable and standard layout, like Block.
#pragma once

#include <cstdint>
#include <string>
#include <type_traits>
#include <vector>

#include "geometry/hermite_curve.hpp"
#include "geometry/ruled_model.hpp"
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
  double schedule_u[kMaxRuledSchedule]{};
  double schedule_speed[kMaxRuledSchedule]{};
};
static_assert(std::is_trivially_copyable_v<RuledGeometry>, "RuledGeometry lives in shared memory");
static_assert(std::is_standard_layout_v<RuledGeometry>, "RuledGeometry lives in shared memory");

/// The curves of the piece as the geometry library evaluates them (views into `g`).
RuledCurves curves_of(const RuledGeometry& g);

/// Fills `g` from a model (host side): its segments, the directrix's length (Gauss–Legendre),
/// a constant schedule at `feed_mm_s`, `accel`, start and end speeds. Returns an error
/// sentence when the model does not fit one block or a value is out of range; empty when done.
std::string to_geometry(const RuledModel& model, double feed_mm_s, double accel_mm_s2, double start_speed,
                        double end_speed, RuledGeometry& g);

/// The model cut at set points into parts of at most kMaxRuledSegments segments, each keeping
/// the piece's own segments (the tangents at a cut stay the whole piece's).
std::vector<RuledModel> split_for_blocks(const RuledModel& model);

/// Arc length of a Hermite chain over [0, count] (16-point Gauss–Legendre per segment).
double hermite_arc_length(const HermiteView& c);

}  // namespace pcnc
