// work_store.hpp — the service's work-coordinate state (config/work_state.hpp): loaded from
// its file in the private state directory when the service starts, changed by set_offset and
// saved at once (so a change survives a restart of the service), read by status and copied
// into each job when it starts. The config's gcode.g54..g59 are only its defaults.
//
// Loop thread only (set_offset, status and run all run there): no lock.
//
// May include: shared/config.
#pragma once

#include <optional>
#include <string>

#include "config/work_state.hpp"

namespace pcnc {

class WorkStore {
 public:
  /// `path`: the file (work_state_path(config)); empty: kept in memory only, never saved.
  /// Holds `initial` until load().
  WorkStore(std::string path, WorkState initial) : path_(std::move(path)), state_(initial) {}

  /// Reads the file (a missing one gives `config`'s default). Throws WorkStateError.
  void load(const MachineConfig& config);

  const WorkState& state() const { return state_; }
  const std::string& path() const { return path_; }

  /// G54..G59.3 (0..8) := `xyz` where given, then saved. On a failed save the state is left as
  /// it was and the error returned.
  std::optional<std::string> set_g5x(int index, const std::optional<double> (&xyz)[kAxes]);

 private:
  std::string path_;
  WorkState state_;
};

/// G54..G59 of `g5x` in the config's form (gcode.work_offsets, what the interpreter reads).
std::array<Vec3, 6> first_six(const WorkOffsets& g5x);

}  // namespace pcnc
