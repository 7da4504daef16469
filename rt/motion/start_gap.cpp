// start_gap.cpp — the gap move before a block that starts from rest (start_gap.hpp).
#include "motion/start_gap.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "motion/junction.hpp"

namespace pcnc {

void StartGap::begin(const Vec3& from, const Vec3& to, const MachineConfig& config, double dt) {
  from_ = from;
  to_ = to;
  length_ = norm(to - from);
  dir_ = length_ > 0.0 ? (1.0 / length_) * (to - from) : Vec3{0.0, 0.0, 0.0};
  // along dir_, the path acceleration (speed) that keeps every axis within its own
  accel_ = std::numeric_limits<double>::infinity();
  vmax_ = std::numeric_limits<double>::infinity();
  for (int i = 0; i < kAxes; ++i) {
    const double share = std::abs(dir_[i]);
    if (share == 0.0) continue;
    accel_ = std::min(accel_, config.axes[i].max_accel_mm_s2 / share);
    vmax_ = std::min(vmax_, config.axes[i].max_velocity_mm_s / share);
  }
  dt_ = dt;
  s_ = 0.0;
  v_ = 0.0;
  pos_ = from;
  vel_ = acc_ = {0.0, 0.0, 0.0};
  active_ = length_ > 0.0 && std::isfinite(accel_) && accel_ > 0.0 && dt > 0.0;
}

bool StartGap::step() {
  if (!active_) return false;
  const double remaining = length_ - s_;
  const double v_old = v_;
  double v = std::min({v_ + accel_ * dt_, stop_speed_exact(remaining, accel_, dt_), vmax_});
  v = std::max({v, v_ - accel_ * dt_, 0.0});
  // land when the rest takes no more than one cycle's acceleration either way (and the stop
  // after it is within one cycle's too), as a block lands at a stop
  const double v_land = remaining / dt_;
  const bool lands = v_land <= accel_ * dt_ && v_land >= v_ - accel_ * dt_;
  if (lands) v = v_land;
  v_ = v;
  s_ = lands ? length_ : std::min(length_, s_ + v * dt_);
  pos_ = lands ? to_ : from_ + s_ * dir_;
  vel_ = v * dir_;
  acc_ = ((v - v_old) / dt_) * dir_;
  if (lands) active_ = false;
  return lands;
}

}  // namespace pcnc
