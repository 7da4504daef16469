// jog.cpp — one-axis jog motion (see jog.hpp).
#include "motion/jog.hpp"

#include <algorithm>
#include <cmath>

#include "motion/junction.hpp"

namespace pcnc {

namespace {
// How far a continuous jog of a continuous rotary joint heads (rad): 1000 turns.
constexpr double kEndless = 2000.0 * 3.14159265358979323846;
}  // namespace

Jog::Jog(const MachineConfig& config) : cfg_(config), dt_(config.cycle_period_s()) {}

bool Jog::valid_axis(int axis) const {
  if (axis >= 0 && axis < kAxes) return true;
  return axis >= kAxes && axis < kAxes + kRotaryJoints && cfg_.rotary[static_cast<std::size_t>(axis - kAxes)].has_value();
}

Jog::Limits Jog::limits(int axis) const {
  if (axis < kAxes) {
    const AxisConfig& ac = cfg_.axes[static_cast<std::size_t>(axis)];
    return {ac.travel_min_mm, ac.travel_max_mm, ac.max_velocity_mm_s, ac.max_accel_mm_s2};
  }
  const RotaryAxisConfig& j = *cfg_.rotary[static_cast<std::size_t>(axis - kAxes)];
  if (j.continuous) return {-kEndless, kEndless, j.max_velocity_rad_s, j.max_accel_rad_s2};
  return {j.travel_min_rad, j.travel_max_rad, j.max_velocity_rad_s, j.max_accel_rad_s2};
}

double& Jog::coord(int axis) {
  return axis < kAxes ? pos_[static_cast<std::size_t>(axis)] : rot_[static_cast<std::size_t>(axis - kAxes)];
}

bool Jog::begin(const Vec3& from, int axis, double target, double feed) {
  if (!valid_axis(axis) || !std::isfinite(target) || !std::isfinite(feed) || !(feed > 0.0)) return false;
  if (active_ && axis != axis_) return false;
  const Limits lim = limits(axis);
  if (!active_) {
    pos_ = from;
    v_ = 0.0;
    a_ = 0.0;
  }
  active_ = true;
  stopping_ = false;
  axis_ = axis;
  target_ = std::clamp(target, lim.min, lim.max);
  feed_ = std::min(feed, lim.vmax);
  accel_ = lim.amax * cfg_.motion.jog_accel_fraction;
  since_keepalive_ = 0.0;
  return true;
}

bool Jog::start_increment(const Vec3& from, int axis, double distance, double feed) {
  if (!std::isfinite(distance)) return false;
  if (!valid_axis(axis)) return false;
  if (!active_) pos_ = from;
  // An increment on a jog in progress adds to its current target.
  const double origin = (active_ && axis == axis_ && !continuous_) ? target_ : coord(axis);
  if (!begin(from, axis, origin + distance, feed)) return false;
  continuous_ = false;
  return true;
}

bool Jog::start_continuous(const Vec3& from, int axis, double direction, double feed) {
  if (!valid_axis(axis) || !std::isfinite(direction) || direction == 0.0) return false;
  const Limits lim = limits(axis);
  if (!active_) pos_ = from;
  const double base = axis >= kAxes ? coord(axis) : 0.0;  // an endless joint heads 1000 turns on
  if (!begin(from, axis, direction > 0.0 ? std::min(lim.max, base + kEndless) : std::max(lim.min, base - kEndless), feed)) {
    return false;
  }
  continuous_ = true;
  return true;
}

Vec3 Jog::velocity() const {
  Vec3 v{};
  if (axis_ < kAxes) v[static_cast<std::size_t>(axis_)] = v_;
  return v;
}

Vec3 Jog::acceleration() const {
  Vec3 a{};
  if (axis_ < kAxes) a[static_cast<std::size_t>(axis_)] = a_;
  return a;
}

Rot3 Jog::rotary_velocity() const {
  Rot3 v{};
  if (axis_ >= kAxes) v[static_cast<std::size_t>(axis_ - kAxes)] = v_;
  return v;
}

Rot3 Jog::rotary_acceleration() const {
  Rot3 a{};
  if (axis_ >= kAxes) a[static_cast<std::size_t>(axis_ - kAxes)] = a_;
  return a;
}

bool Jog::step() {
  if (!active_) return false;
  if (continuous_) {
    since_keepalive_ += dt_;
    if (since_keepalive_ > cfg_.process.jog_deadman_s) stopping_ = true;
  }
  const double x = coord(axis_);
  const Limits lim = limits(axis_);
  const double dir = target_ >= x ? 1.0 : -1.0;
  const double remaining = std::abs(target_ - x);
  const double v = v_ * dir;  // speed toward the target (negative: moving away)
  double allow = stopping_ ? 0.0 : std::min(feed_, stop_speed(remaining, 0.0, accel_, dt_, 1.0));
  double v_new = std::clamp(allow, v - accel_ * dt_, v + accel_ * dt_);
  if (stopping_) v_new = v >= 0.0 ? std::max(v - accel_ * dt_, 0.0) : std::min(v + accel_ * dt_, 0.0);
  bool arrived = false;
  if (!stopping_ && remaining / dt_ <= accel_ * dt_ && remaining / dt_ >= v - accel_ * dt_) {
    v_new = remaining / dt_;  // land exactly on the target
    arrived = true;
  }
  double x_new = x + dir * v_new * dt_;
  x_new = std::clamp(x_new, lim.min, lim.max);
  const double v_signed = (x_new - x) / dt_;
  a_ = (v_signed - v_) / dt_;
  v_ = v_signed;
  coord(axis_) = x_new;
  if ((arrived || stopping_) && v_new == 0.0) {
    active_ = false;
    v_ = 0.0;
    a_ = 0.0;
  } else if (arrived) {
    // the next cycle holds at rest
    stopping_ = true;
  }
  return active_;
}

}  // namespace pcnc
