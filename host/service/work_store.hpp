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
  /// G10 L20's meaning for one axis of the active system: its offset := `machine` (the
  /// position now, machine mm) - the applied G92 offset - the tool length offset in effect
  /// (G43) - `value`, so that the tool tip reads `value` in work coordinates; then saved.
  /// Same failure rule.
  std::optional<std::string> touch_off(int axis, double value, const Vec3& machine);
  /// The whole state (what a program or MDI left: G10, G92, G28.1...), then saved. Same rule.
  std::optional<std::string> replace(const WorkState& next);

 private:
  std::string path_;
  WorkState state_;
};

/// `current` with what a job changed from `before` to `after`, part by part (each of the nine
/// systems, the selection, G92 with its flag, G28, G30, the tool with its offset): a part the job left alone keeps
/// `current`'s value, which set_offset may have changed while the job ran.
WorkState merge_work_change(const WorkState& current, const WorkState& before, const WorkState& after);

/// Work coordinates of a machine position: machine - the active G5x - the applied G92 - the
/// tool length offset in effect (what the program would read as its position).
Vec3 work_position(const WorkState& w, const Vec3& machine);

/// G54..G59 of `g5x` in the config's form (gcode.work_offsets, what the interpreter reads).
std::array<Vec3, 6> first_six(const WorkOffsets& g5x);

}  // namespace pcnc
