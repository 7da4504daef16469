// job_runner.hpp — runs one checked program on the machine: tells the rt a program starts,
// streams its blocks through the ring feeder, waits for the end (or a fault, a lost rt, or
// an interrupt), and collects what the run report needs.
//
// May include: ring_feeder.hpp, rt_link.hpp, gcode/program.hpp, report/job_result.hpp, shared/.
#pragma once

#include <atomic>
#include <functional>
#include <optional>
#include <string>

#include "gcode/program.hpp"
#include "report/job_result.hpp"
#include "service/ring_feeder.hpp"
#include "service/rt_link.hpp"

namespace pcnc {

struct JobProgress {
  std::uint64_t lines_read = 0;
  std::uint64_t bytes_read = 0;
  std::uint64_t total_bytes = 0;
  Status status{};
  double planned_done_s = 0.0;  // planned time (gcode/planned_time.hpp) of the blocks the rt has done
};

/// Where a job's blocks come from: normally a BlockStream over the checked file; the
/// service also resumes a program from the middle of a block (job_control.cpp).
struct BlockSource {
  std::function<bool(Block&)> next;  // false after the last block (the End block included)
  std::function<JobProgress()> progress;  // lines/bytes so far (status is filled in by the runner)
  // Called when next() returned false with everything sent (optional): a source that stopped
  // at a sync point (a probing move, docs/probe.md) waits for what it needs and says whether it
  // has more ("" and true), has ended ("" and false), or cannot go on (the reason).
  std::function<std::string(const std::atomic<bool>& interrupt, bool& more)> resume;
};

/// What the program's M0/M1 (and a tool change with gcode.pause_on_tool_change) do in a run.
enum class ProgramPauses {
  kWait,      // the rt waits at rest for a resume command (the service: the operator resumes over the socket)
  kContinue,  // the block is sent as a dwell of 0 s: the machine comes to rest there and goes on (pcnc run, no operator)
  kAsk,       // the rt waits at rest; the runner calls the ask function, which says whether to resume or stop
};
const char* to_string(ProgramPauses p);

/// A program pause the rt reached: its source line, and whether it is an M1.
struct PauseAt {
  std::uint32_t line = 0;
  bool optional = false;
};

class JobRunner {
 public:
  JobRunner(RtLink& link, const MachineConfig& config);
  /// Runs `path` (already checked: `check` is its CheckResult). `interrupt` stops the run
  /// with a controlled stop. `progress` is called now and then from this thread.
  /// After run() completed the program: the offsets and stored positions as it left them (for
  /// the state file); nothing otherwise.
  const std::optional<WorkState>& work_after() const { return work_after_; }

  JobResult run(const std::string& path, const JobOptions& options, const CheckResult& check,
                const std::atomic<bool>& interrupt, const std::function<void(const JobProgress&)>& progress = {});
  /// The same over any block source; `contouring` is the mode at program start.
  JobResult run_source(const BlockSource& source, bool contouring, const std::atomic<bool>& interrupt,
                       const std::function<void(const JobProgress&)>& progress = {});
  /// The ring feeder's staging (ring_feeder.hpp); off for a streamed program.
  void set_staging(bool on) { staging_ = on; }
  /// Called with every probe result of run()'s program so far, as each arrives (docs/probe.md).
  void set_on_probe_result(std::function<void(const ProbeResults&)> fn) { on_probe_result_ = std::move(fn); }
  /// What M0/M1 do (default kWait). kAsk: `ask` is called from this thread while the rt waits
  /// at rest at the pause; it returns true to resume, false to stop the program there. It
  /// should return false when the run's interrupt is raised.
  void set_program_pauses(ProgramPauses mode, std::function<bool(const PauseAt&)> ask = {}) {
    pauses_ = mode;
    ask_ = std::move(ask);
  }
  /// Called once the rt has taken the program start (the program is under way).
  void set_on_started(std::function<void()> fn) { on_started_ = std::move(fn); }

 private:
  std::optional<WorkState> work_after_;
  bool wait_until_state(const std::function<bool(const Status&)>& done, const std::atomic<bool>& interrupt,
                        double timeout_s, Status& last);
  RtLink& link_;
  const MachineConfig& config_;
  std::function<void()> on_started_;
  std::function<void(const ProbeResults&)> on_probe_result_;
  bool staging_ = true;
  ProgramPauses pauses_ = ProgramPauses::kWait;
  std::function<bool(const PauseAt&)> ask_;
};

}  // namespace pcnc
