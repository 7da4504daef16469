// offset.cpp — offsets of plane pieces and the corner rule (see offset.hpp).
#include "geometry/offset.hpp"

#include <numbers>

namespace pcnc {

namespace {
constexpr double kPi = std::numbers::pi;
}

double turn_angle(Vec2 p1, Vec2 c, int turn, Vec2 p2) {
  if (turn == 0) return 0.0;
  double alpha = std::atan2(p1.y - c.y, p1.x - c.x);
  double beta = std::atan2(p2.y - c.y, p2.x - c.x);
  if (turn > 0) {
    if (beta <= alpha) beta += 2.0 * kPi;
    return (beta - alpha) + (turn - 1) * 2.0 * kPi;
  }
  if (alpha <= beta) alpha += 2.0 * kPi;
  return (beta - alpha) + (turn + 1) * 2.0 * kPi;
}

Piece arc_piece(Vec2 a, Vec2 b, Vec2 c, int turn) {
  Piece p;
  p.arc = true;
  p.a = a;
  p.b = b;
  p.c = c;
  p.r = norm(a - c);
  p.sweep = turn_angle(a, c, turn, b);
  return p;
}

Vec2 tangent(const Piece& p, bool at_end) {
  if (!p.arc) {
    const Vec2 d = p.b - p.a;
    const double n = norm(d);
    return n > 0.0 ? (1.0 / n) * d : Vec2{};
  }
  const Vec2 radial = (at_end ? p.b : p.a) - p.c;
  const double n = norm(radial);
  if (!(n > 0.0)) return {};
  const Vec2 t = left_normal((1.0 / n) * radial);
  return p.sweep >= 0.0 ? t : -1.0 * t;
}

Piece offset_piece(const Piece& p, CompSide side, double radius, bool& ok) {
  ok = true;
  Piece o = p;
  if (!p.arc) {
    const Vec2 t = tangent(p, false);
    const Vec2 n = side == CompSide::kLeft ? left_normal(t) : -1.0 * left_normal(t);
    o.a = p.a + radius * n;
    o.b = p.b + radius * n;
    return o;
  }
  const int turn = p.sweep >= 0.0 ? 1 : -1;
  const double r = tool_inside_arc(side, turn) ? p.r - radius : p.r + radius;
  if (!(r > 0.0)) {
    ok = false;
    return o;
  }
  const auto moved = [&](Vec2 q) {
    const Vec2 d = q - p.c;
    const double n = norm(d);
    return n > 0.0 ? p.c + (r / n) * d : q;
  };
  o.a = moved(p.a);
  o.b = moved(p.b);
  o.r = r;
  return o;
}

Corner classify_corner(Vec2 t0, Vec2 t1, CompSide side, double tolerance, double* turn_angle_out) {
  const double turn = std::atan2(cross(t0, t1), dot(t0, t1));  // > 0: the path turns left
  if (turn_angle_out) *turn_angle_out = turn;
  if (std::fabs(turn) <= tolerance) return Corner::kTangent;
  // The tool on the left goes around the outside of a right turn.
  const bool convex = side == CompSide::kLeft ? turn < 0.0 : turn > 0.0;
  return convex ? Corner::kConvex : Corner::kConcave;
}

}  // namespace pcnc
