// probe_sync.hpp — a program's blocks for a run, through its probing moves (docs/probe.md).
//
// A probing move (G38.2-G38.5) ends where the probe stopped, so nothing after it can be made
// before its result is known. The stream ends at each such move (ProbeResults::stop_at_unknown);
// once everything before it is sent, resume() waits for the rt's result (Status::probe_*),
// checks the rest of the program again with it (check_program: a G38.2 without contact, or the
// moves after it leaving the travel, are errors with file:line:col before anything moves), then
// interprets the program again from its start with every result known so far and hands on the
// blocks after the probing move: the interpretation is deterministic, so the blocks before it
// are the ones already sent (their count is skipped), and the message comments already shown
// are not shown twice. Each result goes to the probe log the program opened with
// (PROBEOPEN name), in LinuxCNC's format, the name relative to the program's folder.
//
// May include: rt_link.hpp, gcode/program.hpp, shared/.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <set>
#include <string>

#include "gcode/program.hpp"
#include "service/rt_link.hpp"

namespace pcnc {

class ProbeSync {
 public:
  ProbeSync(RtLink& link, const MachineConfig& config, std::string path, const JobOptions& options,
            const Transform& transform);
  /// An MDI: the program is `text`, named `name` in messages (a probe log's relative name is
  /// then taken from the service's working directory).
  struct FromText {};
  ProbeSync(RtLink& link, const MachineConfig& config, FromText, std::string text, std::string name,
            const JobOptions& options, const Transform& transform);

  /// The next block to send; false at the end of the program or at a sync point.
  bool next(Block& out);
  /// After next() returned false and everything was sent (see BlockSource::resume).
  std::string resume(const std::atomic<bool>& interrupt, bool& more);
  const BlockStream& stream() const { return *stream_; }
  /// Called with all results known each time one arrives (the service's journal).
  void set_on_result(std::function<void(const ProbeResults&)> fn) { on_result_ = std::move(fn); }
  /// A resumed run: the blocks up to program block `through` are not handed out again, and the
  /// rt numbers this run's blocks from 1, so program seq = rt seq + `seq_base`. Its probe logs
  /// are appended to (the interrupted run wrote their first lines).
  void resume_after(std::uint64_t through, std::uint64_t seq_base) {
    skip_through_ = through;
    seq_base_ = seq_base;
    resumed_ = true;
  }
  /// The results so far (the journal's, for a resumed program).
  const ProbeResults& results() const { return *results_; }

 private:
  void open_stream();
  std::string write_log(const ProbeResult& r);

  RtLink& link_;
  const MachineConfig& config_;
  std::string path_;
  bool from_text_ = false;
  std::string text_;  // FromText: the program
  JobOptions options_;
  Transform transform_;
  std::shared_ptr<ProbeResults> results_;
  std::unique_ptr<BlockStream> stream_;
  std::uint64_t skip_through_ = 0;  // blocks with seq up to this were sent by an earlier stream
  std::uint64_t last_seq_ = 0;      // seq of the last block handed out
  std::uint64_t messages_shown_ = 0;
  std::uint64_t messages_seen_ = 0;  // by the current stream
  std::uint64_t probe_count_at_start_ = 0;
  std::set<std::string> logs_written_;  // probe logs this run has created
  std::uint64_t seq_base_ = 0;
  bool resumed_ = false;
  std::function<void(const ProbeResults&)> on_result_;
};

/// One line of LinuxCNC's probe log for `r` in the log that `stream` has open (PROBEOPEN; none:
/// nothing written), a new file when `truncate`, else appended. A relative name is taken from
/// `program_path`'s folder (empty: the working directory). Returns "" or why it failed.
std::string write_probe_log(const BlockStream& stream, const std::string& program_path, const ProbeResult& r,
                            bool truncate);

}  // namespace pcnc
