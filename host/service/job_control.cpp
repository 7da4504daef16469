// job_control.cpp — run and resume in a worker thread, the job record, the journal (see
// job_control.hpp).
#include "service/job_control.hpp"

#include <spdlog/spdlog.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <future>
#include <memory>

#include "service/probe_sync.hpp"
#include "service/resume.hpp"
#include "service/sha256.hpp"
#include "service/work_store.hpp"

namespace pcnc {

using rpc::json;

namespace {
json diagnostics_json(const CheckResult& check, Diagnostic::Severity severity) {
  json list = json::array();
  for (const auto& d : check.diagnostics) {
    if (d.severity == severity) list.push_back(format_diagnostic(d));
  }
  return list;
}
}  // namespace

JobControl::JobControl(std::string journal_path, JobNotices notices)
    : journal_(std::move(journal_path)), notices_(std::move(notices)) {}

JobControl::~JobControl() {
  interrupt();
  join();
}

void JobControl::interrupt() {
  interrupt_ = true;
  std::lock_guard<std::mutex> lock(mutex_);
  if (feed_) feed_->close();
}

void JobControl::join() {
  if (worker_.joinable()) worker_.join();
}

bool JobControl::start_worker(ClientId client, const json& id, std::function<void()> fn) {
  if (active_.load()) return false;
  if (worker_.joinable()) worker_.join();
  active_ = true;
  interrupt_ = false;
  replied_ = false;
  worker_ = std::thread([this, client, id, fn = std::move(fn)] {
    // Nothing the job meets (a program, the file system, the rt) may end the host: an
    // exception ends the job, is logged and becomes the reply (when none was sent yet) and the
    // last job's record.
    std::string failure;
    try {
      fn();
    } catch (const std::exception& e) {
      failure = e.what();
    } catch (...) {
      failure = "unknown exception";
    }
    if (!failure.empty()) {
      spdlog::error("job worker: {}", failure);
      const json last = {{"end", "internal error"}, {"message", "the job ended on an internal error: " + failure}};
      if (!replied_.load()) job_reply(client, id, Outcome::fail(rpc::Error{rpc::kInternalError, last["message"].get<std::string>(), nullptr}));
      end_job(&last);
      json ev = last;
      ev["event"] = "program_end";
      notices_.event(ev);
    }
    active_ = false;  // after an exception; normally end_job() already did
  });
  return true;
}

void JobControl::job_reply(ClientId client, const json& id, Outcome outcome) {
  if (replied_.exchange(true)) return;  // one reply per request (a stream has had its own)
  notices_.reply(client, id, std::move(outcome));
}

// The job is over as far as any client can tell: its record (the last job, when one ran)
// and "not active" change together under the mutex, before any reply or event says so, so
// that a client's next run is never refused as "already running". A new worker may start
// at once: start_worker() joins this thread first.
void JobControl::end_job(const json* last) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (last) last_ = *last;
  info_ = json::object();
  active_ = false;
}

void JobControl::abandon_interrupted() { remove_journal(journal_); }

// A journal that cannot be written leaves the previous one as it was (write_journal) and the
// program runs on, but a host lost during it cannot be resumed: say so in the log, in the
// status object (journal_error) and as an event.
void JobControl::journal_failed(const std::string& why) {
  spdlog::error("journal: {}; a program interrupted by a lost host could not be resumed", why);
  {
    std::lock_guard<std::mutex> lock(mutex_);
    journal_error_ = why;
  }
  notices_.event(json{{"event", "journal_error"}, {"message", why}});
}

void JobControl::journal_ok() {
  std::lock_guard<std::mutex> lock(mutex_);
  journal_error_.clear();
}

void JobControl::describe(json& j, const std::optional<Status>& st) const {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    j["job"] = info_;
    j["last_job"] = last_;
    j["job"]["active"] = active_.load();
    if (feed_) {  // a stream: has it made blocks of all it received?
      j["job"]["waiting_for_lines"] = feed_->waiting();
      j["job"]["blocks_streamed"] = stream_blocks_.load();
    }
    j["journal_error"] = journal_error_.empty() ? json(nullptr) : json(journal_error_);
  }
  j["resume"] = nullptr;
  if (st && st->state == MachineState::kHostLost) {
    if (auto jj = read_journal(journal_, nullptr)) {
      j["resume"] = json{{"file", jj->file}, {"line", st->line}, {"block_seq", st->block_seq + jj->seq_base}};
    }
  }
}

// Why a program (or MDI) cannot start now; ok() when it can.
Outcome JobControl::refuse_start(const Status& st) const {
  if (active_.load()) return Outcome::fail(refused("a program is already running; stop it first"));
  if (st.state != MachineState::kIdle) {
    std::string why = std::string("the machine is ") + to_string(st.state) + ", not IDLE";
    if (st.state == MachineState::kHostLost) why += ": resume or stop the program the lost host was running first";
    if (st.state == MachineState::kFault || st.state == MachineState::kEstop) why += ": reset first";
    if (st.state == MachineState::kPaused) why += ": resume or stop the program first";
    return Outcome::fail(refused(why));
  }
  return Outcome::ok(json());
}

Outcome JobControl::run(ClientId client, const json& id, const rpc::RunParams& params, std::shared_ptr<RtLink> link,
                        const Status& st, const MachineConfig& config, const WorkState& work) {
  if (Outcome no = refuse_start(st); no.error) return no;
  // Copies: set_offset may change the service's work state meanwhile.
  MachineConfig job_config = config;
  job_config.gcode.work_offsets = first_six(work.g5x);
  start_worker(client, id, [this, client, id, rp = params, link, job_config, ws = work, start = st.commanded] {
    run_job(client, id, rp, link, job_config, ws, start);
  });
  return Outcome::later();
}

void JobControl::run_job(ClientId client, const json& id, const rpc::RunParams& rp, std::shared_ptr<RtLink> l,
                         const MachineConfig& cfg, const WorkState& ws, const Vec3& start) {
  const WorkOffsets& g5x = ws.g5x;
  JobOptions opts;
  opts.work = ws;  // G92 and the G28/G30 positions too, as the service's state file holds them

  if (!cfg.gcode.tool_table.empty()) {
    if (const std::string why = load_job_state(cfg, cfg.gcode.tool_table, opts); !why.empty()) {
      end_job(nullptr);
      job_reply(client, id, Outcome::fail(rpc::Error{rpc::kPreflightFailed, why, json()}));
      return;
    }
    opts.work = ws;  // the service's own copy, not the file's
  }
  opts.work_offset_index = rp.work_offset;
  opts.fit = rp.fit;
  opts.contouring = rp.contouring;
  opts.offset = rp.offset;  // replaces G54 for this run, as `pcnc run --offset`
  opts.start_position = start;
  if (l) opts.start_rotary = l->status().rot_commanded;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    info_ = json{{"file", rp.file}, {"phase", "preflight"}};
  }
  // The content the run is checked from, before the check reads it: a resume refuses a
  // program whose content changed since.
  std::string hash_error;
  const std::string sha256 = sha256_file(rp.file, &hash_error);
  opts.on_check_progress = check_progress_fn();
  CheckResult check = check_program(rp.file, cfg, opts);
  opts.on_check_progress = nullptr;  // a probing run's checks of the rest report nothing
  if (check.interrupted) {
    spdlog::info("run {} stopped during its preflight", rp.file);
    end_job(nullptr);  // no job ran
    job_reply(client, id, Outcome::fail(refused(rp.file + ": stopped during the preflight check; nothing was moved")));
    return;
  }
  if (!check.ok) {
    const auto errors = static_cast<std::size_t>(check.error_count);  // also those beyond the ones listed
    json data = {{"file", rp.file}, {"errors", diagnostics_json(check, Diagnostic::Severity::kError)}};
    spdlog::warn("run {} refused: preflight found {} error(s)", rp.file, errors);
    end_job(nullptr);  // no job ran
    job_reply(client, id,
                   Outcome::fail(rpc::Error{rpc::kPreflightFailed,
                                            rp.file + ": preflight found " + std::to_string(errors) + " error(s); nothing was moved",
                                            data}));
    return;
  }
  JobJournal jj;
  jj.file = rp.file;
  jj.work_offset = rp.work_offset;
  jj.work_offsets = g5x;
  if (rp.offset) jj.work_offsets[0] = *rp.offset;  // a resume starts from the G54 the run had
  jj.fit = rp.fit;
  jj.contouring = rp.contouring ? (*rp.contouring ? 1 : 0) : -1;
  jj.start_position = start;
  jj.host_pid = getpid();
  jj.file_sha256 = sha256;
  jj.transform_offset = check.transform.offset;
  jj.transform_scale = check.transform.scale;
  jj.path_tolerance_mm = cfg.motion.path_tolerance_mm;
  jj.config_path = cfg.source_path;
  file_identity(rp.file, jj.file_size, jj.file_mtime_ns);
  std::string jerr;
  if (sha256.empty()) {
    journal_failed("cannot record " + rp.file + " in the journal: " + hash_error);
  } else if (!write_journal(journal_, jj, &jerr)) {
    journal_failed(jerr);
  } else {
    journal_ok();
  }

  json started = {{"started", true},
                  {"file", rp.file},
                  {"lines", check.lines},
                  {"moves", check.moves},
                  {"offset", rpc::vec3_to_json(check.transform.offset)},
                  {"scale", check.transform.scale},
                  {"planned_time_s", check.planned_time_s},
                  {"warnings", diagnostics_json(check, Diagnostic::Severity::kWarning)}};
  // (MSG,...)/(DEBUG,...)/(PRINT,...): in the log and to subscribers as the stream (not the
  // check) reaches them, close to when the machine does.
  opts.on_message = [this, file = rp.file](const ProgramMessage& m) {
    spdlog::info("{}:{}: {}", file, m.line, m.text);
    notices_.event(json{{"event", "message"}, {"file", file}, {"line", m.line}, {"text", m.text}});
  };
  follow_job(
      client, id, l, cfg, started, rp.file,
      [&](JobRunner& runner) {
        if (!sha256.empty()) {
          // each probe result into the journal, so that a resumed run interprets with it
          runner.set_on_probe_result([&](const ProbeResults& r) { journal_probes(jj, r); });
        }
        return runner.run(rp.file, opts, check, interrupt_, progress_fn(check.planned_time_s));
      },
      &ws);
}

Outcome JobControl::mdi(ClientId client, const json& id, const std::string& text, std::shared_ptr<RtLink> link,
                        const Status& st, const MachineConfig& config, const WorkState& work) {
  if (Outcome no = refuse_start(st); no.error) return no;
  MachineConfig job_config = config;
  job_config.gcode.work_offsets = first_six(work.g5x);
  start_worker(client, id, [this, client, id, text, link, job_config, ws = work, start = st.commanded] {
    mdi_job(client, id, text, link, job_config, ws, start);
  });
  return Outcome::later();
}

// MDI is a small program: the same check and the same stream, over the text. No journal: a
// lost host's MDI is not resumed (stop abandons it).
void JobControl::mdi_job(ClientId client, const json& id, const std::string& text, std::shared_ptr<RtLink> l,
                         const MachineConfig& cfg, const WorkState& ws, const Vec3& start) {
  static const std::string kName = "mdi";
  JobOptions opts;
  if (!cfg.gcode.tool_table.empty()) {
    if (const std::string why = load_job_state(cfg, cfg.gcode.tool_table, opts); !why.empty()) {
      end_job(nullptr);
      job_reply(client, id, Outcome::fail(rpc::Error{rpc::kPreflightFailed, why, json()}));
      return;
    }
  }
  opts.work = ws;
  opts.work_offset_index = ws.active;
  opts.start_position = start;
  if (l) opts.start_rotary = l->status().rot_commanded;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    info_ = json{{"file", "MDI"}, {"phase", "preflight"}};
  }
  const CheckResult check = check_program_text(text, kName, cfg, opts);
  if (!check.ok) {
    json errors = diagnostics_json(check, Diagnostic::Severity::kError);
    spdlog::warn("mdi refused: {} error(s)", errors.size());
    end_job(nullptr);
    job_reply(client, id,
              Outcome::fail(rpc::Error{rpc::kPreflightFailed,
                                       "mdi: " + std::to_string(errors.size()) + " error(s); nothing was moved",
                                       json{{"file", kName}, {"errors", errors}}}));
    return;
  }
  json warnings = json::array();
  for (const auto& d : check.diagnostics) {  // an MDI text has no M2 by nature: its implicit end is no news
    if (d.severity == Diagnostic::Severity::kWarning && d.message.find("has no M2/M30") == std::string::npos) {
      warnings.push_back(format_diagnostic(d));
    }
  }
  // through its probing moves' sync points, as a file runs (docs/probe.md)
  auto sync = std::make_shared<ProbeSync>(*l, cfg, ProbeSync::FromText{}, text, kName, opts, check.transform);
  BlockSource source;
  source.next = [sync](Block& b) { return sync->next(b); };
  source.progress = [sync] {
    const BlockStream& s = sync->stream();
    return JobProgress{s.lines_read(), s.bytes_read(), s.total_bytes(), Status{}};
  };
  source.resume = [sync](const std::atomic<bool>& stop, bool& more) { return sync->resume(stop, more); };
  json started = {{"started", true},         {"mdi", true},
                  {"lines", check.lines},     {"moves", check.moves},
                  {"planned_time_s", check.planned_time_s}, {"warnings", warnings}};
  const bool contouring = cfg.motion.contouring_default;
  follow_job(
      client, id, l, cfg, started, "MDI",
      [&](JobRunner& runner) { return runner.run_source(source, contouring, interrupt_, progress_fn(check.planned_time_s)); },
      &ws, [sync](const JobRunner&) { return std::optional<WorkState>(sync->stream().work_state()); });
}

// The preflight's progress in the status object (`check_pass`, `check_line`, `check_fraction`:
// how much of the program's text is read), and `stop` (or the service's shutdown) ends the
// check there: a long program's check is not waited for.
CheckProgressHandler JobControl::check_progress_fn() {
  return [this](const CheckProgress& c) {
    if (interrupt_.load()) throw CheckInterrupted("stopped during the preflight check");
    std::lock_guard<std::mutex> lock(mutex_);
    info_["check_pass"] = c.pass == CheckPass::kFit ? "fit" : "check";
    info_["check_line"] = c.line;
    info_["check_fraction"] = c.fraction();
  };
}

// A resume's locate pass (the program run again up to the interrupted block) in the status
// object as `check_pass` "locate", with the line and the share of the text read, at most every
// 0.1 s; false once `stop` (or the service's shutdown) asked the resume to end.
std::function<bool()> JobControl::locate_progress_fn(const BlockStream& stream) {
  return [this, &stream, last = std::chrono::steady_clock::now()]() mutable {
    if (interrupt_.load()) return false;
    const auto now = std::chrono::steady_clock::now();
    if (now - last < std::chrono::milliseconds(100)) return true;
    last = now;
    CheckProgress c;
    c.line = stream.lines_read();
    c.bytes_read = stream.bytes_read();
    c.total_bytes = stream.total_bytes();
    std::lock_guard<std::mutex> lock(mutex_);
    info_["check_pass"] = "locate";
    info_["check_line"] = c.line;
    info_["check_fraction"] = c.fraction();
    return true;
  };
}

// The job's progress in the status object; with the check's planned time, the planned time of
// the blocks done (the ETA's base: `pcnc ctl status --watch`, docs/protocol.md).
std::function<void(const JobProgress&)> JobControl::progress_fn(double planned_total_s) {
  return [this, planned_total_s](const JobProgress& p) {
    std::lock_guard<std::mutex> lock(mutex_);
    info_["lines_read"] = p.lines_read;
    info_["bytes_read"] = p.bytes_read;
    info_["total_bytes"] = p.total_bytes;
    if (planned_total_s > 0.0) {
      info_["planned_time_s"] = planned_total_s;
      info_["planned_done_s"] = p.planned_done_s;
    }
  };
}

// Runs a job to its end with replies, events, the last-job record and the journal.
void JobControl::follow_job(ClientId client, const json& id, std::shared_ptr<RtLink> l, const MachineConfig& cfg,
                            json started, const std::string& file, const std::function<JobResult(JobRunner&)>& body,
                            const WorkState* work_before,
                            const std::function<std::optional<WorkState>(const JobRunner&)>& work_after) {
  JobRunner runner(*l, cfg);
  bool replied = false;
  runner.set_on_started([&] {
    replied = true;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      info_ = json{{"file", file}, {"phase", "running"}};
    }
    spdlog::info("program {} started", file);
    job_reply(client, id, Outcome::ok(started));
    notices_.event(json{{"event", "program_started"}, {"file", file}});
  });
  const JobResult r = body(runner);
  // What the program left (G10, G92...) is kept, as LinuxCNC's var file keeps it. The loop
  // thread applies it; the job is not over (end_job, the reply, the program_end event) until
  // it has, or a status read between the two would show the job done with the old offsets.
  // The wait is bounded: a loop thread that is shutting down never answers.
  if (r.end == JobEnd::kCompleted && work_before && notices_.work_after) {
    if (auto w = work_after ? work_after(runner) : runner.work_after()) {
      auto applied = std::make_shared<std::promise<void>>();
      std::future<void> done = applied->get_future();
      notices_.work_after(*work_before, *w, [applied] { applied->set_value(); });
      if (done.wait_for(std::chrono::seconds(10)) != std::future_status::ready) {
        spdlog::warn("the service did not take the work offsets the program left within 10 s");
      }
    }
  }
  const bool host_lost = r.final_status.state == MachineState::kHostLost;
  if (!host_lost) remove_journal(journal_);  // before end_job: a next job writes its own
  json end = {{"file", file},
              {"end", to_string(r.end)},
              {"message", r.message},
              {"blocks_sent", r.blocks_sent},
              {"lines_read", r.lines_read},
              {"underruns", r.final_status.underruns},
              {"program_time_s", r.final_status.program_time_s},
              {"wall_time_s", r.wall_time_s},
              {"final_position", rpc::vec3_to_json(r.final_status.commanded)}};
  if (r.end == JobEnd::kCompleted) {
    spdlog::info("program {} completed: {} blocks, {:.3f} s machine time, {} underruns", file, r.blocks_sent,
                 r.final_status.program_time_s, r.final_status.underruns);
  } else {
    spdlog::warn("program {} ended: {}: {}", file, to_string(r.end), r.message);
  }
  end_job(&end);
  if (!replied) job_reply(client, id, Outcome::fail(refused(r.message)));
  json ev = end;
  ev["event"] = "program_end";
  notices_.event(ev);
}

Outcome JobControl::resume(ClientId client, const json& id, std::shared_ptr<RtLink> link, const Status& st,
                           const MachineConfig& config) {
  if (st.state != MachineState::kHostLost) {
    return Outcome::fail(refused(std::string("nothing to resume: the machine is ") + to_string(st.state)));
  }
  if (active_.load()) return Outcome::fail(refused("a program is already being resumed"));
  std::string why;
  auto jj = read_journal(journal_, &why);
  if (!jj) {
    return Outcome::fail(refused("the machine is HOST_LOST but there is no record of the interrupted program (" + why +
                                 "); use stop or reset"));
  }
  MachineConfig job_config = config;
  job_config.gcode.work_offsets = first_six(jj->work_offsets);
  start_worker(client, id, [this, client, id, link, job_config, j = *jj] { resume_job(client, id, link, job_config, j); });
  return Outcome::later();
}

// The probe results so far into the journal (a failed write is reported as the others are).
void JobControl::journal_probes(JobJournal& jj, const ProbeResults& r) {
  jj.probes.clear();
  for (const ProbeResult& p : r.known) jj.probes.push_back(JournalProbe{static_cast<int>(p.outcome), p.latched, p.stop});
  std::string jerr;
  if (write_journal(journal_, jj, &jerr)) {
    journal_ok();
  } else {
    journal_failed(jerr);
  }
}

void JobControl::resume_job(ClientId client, const json& id, std::shared_ptr<RtLink> l, const MachineConfig& cfg,
                            JobJournal jj) {
  auto fail = [&](std::string why) {
    spdlog::warn("resume refused: {}", why);
    end_job(nullptr);  // nothing runs
    job_reply(client, id, Outcome::fail(refused("cannot resume: " + why + "; use stop to abandon the program")));
  };
  // `stop` in HOST_LOST (methods.cpp) has abandoned the program while this resume got ready
  auto stopped = [&](const std::string& when) {
    spdlog::info("resume of {} stopped {}", jj.file, when);
    remove_journal(journal_);  // abandoned: a journal written since must not be resumed later
    end_job(nullptr);
    job_reply(client, id, Outcome::fail(refused("resume stopped " + when + "; the program was abandoned and nothing was moved")));
  };
  // The same program: its content (SHA-256), not only its size and time.
  if (jj.file_sha256.empty()) return fail("the journal holds no hash of " + jj.file + " (written by an older pcnc-host)");
  std::string hash_error;
  const std::string sha256 = sha256_file(jj.file, &hash_error);
  if (sha256.empty()) return fail(jj.file + " cannot be read any more (" + hash_error + ")");
  if (sha256 != jj.file_sha256) {
    return fail(jj.file + " changed since the program started (its SHA-256 is " + sha256.substr(0, 16) + "..., the journal's " +
                jj.file_sha256.substr(0, 16) + "...): resuming would run a different program");
  }
  JobOptions opts;
  opts.work_offset_index = jj.work_offset;
  opts.fit = jj.fit;
  if (jj.contouring >= 0) opts.contouring = jj.contouring == 1;
  opts.start_position = jj.start_position;
  if (cfg.motion.path_tolerance_mm != jj.path_tolerance_mm) {
    return fail("the path tolerance changed since the program started (" + std::to_string(jj.path_tolerance_mm) + " mm, now " +
                std::to_string(cfg.motion.path_tolerance_mm) + " mm)");
  }
  // the probing moves' results so far (docs/probe.md): the program is interpreted with them
  auto known = std::make_shared<ProbeResults>();
  for (const JournalProbe& p : jj.probes) {
    known->known.push_back(ProbeResult{static_cast<ProbeOutcome>(p.outcome), p.latched, p.stop});
  }
  opts.probe = known;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    info_ = json{{"file", jj.file}, {"phase", "preflight"}};
  }
  opts.on_check_progress = check_progress_fn();  // in status; the service's shutdown ends it
  const CheckResult check = check_program(jj.file, cfg, opts);
  opts.on_check_progress = nullptr;
  // `stop` in HOST_LOST abandons the program (methods.cpp): a stop during the check or the
  // locate pass below ends the resume before anything is sent.
  if (check.interrupted || interrupt_.load()) return stopped("during the preflight check");
  if (!check.ok) return fail(jj.file + " no longer passes preflight");
  if (check.transform.offset != jj.transform_offset || check.transform.scale != jj.transform_scale) {
    return fail("the program's placement (offset and scale) differs from the one it started with");
  }

  const Status st = l->status();
  if (st.state != MachineState::kHostLost) return fail(std::string("the machine left HOST_LOST (now ") + to_string(st.state) + ")");
  // The program block the rt stood in (its seq in this run plus the blocks an earlier
  // resume skipped), and the machine position on it.
  const std::uint64_t k = st.block_seq == 0 ? jj.seq_base + 1 : st.block_seq + jj.seq_base;
  const Vec3 at = st.commanded;
  JobOptions locate = opts;  // up to the interrupted block, which no unknown probe may precede
  auto located = std::make_shared<ProbeResults>(*known);
  located->stop_at_unknown = true;
  locate.probe = located;
  auto stream = std::make_shared<BlockStream>(jj.file, cfg, locate, check.transform);
  Block b{};
  std::size_t probes_located = 0;  // probing blocks up to block k
  const auto report_locate = locate_progress_fn(*stream);
  for (std::uint64_t n = 0; n < k; ++n) {
    if (n % kLocateReportEvery == 0 && n > 0 && !report_locate()) return stopped("while locating the interrupted block");
    if (n > 0 && b.probe_rule != 0) ++probes_located;
    if (!stream->next(b)) {
      if (stream->probe_sync()) {
        return fail("the machine stopped after a probing move whose result the journal does not hold (the host was lost "
                    "waiting for it)");
      }
      return fail("the program has fewer blocks than where the machine stopped");
    }
  }
  std::optional<Continuation> cont;
  std::string why;
  if (b.probe_rule != 0) {
    ++probes_located;
    // The machine stands at a probing move. The rt finished it when its status holds the result
    // of this very block (then it stands where the probe stopped: nothing of the move is left);
    // a move that the host's loss cut short is not resumed (the probe would start elsewhere).
    const bool finished = st.probe_count > 0 && st.probe_seq == st.block_seq && st.probe_outcome != ProbeOutcome::kNone;
    if (!finished) return fail("the machine stopped in a probing move (line " + std::to_string(b.line) + ")");
    if (probes_located == known->known.size() + 1) {
      // The host was lost while it waited for this result: take it from the rt's status, as the
      // sync point would have, into the journal and the probe log; check the rest with it.
      const ProbeResult r{st.probe_outcome, st.probe_latched, st.probe_stop};
      known->known.push_back(r);
      jj.probes.push_back(JournalProbe{static_cast<int>(r.outcome), r.latched, r.stop});
      if (const std::string e = write_probe_log(*stream, jj.file, r, false); !e.empty()) return fail(e);
      spdlog::info("resume: the probing move at line {} ended while the host was lost; its result is pcnc-rt's", b.line);
      const CheckResult again = check_program(jj.file, cfg, opts);
      if (!again.ok) {
        for (const Diagnostic& d : again.diagnostics)
          if (d.severity == Diagnostic::Severity::kError) return fail(format_diagnostic(d));
        return fail("the program cannot go on after the probing move at line " + std::to_string(b.line));
      }
    } else if (probes_located != known->known.size()) {
      return fail("the journal holds " + std::to_string(known->known.size()) + " probe results, the program " +
                  std::to_string(probes_located) + " probing moves up to where the machine stopped");
    }
    cont = Continuation{true, Block{}};
  } else {
    const double tol = std::max(10.0 * cfg.motion.block_tolerance_mm, 0.005);
    cont = continue_block(b, at, cfg, tol, &why, st.rot_commanded);
    if (!cont) return fail(why);
  }
  // The continuation starts exactly where the machine stands (a ruled block: at the tip its
  // joints give, on the piece, which continue_block placed).
  if (!cont->skip && b.kind != BlockKind::kDwell && b.kind != BlockKind::kEnd && b.kind != BlockKind::kRuled)
    cont->block.start = at;
  // The journal first: a resumed run that could not be recorded would leave one that points
  // at the wrong block, so the resume is refused and the old journal stays as it was.
  jj.seq_base = cont->skip ? k : k - 1;
  jj.host_pid = getpid();
  if (std::string jerr; !write_journal(journal_, jj, &jerr)) {
    journal_failed(jerr);
    return fail("the journal cannot be written (" + jerr + ")");
  }
  journal_ok();
  if (interrupt_.load()) return stopped("before the program went on");
  // Leave HOST_LOST (the rt keeps its position), then start the rest as a new program.
  const std::uint64_t reset_id = l->send(CommandKind::kReset);
  if (reset_id == 0) return fail("pcnc-rt's mailbox is full");
  for (int i = 0; i < 1000; ++i) {
    const Status s = l->status();
    if (s.last_command_id >= reset_id && s.state == MachineState::kIdle) break;
    if (!l->rt_alive()) return fail("pcnc-rt was lost");
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  spdlog::info("resuming {} at line {} (block {}) from X{:.4f} Y{:.4f} Z{:.4f}", jj.file, b.line, k, at[0], at[1], at[2]);

  auto first = std::make_shared<std::optional<Block>>();
  if (!cont->skip) *first = cont->block;
  // the rest through the probing moves' sync points (docs/probe.md), from block k + 1 on
  auto sync = std::make_shared<ProbeSync>(*l, cfg, jj.file, opts, check.transform);
  sync->resume_after(k, jj.seq_base);
  sync->set_on_result([this, &jj](const ProbeResults& r) { journal_probes(jj, r); });
  BlockSource source;
  source.next = [sync, first](Block& out) {
    if (first->has_value()) {
      out = **first;
      first->reset();
      return true;
    }
    return sync->next(out);
  };
  source.progress = [sync] {
    const BlockStream& s = sync->stream();
    return JobProgress{s.lines_read(), s.bytes_read(), s.total_bytes(), Status{}};
  };
  source.resume = [sync](const std::atomic<bool>& stop, bool& more) { return sync->resume(stop, more); };
  const bool contouring = jj.contouring >= 0 ? jj.contouring == 1 : cfg.motion.contouring_default;
  json started = {{"resumed", true}, {"file", jj.file}, {"line", b.line}, {"block", k}, {"from", rpc::vec3_to_json(at)}};
  follow_job(client, id, l, cfg, started, jj.file,
             [&](JobRunner& runner) { return runner.run_source(source, contouring, interrupt_, progress_fn()); });
}

}  // namespace pcnc
