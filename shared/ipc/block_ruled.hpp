// block_ruled.hpp — a ruled-surface piece as fixed-size data for a ring slot (issue 17): what
// the host sends and the rt's RuledFollower (rt/motion/ruled_follower.hpp) evaluates every
// cycle. The directrix (tool tip, workpiece coordinates after the work offsets, mm) and the
// ruling (the tool axis, tip to spindle: vectors normalised at evaluation, or (theta, phi, 0))
// are Ferguson chains over u in [0, segment_count]; the feed schedule caps the tip's speed
// along the directrix at parameter values, linear in between.
//
// The data itself (RuledGeometry) is ipc/ruled_geometry.hpp, a member of every Block (the
// `ruled` block kind, layout version 9); this header adds the host's and the rt's functions on it.
#pragma once

#include <cstdint>
#include <string>
#include <type_traits>
#include <vector>

#include "geometry/hermite_curve.hpp"
#include "geometry/ruled_model.hpp"
#include "geometry/ruled_surface.hpp"
#include "ipc/ruled_geometry.hpp"

namespace pcnc {

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

/// The NURBS blocks' driving-axis rule for a ruled piece: over its set points (the segments'
/// ends), the axes that move (extent > 1e-12 mm) and the one with the widest extent (the first
/// on a tie). The host writes it into the block, the block check verifies it.
struct RuledExtent {
  int moving = 0;
  int widest = 0;
};
RuledExtent ruled_extent(const RuledGeometry& g);

/// Arc length of a Hermite chain over [0, count] (16-point Gauss–Legendre per segment).
double hermite_arc_length(const HermiteView& c);

}  // namespace pcnc
