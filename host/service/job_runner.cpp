// job_runner.cpp — feeding a program to the rt and following it to its end.
#include "service/job_runner.hpp"

#include <chrono>
#include <deque>
#include <optional>
#include <utility>

#include "gcode/planned_time.hpp"
#include "service/probe_sync.hpp"
#include <thread>

namespace pcnc {

namespace {
bool faulted(const Status& s) {
  return s.state == MachineState::kFault || s.state == MachineState::kEstop || s.state == MachineState::kHostLost;
}
std::string fault_text(const Status& s) {
  std::string m = std::string("machine entered ") + to_string(s.state);
  if (s.fault != FaultCode::kNone) {
    m += ": " + std::string(to_string(s.fault)) + " on axis " + axis_name(s.fault_axis) + " at line " +
         std::to_string(s.fault_line) + " (value " + std::to_string(s.fault_value) + ")";
  }
  return m;
}
}  // namespace

const char* to_string(ProgramPauses p) {
  switch (p) {
    case ProgramPauses::kWait: return "wait";
    case ProgramPauses::kContinue: return "continue";
    case ProgramPauses::kAsk: return "ask";
  }
  return "?";
}

JobRunner::JobRunner(RtLink& link, const MachineConfig& config) : link_(link), config_(config) {}

bool JobRunner::wait_until_state(const std::function<bool(const Status&)>& done, const std::atomic<bool>& interrupt,
                                 double timeout_s, Status& last) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  // Status follow-up, not the ring path: every 2 ms; under the virtual clock every 100 µs,
  // since the whole end of a replayed program (the ring's last blocks) takes a few ms of wall
  // time and the host waits for it before it reports.
  const auto period = last.clock_virtual ? std::chrono::microseconds(100) : std::chrono::microseconds(2000);
  for (;;) {
    last = link_.status();
    if (done(last)) return true;
    if (interrupt.load() || !link_.rt_alive() || std::chrono::steady_clock::now() >= deadline) return false;
    std::this_thread::sleep_for(period);
  }
}

JobResult JobRunner::run(const std::string& path, const JobOptions& options, const CheckResult& check,
                         const std::atomic<bool>& interrupt, const std::function<void(const JobProgress&)>& progress) {
  ProbeSync sync(link_, config_, path, options, check.transform);
  if (on_probe_result_) sync.set_on_result(on_probe_result_);
  BlockSource source;
  source.next = [&](Block& b) { return sync.next(b); };
  source.progress = [&] {
    const BlockStream& s = sync.stream();
    return JobProgress{s.lines_read(), s.bytes_read(), s.total_bytes(), Status{}};
  };
  source.resume = [&](const std::atomic<bool>& stop, bool& more) { return sync.resume(stop, more); };
  work_after_.reset();
  JobResult r = run_source(source, options.contouring.value_or(config_.motion.contouring_default), interrupt, progress);
  if (r.end == JobEnd::kCompleted) work_after_ = sync.stream().work_state();
  return r;
}

JobResult JobRunner::run_source(const BlockSource& source, bool contouring, const std::atomic<bool>& interrupt,
                                const std::function<void(const JobProgress&)>& progress) {
  JobResult result;
  const auto t0 = std::chrono::steady_clock::now();
  auto finish = [&](JobEnd end, std::string message) {
    result.end = end;
    result.message = std::move(message);
    result.final_status = link_.status();
    result.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return result;
  };

  Status st = link_.status();
  if (st.state != MachineState::kIdle) {
    return finish(JobEnd::kFault, std::string("machine is ") + to_string(st.state) + ", not IDLE: cannot start a program");
  }

  if (st.clock_virtual) {
    // Blocks a stopped program left in the replay stage go through the rt's ring, which drops
    // them until the next start: start only once they are gone (microseconds), so that none
    // can be taken for the new program's.
    auto& shm = link_.shm();
    for (int i = 0; i < 10000 && !(shm.stage.empty() && shm.motion.empty()); ++i) {
      shm.block_published.notify();
      std::this_thread::sleep_for(std::chrono::microseconds(100));
    }
  }

  // Waiting for a free slot: spin 20 µs, then sleep; under the virtual clock nap until the
  // rt has drained the replay stage to its low-water mark (see RingFeeder).
  RingFeeder feeder(link_, 0.02, 20000);
  feeder.set_staging(staging_);
  feeder.set_via_stage(st.clock_virtual);  // the rt fills its ring from the replay stage
  Command start;
  start.kind = CommandKind::kProgramStart;
  start.value = contouring ? 1.0 : 0.0;
  const std::uint64_t start_id = link_.send(start);
  if (start_id == 0) return finish(JobEnd::kFault, "the rt's mailbox is full");
  // Blocks follow the start command at once: the rt takes the command before it looks at the
  // ring in the same cycle, so the program's first cycles never find the ring empty (waiting
  // for the command to be taken first cost a few underruns under the real clock).
  bool started = false;
  auto note_started = [&] {
    if (started || link_.status().last_command_id < start_id) return;
    started = true;
    if (on_started_) on_started_();
  };

  // The planned time of the blocks done: the running sum of each block's planned time as it
  // is sent, kept for the blocks in flight (ring and staging: a few dozen) until the rt's
  // blocks_done passes them.
  std::deque<std::pair<std::uint64_t, double>> in_flight;  // (seq, planned time up to and including it)
  std::uint64_t filled = 0;
  double planned_sent = 0.0, planned_done = 0.0;
  // The program's pauses (M0/M1): noted for the report; under kContinue sent as a dwell of
  // 0 s (the same stop at rest, and the machine goes on at once: machine time stays
  // deterministic); under kAsk remembered by sequence number until the rt stands there.
  std::deque<std::pair<std::uint64_t, PauseAt>> pauses_ahead;
  auto note_pause = [&](Block& b) {
    if (b.kind != BlockKind::kPause || pauses_ == ProgramPauses::kWait) return;
    const PauseAt at{b.line, b.optional_stop != 0};
    ++result.pauses;
    result.pauses_mode = to_string(pauses_);
    if (result.pause_lines.size() < JobResult::kMaxPauseLines) result.pause_lines.push_back(at.line);
    if (pauses_ == ProgramPauses::kContinue) {
      b.kind = BlockKind::kDwell;
      b.dwell_s = 0.0;
      b.optional_stop = 0;
    } else {
      pauses_ahead.emplace_back(filled + 1, at);  // the seq the feeder gives it
    }
  };
  auto next_block = [&](Block& b) {
    if (!source.next(b)) return false;
    note_pause(b);
    planned_sent += planned_time_s(b);
    in_flight.emplace_back(++filled, planned_sent);
    return true;
  };
  auto done_until = [&](std::uint64_t blocks_done) {
    while (!in_flight.empty() && in_flight.front().first <= blocks_done) {
      planned_done = in_flight.front().second;
      in_flight.pop_front();
    }
    return planned_done;
  };

  auto last_progress = std::chrono::steady_clock::now();
  auto report_progress = [&] {
    if (!progress) return;
    const auto now = std::chrono::steady_clock::now();
    if (now - last_progress < std::chrono::milliseconds(100)) return;
    last_progress = now;
    JobProgress p = source.progress ? source.progress() : JobProgress{};
    p.status = link_.status();
    p.planned_done_s = done_until(p.status.blocks_done);
    progress(p);
  };

  // kAsk: when the rt stands at one of the program's pauses, ask; resume, or stop the program
  // there. Checked while the feeder waits for a slot and while the end is awaited.
  std::atomic<bool> halt{false};  // the interrupt, or a pause the ask function declined
  std::optional<PauseAt> declined;
  auto answer_pause = [&] {
    if (interrupt.load()) halt = true;
    if (pauses_ahead.empty() || halt.load()) return;
    const Status s = link_.status();
    while (!pauses_ahead.empty() && pauses_ahead.front().first < s.block_seq) pauses_ahead.pop_front();
    if (pauses_ahead.empty() || s.state != MachineState::kPaused || s.block_seq != pauses_ahead.front().first) return;
    const PauseAt at = pauses_ahead.front().second;
    pauses_ahead.pop_front();
    if (ask_ && ask_(at) && !interrupt.load()) {
      Command resume;
      resume.kind = CommandKind::kResume;
      link_.send(resume);
    } else {
      declined = at;
      halt = true;
    }
  };
  feeder.set_while_waiting(answer_pause);
  auto stop_here = [&](JobEnd end, std::string why) {  // a controlled stop along the path, then the end
    Command stop;
    stop.kind = CommandKind::kStop;
    link_.send(stop);
    wait_until_state([&](const Status& s) { return s.state != MachineState::kStopping && s.state != MachineState::kRunning; },
                     std::atomic<bool>{false}, 10.0, st);
    return finish(end, std::move(why));
  };
  auto declined_text = [&] {
    return std::string("stopped at the ") + (declined->optional ? "M1" : "M0") + " on line " + std::to_string(declined->line) +
           ": the operator did not resume";
  };

  for (;;) {
    const FeedResult r = feeder.push(next_block, &halt);
    if (r == FeedResult::kEndOfInput && source.resume && !interrupt.load()) {
      bool more = false;
      const std::string why = source.resume(interrupt, more);
      if (!why.empty()) {  // e.g. G38.2 without contact: the program ends here
        result.blocks_sent = feeder.pushed();
        return stop_here(JobEnd::kStopped, why);
      }
      if (more) {
        feeder.resume_input();
        continue;
      }
    }
    if (r == FeedResult::kEndOfInput) break;
    if (r == FeedResult::kRtLost) return finish(JobEnd::kRtLost, "pcnc-rt stopped responding");
    if (r == FeedResult::kAborted || interrupt.load() || halt.load()) break;
    note_started();
    report_progress();
    // A fault flushes the ring on the rt side; stop feeding at once.
    if ((feeder.pushed() & 63) == 0 && faulted(link_.status())) break;
  }
  result.blocks_sent = feeder.pushed();
  result.lines_read = source.progress ? source.progress().lines_read : 0;
  result.refill_latency = feeder.refill_latency();

  for (;;) {
    const bool ended = wait_until_state(
        [&](const Status& s) {
          return s.last_command_id >= start_id &&  // not the previous program's end
                 (s.program_done || faulted(s) || (!s.program_active && s.state == MachineState::kIdle));
        },
        interrupt, 0.1, st);
    note_started();
    if (ended) break;
    answer_pause();
    if (interrupt.load()) return stop_here(JobEnd::kInterrupted, "stopped along the path");
    if (declined) return stop_here(JobEnd::kStopped, declined_text());
    if (!link_.rt_alive()) return finish(JobEnd::kRtLost, "pcnc-rt stopped responding");
    report_progress();
  }
  if (faulted(st)) return finish(JobEnd::kFault, fault_text(st));
  if (!st.program_done) {
    return finish(JobEnd::kStopped, st.trace_failed ? "stopped by pcnc-rt before its end: its trace file could not be written "
                                                      "(process.on_trace_failure = \"stop\")"
                                                    : "the program was stopped before its end");
  }
  return finish(JobEnd::kCompleted, "");
}

}  // namespace pcnc
