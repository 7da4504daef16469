// machine_runner.hpp — test helper: drives a Machine in-process like the loop does under
// --clock virtual (the ring is refilled before every cycle, so the host is never slow),
// records every cycle, and checks the setpoints against the axis limits.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "loop/machine.hpp"

namespace pcnc::test {

struct CycleRecord {
  MachineState state = MachineState::kIdle;
  std::uint32_t line = 0;
  std::uint64_t seq = 0;  // the block in execution (Status::block_seq)
  Vec3 cmd{}, act{}, ferr{}, truth{};
  double speed = 0.0;
  bool blend = false;  // the setpoint was inside a corner blend's window
};

class MachineRunner {
 public:
  explicit MachineRunner(const MachineConfig& config);

  /// Queues a program (fed to the ring as space frees) and sends kProgramStart.
  void start(const std::vector<Block>& program);
  void send(CommandKind kind, double value = 0.0, int axis = 0, double feed = 0.0);
  /// Host heartbeat seen by the machine.
  void set_host_alive(bool alive) { machine_.set_host_alive(alive); }
  /// Stops feeding the ring (simulates a host that went quiet).
  void set_feeding(bool on) { feeding_ = on; }

  /// One cycle; `hook`, when set, runs after each cycle.
  void cycle();
  /// Cycles until the program is done, a fault, or `max_cycles`. Returns cycles run.
  std::size_t run_until_done(std::size_t max_cycles = 2'000'000);
  /// Cycles while `pred` holds (at most max_cycles).
  std::size_t run_while(const std::function<bool(const Status&)>& pred, std::size_t max_cycles = 2'000'000);
  void run(std::size_t cycles);

  Machine& machine() { return machine_; }
  MotionRing& ring() { return ring_; }
  const Status& status() const { return machine_.status(); }
  const std::vector<CycleRecord>& records() const { return records_; }
  const MachineConfig& config() const { return cfg_; }
  double dt() const { return cfg_.cycle_period_s(); }

  /// First violation of velocity, acceleration or soft limits by the commanded setpoints
  /// over all recorded cycles ("" when none). `accel_scale` scales the allowed acceleration.
  std::string check_setpoint_limits(double accel_scale = 1.0) const;

 private:
  MachineConfig cfg_;
  Machine machine_;
  MotionRing ring_;
  std::vector<Block> program_;
  std::size_t next_ = 0;
  bool feeding_ = true;
  std::uint64_t next_id_ = 1;
  std::vector<CycleRecord> records_;
};

/// configs/desktop-mill.toml with path tolerance 0 (the seed's contouring rule, no smoothing);
/// service_procs.hpp's mill_config() is the config as shipped.
MachineConfig default_machine_config();
/// configs/desktop-5axis.toml loaded as shipped.
MachineConfig five_axis_config();

/// A long straight line along X at `feed` (mm/s), from home: rapid to X1, line to X24, end.
std::vector<Block> long_line(const MachineConfig& config, double feed);

/// Runs until the machine executes source line `line` at `min_speed` or more (or faults).
void run_to_line(MachineRunner& run, std::uint32_t line, double min_speed);

}  // namespace pcnc::test
