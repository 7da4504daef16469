// job_control.hpp — the life cycle of the service's jobs: at most one program at a time, run
// in a worker thread. A `run` is checked (preflight) and recorded in the journal before it
// starts; a `resume` after a lost host re-streams the journal's program from the block where
// the rt held the machine. The job runner (job_runner.hpp) feeds the blocks; this part keeps
// the job's record for the status object (the job under way, the last job), sends the
// delayed reply of run and resume, the program_started and program_end events, and removes
// the journal when a job ends (or is abandoned) with the machine no longer HOST_LOST.
//
// Threads: run(), resume(), interrupt(), abandon_interrupted() and describe() are called on
// the loop thread; the worker only reports back through the notices it is given.
//
// May include: outcome.hpp, rpc.hpp, job_runner.hpp, job_journal.hpp, resume.hpp, work_store.hpp,
// rt_link.hpp, gcode/program.hpp, shared/.
#pragma once

#include <atomic>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "config/config.hpp"
#include "config/work_state.hpp"
#include "gcode/program.hpp"
#include "service/control_server.hpp"
#include "service/job_journal.hpp"
#include "service/job_runner.hpp"
#include "service/outcome.hpp"
#include "service/rt_link.hpp"

namespace pcnc {

struct JobNotices {
  // Called from the job worker; the service delivers both on its loop thread.
  std::function<void(ClientId client, rpc::json id, Outcome outcome)> reply;
  std::function<void(rpc::json event)> event;
  // A program or MDI ran to its end: the work state it started with and the one it left (G10,
  // G92, G28.1...), for the service's WorkStore (merge_work_change). `applied` is called on
  // the loop thread once the store holds it: the job's end is not published before that, so
  // a client that sees the job over also sees its offsets. May be empty.
  std::function<void(WorkState before, WorkState after, std::function<void()> applied)> work_after;
};

class JobControl {
 public:
  JobControl(std::string journal_path, JobNotices notices);
  ~JobControl();  // interrupts a job still running and waits for its worker
  JobControl(const JobControl&) = delete;
  JobControl& operator=(const JobControl&) = delete;

  /// A job is being checked, started, run or resumed.
  bool active() const { return active_.load(); }
  /// The worker stops feeding; the rt decelerates on the path (or the rt was told to stop).
  /// A stream's feed is closed, so that its reader stops waiting for lines.
  void interrupt();
  /// Waits for the worker to end (after interrupt(), at shutdown).
  void join();

  /// The `run` method once its parameters are checked (`file` absolute): refused while a
  /// job is active or the machine is not IDLE; else the job starts with a copy of `config`
  /// whose G54..G59 are `work`'s (set_offset may change the service's meanwhile), the
  /// journal records all of `work`'s G54..G59.3, and the reply comes later.
  Outcome run(ClientId client, const rpc::json& id, const rpc::RunParams& params, std::shared_ptr<RtLink> link,
              const Status& st, const MachineConfig& config, const WorkState& work);
  /// The `mdi` method: `text` is a small program (work offsets `work`, starting where the
  /// machine stands, an implicit end), checked whole before anything moves; refused like run.
  /// The reply comes once it has started (or with the check's errors, line:col, code 3).
  Outcome mdi(ClientId client, const rpc::json& id, const std::string& text, std::shared_ptr<RtLink> link, const Status& st,
              const MachineConfig& config, const WorkState& work);
  /// The `stream_open` method (the grbl port, stream_job.cpp): a program whose lines arrive
  /// while it runs (stream_lines), each checked as it passes; `check` runs them through every
  /// check without motion ($C). Refused like run. The reply comes at once (the lines follow
  /// it); then `stream` events say how many lines are done, and the error that ended it.
  Outcome stream_open(ClientId client, const rpc::json& id, bool check, std::shared_ptr<RtLink> link, const Status& st,
                      const MachineConfig& config, const WorkState& work);
  /// `stream_lines`: appends whole lines to the open stream (refused when none is open).
  Outcome stream_lines(const std::string& text);
  /// `stream_close`: the end of the stream's input; its program ends after the last line.
  Outcome stream_close();

  /// The `resume` method in HOST_LOST: continues the journal's program with the work offsets
  /// the journal recorded (reply later).
  Outcome resume(ClientId client, const rpc::json& id, std::shared_ptr<RtLink> link, const Status& st,
                 const MachineConfig& config);
  /// The program interrupted by a lost host is abandoned (stop or reset in HOST_LOST).
  void abandon_interrupted();

  /// Fills the status object's "job", "last_job" and "resume" (what `resume` would continue,
  /// when the machine `st` is HOST_LOST).
  void describe(rpc::json& status, const std::optional<Status>& st) const;

 private:
  bool start_worker(ClientId client, const rpc::json& id, std::function<void()> fn);
  void job_reply(ClientId client, const rpc::json& id, Outcome outcome);  // the job's one reply
  void end_job(const rpc::json* last);
  void run_job(ClientId client, const rpc::json& id, const rpc::RunParams& rp, std::shared_ptr<RtLink> l,
               const MachineConfig& cfg, const WorkState& ws, const Vec3& start);
  void mdi_job(ClientId client, const rpc::json& id, const std::string& text, std::shared_ptr<RtLink> l,
               const MachineConfig& cfg, const WorkState& ws, const Vec3& start);
  Outcome refuse_start(const Status& st) const;
  void stream_job(ClientId client, const rpc::json& id, bool check, std::shared_ptr<LineFeed> feed, std::uint64_t n,
                  std::shared_ptr<RtLink> l, const MachineConfig& cfg, const WorkState& ws, const Vec3& start);
  void resume_job(ClientId client, const rpc::json& id, std::shared_ptr<RtLink> l, const MachineConfig& cfg, JobJournal jj);
  void follow_job(ClientId client, const rpc::json& id, std::shared_ptr<RtLink> l, const MachineConfig& cfg,
                  rpc::json started, const std::string& file, const std::function<JobResult(JobRunner&)>& body,
                  const WorkState* work_before = nullptr,  // null: what the job leaves is not kept (resume)
                  const std::function<std::optional<WorkState>(const JobRunner&)>& work_after = {});
  std::function<void(const JobProgress&)> progress_fn(double planned_total_s = 0.0);
  CheckProgressHandler check_progress_fn();
  static constexpr std::uint64_t kLocateReportEvery = 256;  // blocks between the locate pass's reports
  std::function<bool()> locate_progress_fn(const BlockStream& stream);
  void journal_failed(const std::string& why);
  void journal_probes(JobJournal& jj, const ProbeResults& r);  // docs/probe.md
  void journal_ok();

  const std::string journal_;
  JobNotices notices_;
  std::thread worker_;
  std::atomic<bool> active_{false};
  std::atomic<bool> interrupt_{false};
  std::atomic<bool> replied_{false};  // the job's request has its reply
  mutable std::mutex mutex_;  // guards info_, last_, journal_error_
  rpc::json info_ = rpc::json::object();
  rpc::json last_ = nullptr;
  std::string journal_error_;  // the last journal write failure, until one succeeds
  std::shared_ptr<LineFeed> feed_;  // the open stream's input (guarded by mutex_)
  std::uint64_t streams_ = 0;       // streams opened (each stream's number in its events)
  std::atomic<std::uint64_t> stream_blocks_{0};  // blocks the open stream handed to the ring feeder
};

}  // namespace pcnc
