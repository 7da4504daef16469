// drive.cpp — the three axes' servo and plant stepped together (see drive.hpp).
#include "drive/drive.hpp"

#include <algorithm>
#include <cmath>

namespace pcnc {
namespace {

AxisPlant make_plant(const MachineConfig& c, int i) {
  const int sub = static_cast<int>(std::lround(c.motion.subsample_steps));
  return AxisPlant(c.axes[i], c.cycle_period_s(), std::max(1, sub), c.axes[i].home_mm);
}

RotaryAxisConfig joint_or_default(const MachineConfig& c, int i) {
  const auto& j = c.rotary[static_cast<std::size_t>(i)];
  return j ? *j : RotaryAxisConfig{};
}

AxisPid make_rpid(const MachineConfig& c, int i) { return AxisPid(pid_gains(joint_or_default(c, i)), c.cycle_period_s()); }

AxisPlant make_rplant(const MachineConfig& c, int i) {
  const int sub = static_cast<int>(std::lround(c.motion.subsample_steps));
  const RotaryAxisConfig j = joint_or_default(c, i);
  return AxisPlant(plant_model(j), c.cycle_period_s(), std::max(1, sub), j.home_rad);
}

}  // namespace

Drive::Drive(const MachineConfig& c)
    : pid_{AxisPid(c.axes[0], c.cycle_period_s()), AxisPid(c.axes[1], c.cycle_period_s()),
           AxisPid(c.axes[2], c.cycle_period_s())},
      plant_{make_plant(c, 0), make_plant(c, 1), make_plant(c, 2)},
      mask_(c.rotary_mask()),
      rpid_{make_rpid(c, 0), make_rpid(c, 1), make_rpid(c, 2)},
      rplant_{make_rplant(c, 0), make_rplant(c, 1), make_rplant(c, 2)} {
  for (int i = 0; i < kAxes; ++i) hold_a_[i] = c.axes[i].gravity_load_n / c.axes[i].force_constant_n_per_a;
  reset_servo();
}

void Drive::reset_servo() {
  for (int i = 0; i < kAxes; ++i) pid_[i].reset(hold_a_[i]);
  for (int i = 0; i < kRotaryJoints; ++i) rpid_[static_cast<std::size_t>(i)].reset(0.0);
}

Rot3 Drive::rotary_encoder() const {
  Rot3 r{};
  for (int i = 0; i < kRotaryJoints; ++i) {
    if (has_joint(mask_, i)) r[static_cast<std::size_t>(i)] = rplant_[static_cast<std::size_t>(i)].encoder();
  }
  return r;
}

Rot3 Drive::rotary_true_position() const {
  Rot3 r{};
  for (int i = 0; i < kRotaryJoints; ++i) {
    if (has_joint(mask_, i)) r[static_cast<std::size_t>(i)] = rplant_[static_cast<std::size_t>(i)].position();
  }
  return r;
}

void Drive::step_rotary(const Rot3& command, const Rot3& measured, const Rot3& velocity, const Rot3& accel,
                        bool amps_on) {
  for (int i = 0; i < kRotaryJoints; ++i) {
    if (!has_joint(mask_, i)) continue;
    const auto k = static_cast<std::size_t>(i);
    const double u = amps_on ? rpid_[k].update(command[k], measured[k], velocity[k], accel[k]) : 0.0;
    rplant_[k].step(u, amps_on);
  }
}

void Drive::place_rotary(const Rot3& at) {
  for (int i = 0; i < kRotaryJoints; ++i) {
    if (has_joint(mask_, i)) rplant_[static_cast<std::size_t>(i)].place(at[static_cast<std::size_t>(i)]);
  }
  reset_servo();
}

void Drive::step(const Vec3& command, const Vec3& measured, const Vec3& velocity, const Vec3& accel, bool amps_on) {
  for (int i = 0; i < kAxes; ++i) {
    const double u = amps_on ? pid_[i].update(command[i], measured[i], velocity[i], accel[i]) : 0.0;
    plant_[i].step(u, amps_on);
  }
}

void Drive::place(const Vec3& at) {
  for (int i = 0; i < kAxes; ++i) plant_[i].place(at[i]);
  reset_servo();
}

void Drive::set_blocked(int axis, bool blocked) {
  if (axis >= 0 && axis < kAxes) plant_[static_cast<std::size_t>(axis)].set_blocked(blocked);
}

}  // namespace pcnc
