// planned_time.cpp — the planned time of a block (see planned_time.hpp).
#include "gcode/planned_time.hpp"

#include <cmath>

namespace pcnc {

namespace {
// Rest to rest over `length` with speed limit v and acceleration a.
double rest_to_rest(double length, double v, double a) {
  if (!(length > 0.0) || !(v > 0.0)) return 0.0;
  if (!(a > 0.0)) return length / v;
  if (length >= v * v / a) return length / v + v / a;  // accelerate, cruise, decelerate
  return 2.0 * std::sqrt(length / a);                   // a triangle: v is never reached
}
}  // namespace

double planned_time_s(const Block& b) {
  switch (b.kind) {
    case BlockKind::kDwell: return b.dwell_s > 0.0 ? b.dwell_s : 0.0;
    case BlockKind::kPause:
    case BlockKind::kEnd: return 0.0;
    case BlockKind::kArc:
      if (b.arc.angular_speed > 0.0) {
        return rest_to_rest(std::fabs(b.arc.sweep), b.arc.angular_speed, b.arc.angular_accel);
      }
      return rest_to_rest(b.length, b.speed, b.accel);
    default: return rest_to_rest(b.length, b.speed, b.accel);
  }
}

}  // namespace pcnc
