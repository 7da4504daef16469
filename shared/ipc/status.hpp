// status.hpp — the snapshot pcnc-rt publishes every cycle for pcnc-host (seqlock-protected).
// Plain trivially copyable values in machine coordinates (mm, mm/s, s).
#pragma once

#include <cstdint>
#include <type_traits>

#include "geometry/vec3.hpp"
#include "ipc/rotary_joints.hpp"

namespace pcnc {

enum class MachineState : std::uint8_t {
  kStarting = 0,      // segment created, loop not yet cycling
  kIdle = 1,          // at rest, ready for a program or a jog
  kRunning = 2,       // executing program blocks
  kPaused = 3,        // feed hold or M00/M01: at rest (or decelerating) on the path, resumable
  kJogging = 4,       // executing a jog
  kStopping = 5,      // decelerating after stop; the ring is flushed at rest
  kFault = 6,         // amplifiers off; fault_* says why; needs reset
  kEstop = 7,         // amplifiers off by e-stop; needs reset
  kHostLost = 8,      // host heartbeat lost while running: stopped on the path, holding
};

enum class FaultCode : std::uint8_t {
  kNone = 0,
  kFollowingError = 1,  // |following error| exceeded the configured limit on fault_axis
  kSoftLimit = 2,       // a setpoint would have left the travel on fault_axis
  kBadBlock = 3,        // a block failed validation (corrupt or impossible)
  kSequence = 4,        // a block arrived out of sequence
};

/// How the last probing block ended (Status::probe_outcome, docs/probe.md).
enum class ProbeOutcome : std::uint8_t {
  kNone = 0,
  kContact = 1,           // the probe changed state: stopped within the overtravel, position latched
  kNoContact = 2,         // the move reached its end without the change
  kAlreadyTriggered = 3,  // the probe was already in the state sought when the move began: no motion
};

/// Timing figures of the cycle, microseconds, over a sliding window or the whole run.
struct TimingStats {
  double wake_min_us = 0.0, wake_mean_us = 0.0, wake_p99_us = 0.0, wake_max_us = 0.0;
  double compute_min_us = 0.0, compute_mean_us = 0.0, compute_p99_us = 0.0, compute_max_us = 0.0;
  std::uint64_t overruns = 0;  // cycles that started later than one period after their deadline
};

struct Status {
  MachineState state = MachineState::kStarting;
  FaultCode fault = FaultCode::kNone;
  std::uint8_t fault_axis = 0;
  std::uint8_t contouring = 0;    // contouring mode of the block in execution
  std::uint8_t ring_fill = 0;     // blocks waiting in the ring
  std::uint8_t clock_virtual = 0; // 1: --clock virtual
  std::uint8_t program_active = 0;  // between kProgramStart and kEnd/stop
  std::uint8_t program_done = 0;    // the last program reached its End block
  std::uint8_t trace_failed = 0;    // 1: the rt's trace file could not be written (disk full, ...): incomplete
  std::uint32_t line = 0;           // source line of the block in execution
  std::uint32_t fault_line = 0;
  double fault_value = 0.0;         // e.g. the following error that tripped, mm

  std::uint64_t cycle = 0;          // cycles since start
  double time_s = 0.0;              // machine time since start (cycle * period)
  double program_time_s = 0.0;      // machine time since the current/last program started
  std::uint64_t block_seq = 0;      // seq of the block in execution
  std::uint64_t blocks_done = 0;    // blocks completed in this program
  std::uint64_t underruns = 0;      // cycles that wanted a block and found the ring empty
  std::uint64_t junction_stops = 0; // program junctions passed at rest
  std::uint64_t junction_flows = 0; // program junctions passed without stopping
  std::uint64_t last_command_id = 0;

  Vec3 commanded{};       // setpoint, mm
  Vec3 actual{};          // encoder position, mm
  Vec3 velocity{};        // commanded axis velocity, mm/s
  Vec3 following_error{}; // commanded - actual, mm
  Vec3 max_following_error{};  // max |ferr| per axis since program start, mm
  Vec3 following_error_sq_sum{};  // sum of ferr² per axis over the program's cycles, mm² (RMS = sqrt(sum/n))
  std::uint64_t program_cycles = 0;  // cycles summed in following_error_sq_sum / contour_error_sq_sum
  double contour_error = 0.0;       // distance of the measured position from the programmed path, mm
  double max_contour_error = 0.0;   // its maximum since program start (feed moves only), mm
  double contour_error_sq_sum = 0.0;
  double path_speed = 0.0;     // commanded path speed, mm/s
  double feed_override = 1.0;  // 0.0 .. 2.0

  TimingStats timing{};

  // The touch probe (docs/probe.md): its input this cycle, and the result of the last probing
  // block (a new result when probe_count grows).
  std::uint8_t probe_input = 0;    // 1: the stylus is deflected (triggered)
  ProbeOutcome probe_outcome = ProbeOutcome::kNone;
  std::uint32_t probe_line = 0;    // source line of that block
  std::uint64_t probe_count = 0;   // probing blocks finished since pcnc-rt started
  std::uint64_t probe_seq = 0;     // seq of that block
  Vec3 probe_latched{};            // commanded ball centre in the cycle the input changed, mm
  Vec3 probe_stop{};               // where the probing move came to rest, mm

  // Rotary joints (A B C by index, rad; joints the machine does not declare stay 0).
  RotaryMask rotary_mask = 0;      // the machine's joints, bit per joint
  std::uint8_t tcp = 0;            // the block in execution has tool-centre-point control on
  std::uint8_t pad_rot_[6]{};
  Rot3 rot_commanded{};
  Rot3 rot_actual{};
  Rot3 rot_velocity{};
  Rot3 rot_following_error{};
  Rot3 rot_max_following_error{};
};

static_assert(std::is_trivially_copyable_v<Status>, "Status lives in shared memory");

const char* to_string(MachineState state);
const char* to_string(FaultCode code);
const char* to_string(ProbeOutcome outcome);

}  // namespace pcnc
