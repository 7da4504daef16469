// offset.hpp — plane geometry for cutter radius compensation (points: vec2.hpp): the pieces of a
// contour (a straight segment or a circular arc, with its signed sweep), their offsets by a
// tool radius to the left or right, the sweep of an arc between two points (LinuxCNC's
// find_turn rule), and how two pieces meet (a convex or concave corner, or tangent).
// Pure functions: no I/O; the intersections and distances live in intersect.hpp.
#pragma once

#include <cmath>

#include "geometry/vec2.hpp"

namespace pcnc {

inline double angle_of(Vec2 a) { return std::atan2(a.y, a.x); }
inline Vec2 polar(double r, double angle) { return {r * std::cos(angle), r * std::sin(angle)}; }
/// a turned +90 degrees (to its left).
inline constexpr Vec2 left_normal(Vec2 a) { return perp(a); }

/// Which side of the path the tool runs on, looking along the path from +normal (G41 left,
/// G42 right).
enum class CompSide : unsigned char { kOff = 0, kLeft = 1, kRight = 2 };

/// One piece of a plane contour: a segment a->b, or an arc a->b about c of radius r and signed
/// sweep (> 0 counter-clockwise; |sweep| <= 2 pi). A segment with a == b is a point.
struct Piece {
  bool arc = false;
  Vec2 a{};
  Vec2 b{};
  Vec2 c{};
  double r = 0.0;
  double sweep = 0.0;
};

inline Piece segment(Vec2 a, Vec2 b) { return Piece{false, a, b, {}, 0.0, 0.0}; }
/// The arc from a about c turning `turn` (+1 ccw, -1 cw) to the direction of b; its radius is
/// |a - c| (b is taken as given: its distance from c may differ by round-off).
Piece arc_piece(Vec2 a, Vec2 b, Vec2 c, int turn);

/// LinuxCNC's sweep rule: the angle (radians, signed) from p1 to p2 about c turning `turn`
/// times (turn > 0 ccw, < 0 cw, 0 gives 0); p2 in the same direction as p1 is a full turn.
double turn_angle(Vec2 p1, Vec2 c, int turn, Vec2 p2);

/// Unit tangent of a piece at its start (at_end false) or end (true); a point has none (0,0).
Vec2 tangent(const Piece& p, bool at_end);

/// The piece offset by `radius` to `side` (kLeft/kRight) of its direction: a segment moves
/// along its normal; an arc keeps its center and changes radius (r - radius when the tool is
/// inside it). `ok` is false when the offset arc would have a radius <= 0 (the tool does not
/// fit inside the arc).
Piece offset_piece(const Piece& p, CompSide side, double radius, bool& ok);

/// True when the tool (on `side`) is inside an arc turning `turn` (G41 on a G3, G42 on a G2).
inline bool tool_inside_arc(CompSide side, int turn) {
  return (side == CompSide::kLeft && turn > 0) || (side == CompSide::kRight && turn < 0);
}

/// How the path turns from a piece ending in tangent t0 into one starting in tangent t1, with
/// the tool on `side`: the signed turn angle in (-pi, pi] (> 0 left), and whether the corner
/// is convex for the tool (the tool goes around the outside: a right turn for G41) beyond
/// `tolerance` radians, concave beyond it, or tangent within it.
enum class Corner : unsigned char { kTangent, kConvex, kConcave };
Corner classify_corner(Vec2 t0, Vec2 t1, CompSide side, double tolerance, double* turn_angle_out = nullptr);

}  // namespace pcnc
