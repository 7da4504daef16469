// jog.cpp — one-axis jog motion (see jog.hpp).
#include "motion/jog.hpp"

#include <algorithm>
#include <cmath>

#include "motion/junction.hpp"

namespace pcnc {

Jog::Jog(const MachineConfig& config) : cfg_(config), dt_(config.cycle_period_s()) {}

bool Jog::begin(const Vec3& from, int axis, double target, double feed) {
  if (axis < 0 || axis >= kAxes || !std::isfinite(target) || !std::isfinite(feed) || !(feed > 0.0)) return false;
  if (active_ && axis != axis_) return false;
  const AxisConfig& ac = cfg_.axes[axis];
  if (!active_) {
    pos_ = from;
    v_ = 0.0;
    a_ = 0.0;
  }
  active_ = true;
  stopping_ = false;
  axis_ = axis;
  target_ = std::clamp(target, ac.travel_min_mm, ac.travel_max_mm);
  feed_ = std::min(feed, ac.max_velocity_mm_s);
  accel_ = ac.max_accel_mm_s2 * cfg_.motion.jog_accel_fraction;
  since_keepalive_ = 0.0;
  return true;
}

bool Jog::start_increment(const Vec3& from, int axis, double distance, double feed) {
  if (!std::isfinite(distance)) return false;
  const Vec3 base = active_ ? pos_ : from;
  if (axis < 0 || axis >= kAxes) return false;
  // An increment on a jog in progress adds to its current target.
  const double origin = (active_ && axis == axis_ && !continuous_) ? target_ : base[axis];
  if (!begin(from, axis, origin + distance, feed)) return false;
  continuous_ = false;
  return true;
}

bool Jog::start_continuous(const Vec3& from, int axis, double direction, double feed) {
  if (axis < 0 || axis >= kAxes || !std::isfinite(direction) || direction == 0.0) return false;
  const AxisConfig& ac = cfg_.axes[axis];
  if (!begin(from, axis, direction > 0.0 ? ac.travel_max_mm : ac.travel_min_mm, feed)) return false;
  continuous_ = true;
  return true;
}

Vec3 Jog::velocity() const {
  Vec3 v{};
  v[axis_] = v_;
  return v;
}

Vec3 Jog::acceleration() const {
  Vec3 a{};
  a[axis_] = a_;
  return a;
}

bool Jog::step() {
  if (!active_) return false;
  if (continuous_) {
    since_keepalive_ += dt_;
    if (since_keepalive_ > cfg_.process.jog_deadman_s) stopping_ = true;
  }
  const double x = pos_[axis_];
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
  x_new = std::clamp(x_new, cfg_.axes[axis_].travel_min_mm, cfg_.axes[axis_].travel_max_mm);
  const double v_signed = (x_new - x) / dt_;
  a_ = (v_signed - v_) / dt_;
  v_ = v_signed;
  pos_[axis_] = x_new;
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
