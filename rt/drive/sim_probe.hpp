// sim_probe.hpp — the simulated touch-trigger probe: its input, sensed each cycle from the
// commanded ball centre against the table's objects (shared/geometry/probe_contact.hpp).
//
// Why the commanded position (DESIGN.md, docs/probe.md): the latched value a controller reports
// is its commanded position in the cycle the input changed (LinuxCNC latches the commanded
// position too), and sensing from it keeps the trigger independent of the servo's lag, so that
// a probed point differs from the true surface by the probe's own errors (pre-travel, noise)
// alone, the errors the seed's calibration is about.
//
// arm(d) starts a probing move along d: the pre-travel for d plus one draw of the repeatability
// noise (a Gaussian from a deterministic generator seeded by [probe] seed) set the trigger
// radius R − δ − noise for that move. The machine's volumetric error ([machine_error]) moves
// the ball from the commanded position to where the machine really is, unseen by the
// encoders. Pure computation: no allocation, no I/O.
#pragma once

#include <cstdint>

#include "config/config.hpp"
#include "geometry/probe_contact.hpp"

namespace pcnc {

class SimProbe {
 public:
  explicit SimProbe(const MachineConfig& config);

  /// A probing move along `dir` begins: draws this touch's trigger radius.
  void arm(const Vec3& dir);
  /// Senses at the ball centre `c` (the commanded position); returns the input.
  bool sense(const Vec3& c);
  bool input() const { return input_; }
  bool present() const { return present_; }
  double trigger_radius() const { return trigger_radius_; }

 private:
  double gaussian();  // standard normal (Box-Muller over splitmix64)

  bool present_ = false;
  TableScene scene_{};
  ProbeModel model_{};
  bool has_error_ = false;
  VolumetricError error_{};  // [machine_error]: the ball is at actual_position(error_, commanded)
  double trigger_radius_ = 0.0;
  bool input_ = false;
  std::uint64_t state_ = 0;
};

}  // namespace pcnc
