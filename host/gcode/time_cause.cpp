// time_cause.cpp — the causes a run's time is attributed to, and the per-line plan recorded
// from the blocks (see time_cause.hpp).
#include "gcode/time_cause.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "geometry/arc_limits.hpp"
#include "geometry/plane.hpp"
#include "gcode/preprocessor.hpp"

namespace pcnc {
namespace {

constexpr double kCauseInf = std::numeric_limits<double>::infinity();
constexpr double kRel = 1e-9;            // relative tolerance when comparing a speed with a limit
constexpr double kStraightDeg = 0.5;     // a turn under this is no corner worth naming

struct CauseText {
  TimeCause cause;
  const char* key;
  const char* label;
};
constexpr CauseText kText[] = {
    {TimeCause::kFeed, "feed", "programmed feed F"},
    {TimeCause::kFeedClamp, "feed_clamp", "F clamped to the machine's maximum feed"},
    {TimeCause::kRapid, "rapid", "rapid (G0)"},
    {TimeCause::kAxisVelocityX, "axis_velocity_x", "axis X velocity limit"},
    {TimeCause::kAxisVelocityY, "axis_velocity_y", "axis Y velocity limit"},
    {TimeCause::kAxisVelocityZ, "axis_velocity_z", "axis Z velocity limit"},
    {TimeCause::kArcCentripetal, "arc_centripetal", "arc centripetal limit"},
    {TimeCause::kCurveSchedule, "curve_schedule", "curve (NURBS) feed schedule"},
    {TimeCause::kAccelX, "accel_x", "axis X acceleration limit"},
    {TimeCause::kAccelY, "accel_y", "axis Y acceleration limit"},
    {TimeCause::kAccelZ, "accel_z", "axis Z acceleration limit"},
    {TimeCause::kAccelArcCurve, "accel_arc_curve", "arc or curve tangential acceleration"},
    {TimeCause::kJunctionStop, "junction_stop", "junction stop"},
    {TimeCause::kJunctionCorner, "junction_corner", "corner speed (junction passed)"},
    {TimeCause::kStartEndStop, "start_end_stop", "start, end, dwell or pause stop"},
    {TimeCause::kOverride, "override", "feed override"},
    {TimeCause::kDwell, "dwell", "dwell (G4)"},
    {TimeCause::kPaused, "paused", "paused (hold, M0/M1)"},
    {TimeCause::kOther, "other", "other (stopping, underrun, fault)"},
};
static_assert(std::size(kText) == static_cast<std::size_t>(kTimeCauseCount));

TimeCause axis_cause(TimeCause x, int axis) {
  if (axis < 0 || axis >= 3) return TimeCause::kOther;
  return static_cast<TimeCause>(static_cast<int>(x) + axis);
}

bool is_motion(BlockKind k) {
  return k == BlockKind::kRapid || k == BlockKind::kLine || k == BlockKind::kArc || k == BlockKind::kNurbs ||
         k == BlockKind::kRuled;
}

double max_feed_mm_s(const MachineConfig& cfg) {
  double f = cfg.gcode.max_feed_mm_min > 0.0 ? cfg.gcode.max_feed_mm_min / 60.0 : 0.0;
  if (f <= 0.0) {
    for (const AxisConfig& a : cfg.axes) f = std::max(f, a.max_velocity_mm_s);
  }
  return f;
}

// Below `limit` by more than the comparison's tolerance: something else caps the speed.
bool below(double speed, double limit) { return speed < limit * (1.0 - kRel); }

TimeCause feed_or_clamp(double speed, const MachineConfig& cfg) {
  return below(speed, max_feed_mm_s(cfg)) ? TimeCause::kFeed : TimeCause::kFeedClamp;
}

}  // namespace

const char* time_cause_key(TimeCause c) {
  const auto i = static_cast<std::size_t>(c);
  return i < std::size(kText) ? kText[i].key : "other";
}

const char* time_cause_label(TimeCause c) {
  const auto i = static_cast<std::size_t>(c);
  return i < std::size(kText) ? kText[i].label : "other";
}

bool parse_time_cause(const std::string& key, TimeCause& c) {
  for (const CauseText& t : kText) {
    if (key == t.key) {
      c = t.cause;
      return true;
    }
  }
  return false;
}

TimeCause cruise_cause(const Block& b, const MachineConfig& cfg) {
  switch (b.kind) {
    case BlockKind::kRapid: return TimeCause::kRapid;
    case BlockKind::kNurbs: return TimeCause::kCurveSchedule;
    case BlockKind::kRuled: return TimeCause::kCurveSchedule;  // its schedule (the feed, or the joints' cap)
    case BlockKind::kDwell: return TimeCause::kDwell;
    case BlockKind::kPause: return TimeCause::kPaused;
    case BlockKind::kEnd: return TimeCause::kOther;
    case BlockKind::kLine: {
      double v_axes = kCauseInf;
      int axis = -1;
      for (int i = 0; i < kAxes; ++i) {
        const double ui = std::fabs(b.dir_start[static_cast<std::size_t>(i)]);
        if (ui <= 0.0) continue;
        const double v = cfg.axes[static_cast<std::size_t>(i)].max_velocity_mm_s / ui;
        if (v < v_axes) v_axes = v, axis = i;
      }
      // F at the machine's maximum (clamped there) names the clamp even where an axis allows no more
      if (axis < 0 || below(b.speed, v_axes) || !below(b.speed, max_feed_mm_s(cfg))) return feed_or_clamp(b.speed, cfg);
      return axis_cause(TimeCause::kAxisVelocityX, axis);
    }
    case BlockKind::kArc: {
      // the preprocessor's terms (plan_arc), each with what it stands for
      const ArcGeometry& g = b.arc;
      const int n = g.normal_axis;
      const auto pa = plane_axes(n);
      const auto a0 = static_cast<std::size_t>(pa[0]), a1 = static_cast<std::size_t>(pa[1]), nk = static_cast<std::size_t>(n);
      const double r = g.radius, sweep = g.sweep;
      const double pitch = std::fabs(sweep) > 0.0 ? g.helix / std::fabs(sweep) : 0.0;
      const double rho = std::sqrt(r * r + pitch * pitch);
      const double s_max = max_abs_sin(g.start_angle, sweep), c_max = max_abs_cos(g.start_angle, sweep);
      double v_axes = kCauseInf;
      TimeCause cause = TimeCause::kFeed;
      auto term = [&](double v, TimeCause c) {
        if (v < v_axes) v_axes = v, cause = c;
      };
      if (r > 0.0 && s_max > 0.0) term(cfg.axes[a0].max_velocity_mm_s * rho / (r * s_max), axis_cause(TimeCause::kAxisVelocityX, pa[0]));
      if (r > 0.0 && c_max > 0.0) term(cfg.axes[a1].max_velocity_mm_s * rho / (r * c_max), axis_cause(TimeCause::kAxisVelocityX, pa[1]));
      if (std::fabs(pitch) > 0.0) term(cfg.axes[nk].max_velocity_mm_s * rho / std::fabs(pitch), axis_cause(TimeCause::kAxisVelocityX, n));
      const ArcPlane plane = arc_plane(cfg.axes[a0].max_accel_mm_s2, cfg.axes[a1].max_accel_mm_s2, g.start_angle, sweep);
      if (r > 0.0) term(std::sqrt(kArcCentripetalShare * arc_centripetal_limit(plane) * rho * rho / r), TimeCause::kArcCentripetal);
      if (!std::isfinite(v_axes) || below(b.speed, v_axes)) return feed_or_clamp(b.speed, cfg);
      return cause;
    }
  }
  return TimeCause::kOther;
}

TimeCause accel_cause(const Block& b, const MachineConfig& cfg) {
  if (b.kind == BlockKind::kArc || b.kind == BlockKind::kNurbs) return TimeCause::kAccelArcCurve;
  double a_min = kCauseInf;
  int axis = 0;
  for (int i = 0; i < kAxes; ++i) {
    const double ui = std::fabs(b.dir_start[static_cast<std::size_t>(i)]);
    if (ui <= 0.0) continue;
    const double a = cfg.axes[static_cast<std::size_t>(i)].max_accel_mm_s2 / ui;
    if (a < a_min) a_min = a, axis = i;
  }
  return axis_cause(TimeCause::kAccelX, axis);
}

PlanRecorder::PlanRecorder(const MachineConfig& config) : config_(config) {}

void PlanRecorder::push(const LinePlan& p) {
  if (!plan_.empty()) {
    LinePlan& q = plan_.back();
    // one entry for a run of lines that nothing stops or turns between, with one plan
    if (q.after == JunctionKind::kStraight && p.before == JunctionKind::kStraight && q.cruise == p.cruise &&
        q.accel == p.accel && q.speed == p.speed && p.first >= q.first && p.first <= q.last + 1) {
      q.last = std::max(q.last, p.last);
      q.after = p.after;
      q.angle_after_deg = p.angle_after_deg;
      return;
    }
  }
  plan_.push_back(p);
}

void PlanRecorder::add(const Block& b) {
  // the junction between the previous block and this one, by the rt's rules (rt/motion/junction.hpp)
  JunctionKind j = JunctionKind::kStartEnd;
  double angle = 0.0;
  if (has_prev_ && is_motion(prev_.kind) && is_motion(b.kind)) {
    const double c = std::clamp(dot(prev_.dir_end, b.dir_start), -1.0, 1.0);
    angle = std::acos(c) * 180.0 / std::numbers::pi;
    const bool under_angle = angle < config_.motion.contouring_angle_deg;
    const bool tolerance = prev_.path_tolerance_mm > 0.0f && angle < 179.0;  // the block's (G64 P, --tolerance)
    if (prev_.rotary.angular || b.rotary.angular) {
      j = JunctionKind::kTurnStop;  // the rt starts and ends an angular block at rest (executor.cpp)
      angle = 0.0;                  // its dirs are not a tip's: no turn to name
    } else if (!prev_.contouring) {
      j = JunctionKind::kContouringOff;
    } else if (under_angle || tolerance) {
      j = angle < kStraightDeg ? JunctionKind::kStraight : JunctionKind::kCorner;
    } else {
      j = JunctionKind::kAngleStop;
    }
  }
  if (pending_set_) {
    pending_.after = j;
    pending_.angle_after_deg = angle;
    push(pending_);
    pending_set_ = false;
  }
  if (b.kind != BlockKind::kEnd) {
    LinePlan p;
    p.first = p.last = b.line;
    p.cruise = cruise_cause(b, config_);
    p.accel = accel_cause(b, config_);
    p.speed = b.kind == BlockKind::kNurbs
                  ? *std::max_element(b.nurbs.schedule_speed, b.nurbs.schedule_speed + std::max<int>(1, b.nurbs.schedule_count))
                  : b.speed;
    p.before = j;
    p.angle_before_deg = angle;
    pending_ = p;
    pending_set_ = true;
  }
  prev_.kind = b.kind;
  prev_.line = b.line;
  prev_.dir_end = b.dir_end;
  prev_.contouring = b.contouring;
  prev_.rotary.angular = b.rotary.angular;
  prev_.path_tolerance_mm = b.path_tolerance_mm;  // the junction after it is judged with it (rt's rule)
  has_prev_ = true;
}

std::vector<LinePlan> PlanRecorder::finish() {
  if (pending_set_) {
    pending_.after = JunctionKind::kStartEnd;
    push(pending_);
    pending_set_ = false;
  }
  return std::move(plan_);
}

}  // namespace pcnc
