// work_state.hpp — the persistent work-coordinate state, as LinuxCNC keeps it in its var file:
// the nine coordinate systems G54..G59.3 (program zero in machine coordinates), which one is
// selected, the G92 offset and whether it is applied, and the G28/G30 stored positions.
// The config's gcode.g54..g59 are only its defaults: once the file exists, the file wins.
//
// The file is JSON a person can read and edit (docs/protocol.md, "Work-coordinate state"):
//
//   {"version": 1, "units": "mm", "active": "G54",
//    "G54": {"x": 12.5, "y": 12.5, "z": 25.0}, ..., "G59.3": {...},
//    "G92": {...}, "G92_applied": false, "G28": {...}, "G30": {...},
//    "tool": {"number": 3, "offset_applied": true, "offset": {"x": 0, "y": 0, "z": 41.2}}}
//
// The tool in the spindle and its length offset (G43) persist across programs as in LinuxCNC
// (M2 does not cancel G43). "tool" may be absent (files written before it existed: no tool,
// no offset); every other key is required and no other is accepted; every value is finite and within ±1e6 mm.
// A file that breaks a rule is refused (WorkStateError naming the file and the key), never
// read as zeros: a wrong program zero crashes the tool into the part.
//
// May include: the standard library, POSIX, config.hpp, runtime_paths.hpp, atomic_file.hpp.
#pragma once

#include <array>
#include <string>
#include <string_view>

#include "config/config.hpp"

namespace pcnc {

constexpr int kWorkSystems = 9;                  // G54, G55, ..., G59, G59.1, G59.2, G59.3 (P1..P9)
constexpr double kWorkStateLimitMm = 1e6;        // |value| allowed in the file
constexpr int kWorkStateVersion = 1;

using WorkOffsets = std::array<Vec3, kWorkSystems>;  // G54..G59.3

struct WorkState {
  WorkOffsets g5x{};                     // G54..G59.3, mm: program zero in machine coordinates
  int active = 0;                        // 0..8: the selected system (G54 = 0)
  Vec3 g92{};                            // G92/G52 axis offset, mm
  bool g92_applied = false;              // LinuxCNC #5210
  Vec3 g28{}, g30{};                     // G28/G30 stored positions, machine mm
  int tool = 0;                          // in the spindle (M6, M61); 0: none
  bool tool_offset_applied = false;      // G43/G43.1/G43.2 in effect (G49: off)
  Vec3 tool_offset{};                    // the tool length offset in effect, mm

  bool operator==(const WorkState&) const = default;
};

/// A refused work-state file (or one that cannot be written): the message names the file.
struct WorkStateError : ConfigError {
  using ConfigError::ConfigError;
};

/// "G54".."G59", "G59.1".."G59.3" for 0..8.
std::string work_system_name(int index);
/// The inverse, case-insensitive ("g59.1" -> 6); -1 for anything else.
int parse_work_system_name(std::string_view name);

/// g5x[0..5] from config.gcode.work_offsets (G54..G59), G59.1..G59.3 zero, G54 active, no
/// G92, G28 = G30 = each axis's home_mm.
WorkState default_work_state(const MachineConfig& config);
/// state_dir(config) + "/work_state.json" (runtime_paths.hpp).
std::string work_state_path(const MachineConfig& config);

/// The JSON text of `state` (what save_work_state writes).
std::string format_work_state(const WorkState& state);
/// Parses the JSON text; `origin` names it in messages. Throws WorkStateError.
WorkState parse_work_state(const std::string& text, const std::string& origin);

/// Reads `path`: a missing file gives default_work_state(config); a symlink, a non-regular
/// file, an unreadable or corrupt one throws WorkStateError naming the file and what is wrong.
WorkState load_work_state(const MachineConfig& config, const std::string& path);
/// Writes atomically (atomic_file.hpp), mode 0600, after creating its directory private
/// (ensure_private_dir, 0700). `path` must be absolute. Throws WorkStateError (the old file is
/// then left as it was).
void save_work_state(const std::string& path, const WorkState& state);

}  // namespace pcnc
