// sim_probe.cpp — the simulated probe's input and its deterministic noise (sim_probe.hpp).
#include "drive/sim_probe.hpp"

#include <cmath>
#include <numbers>

namespace pcnc {

SimProbe::SimProbe(const MachineConfig& config)
    : present_(config.probe.present),
      scene_(config.table),
      model_(config.probe.model),
      has_error_(config.has_machine_error),
      error_(config.machine_error),
      state_(config.probe.model.seed) {
  trigger_radius_ = model_.ball_radius_mm - pretravel_mm(model_, {0.0, 0.0, -1.0});
}

double SimProbe::gaussian() {
  auto next = [this] {  // splitmix64: a uniform in (0, 1]
    std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    z ^= z >> 31;
    return (static_cast<double>(z >> 11) + 1.0) * 0x1.0p-53;
  };
  const double u1 = next(), u2 = next();
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * std::numbers::pi * u2);
}

void SimProbe::arm(const Vec3& dir) {
  const double noise = model_.repeatability_mm > 0.0 ? model_.repeatability_mm * gaussian() : 0.0;
  trigger_radius_ = model_.ball_radius_mm - pretravel_mm(model_, dir) - noise;
}

bool SimProbe::sense(const Vec3& c) {
  // the ball is where the machine really is, not where its encoders say (the volumetric error)
  input_ = present_ && ball_touches(scene_, has_error_ ? actual_position(error_, c) : c, trigger_radius_);
  return input_;
}

}  // namespace pcnc
