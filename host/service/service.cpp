// service.cpp — the operator service (see service.hpp and docs/protocol.md).
#include "service/service.hpp"

#include <spdlog/spdlog.h>
#include <unistd.h>

#include <chrono>
#include <map>
#include <mutex>
#include <optional>
#include <thread>

#include "service/job_journal.hpp"
#include "service/job_runner.hpp"
#include "gcode/program.hpp"
#include "service/resume.hpp"
#include "service/rpc.hpp"
#include "service/rt_link.hpp"

namespace pcnc {

using rpc::json;
using Clock = std::chrono::steady_clock;

namespace {

double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

rpc::Error refused(std::string message) { return rpc::Error{rpc::kRefused, std::move(message), nullptr}; }

bool segment_error_transient(const std::string& why) {
  return why.find("does not exist") != std::string::npos || why.find("never published") != std::string::npos ||
         why.find("not initialised") != std::string::npos;
}

json diagnostics_json(const CheckResult& check, Diagnostic::Severity severity) {
  json list = json::array();
  for (const auto& d : check.diagnostics) {
    if (d.severity == severity) list.push_back(format_diagnostic(d));
  }
  return list;
}

}  // namespace

struct Service::Impl {
  // What a request handler gives back: a result, an error, or "the reply comes later".
  struct Outcome {
    std::optional<json> result;
    std::optional<rpc::Error> error;
    static Outcome ok(json j) { return Outcome{std::move(j), std::nullopt}; }
    static Outcome fail(rpc::Error e) { return Outcome{std::nullopt, std::move(e)}; }
    static Outcome later() { return Outcome{}; }
  };

  struct Subscription {
    double period_s = 0.1;
    Clock::time_point next{};
  };

  struct ContinuousJog {
    ClientId owner = 0;
    Clock::time_point last_client{}, last_rt{}, started{};
    std::uint64_t cmd_id = 0;
    bool seen_jogging = false;
  };

  // A jog whose acceptance by the rt is checked before replying.
  struct PendingJog {
    ClientId client = 0;
    json id;
    std::uint64_t cmd_id = 0;
    Vec3 before{};
    json result;
    Clock::time_point deadline{};
  };

  Impl(const MachineConfig& c, ServiceOptions o) : config(c), opt(o), journal(journal_path(c.process.socket_path)) {}

  // ---- rt link ----
  std::shared_ptr<RtLink> current_link() {
    std::lock_guard<std::mutex> lock(link_mutex);
    return link;
  }

  std::shared_ptr<RtLink> require_link(rpc::Error& error) {
    auto l = current_link();
    if (l && l->rt_alive()) return l;
    std::lock_guard<std::mutex> lock(link_mutex);
    error = rpc::Error{rpc::kRtUnavailable, "pcnc-rt is not available (" + rt_state + "): " + rt_message, nullptr};
    return nullptr;
  }

  void set_rt_state(const std::string& state, const std::string& message) {
    std::lock_guard<std::mutex> lock(link_mutex);
    rt_state = state;
    rt_message = message;
  }

  void monitor_loop() {
    auto next_attach = Clock::now();
    std::string last_problem;
    while (!monitor_stop.load()) {
      std::shared_ptr<RtLink> l = current_link();
      if (l) {
        if (!l->rt_alive()) {
          std::string why = l->rt_loss_reason();
          if (why.empty()) why = "pcnc-rt stopped responding";
          const double age_ms = l->rt_heartbeat_age_s() * 1000.0;
          {
            std::lock_guard<std::mutex> lock(link_mutex);
            link.reset();
            rt_state = "lost";
            rt_message = why;
          }
          spdlog::error("pcnc-rt lost: {} (last heartbeat {:.1f} ms ago); motion commands are refused until a new "
                        "pcnc-rt starts",
                        why, age_ms);
          server->post([this, why, age_ms] {
            broadcast_event(json{{"event", "rt_lost"}, {"message", why}, {"heartbeat_age_ms", age_ms}});
          });
          next_attach = Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(opt.attach_retry_s));
        }
      } else if (Clock::now() >= next_attach) {
        next_attach = Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(opt.attach_retry_s));
        try_attach(last_problem);
      }
      std::this_thread::sleep_for(std::chrono::duration<double>(opt.monitor_period_s));
    }
  }

  void try_attach(std::string& last_problem) {
    try {
      std::shared_ptr<RtLink> nl = RtLink::attach(config, 0.0);
      if (!nl->rt_alive()) {
        const std::string why = "found a segment left by a pcnc-rt that is gone (" + nl->rt_loss_reason() + "); waiting for a new pcnc-rt";
        if (why != last_problem) spdlog::info("{}", why);
        last_problem = why;
        std::lock_guard<std::mutex> lock(link_mutex);
        rt_message = why;
        return;
      }
      const Status st = nl->status();
      const int pid = nl->rt_pid();
      {
        std::lock_guard<std::mutex> lock(link_mutex);
        link = nl;
        rt_state = "attached";
        rt_message = "";
        rt_pid = pid;
      }
      last_problem.clear();
      spdlog::info("attached to pcnc-rt pid {} (machine {}, {} clock)", pid, to_string(st.state), st.clock_virtual ? "virtual" : "real");
      if (st.state == MachineState::kHostLost) {
        spdlog::warn("the machine is HOST_LOST: a previous pcnc-host was lost while a program ran; 'resume' continues it, "
                     "'stop' abandons it");
      }
      server->post([this, pid, st] {
        broadcast_event(json{{"event", "rt_attached"}, {"pid", pid}, {"state", to_string(st.state)}});
      });
    } catch (const std::exception& e) {
      const std::string why = e.what();
      const bool transient = segment_error_transient(why);
      if (why != last_problem) {
        if (transient) {
          spdlog::info("waiting for pcnc-rt: {}", why);
        } else {
          spdlog::error("refusing pcnc-rt's segment: {}", why);
        }
      }
      last_problem = why;
      std::lock_guard<std::mutex> lock(link_mutex);
      if (!transient) {
        rt_state = "refused";
      } else if (rt_state == "refused" || rt_state == "attached") {
        rt_state = "waiting";
      }
      rt_message = why;
    }
  }

  // ---- replies and notifications (loop thread) ----
  void reply(ClientId client, const json& id, const Outcome& o) {
    if (o.error) {
      server->send(client, rpc::format_error(id, *o.error));
    } else if (o.result) {
      server->send(client, rpc::format_result(id, *o.result));
    }
  }

  // From any thread: the reply goes out on the loop thread.
  void post_reply(ClientId client, json id, Outcome o) {
    server->post([this, client, id = std::move(id), o = std::move(o)] { reply(client, id, o); });
  }

  void broadcast_event(const json& event) {
    const std::string line = rpc::format_notification("event", event);
    for (auto& [client, sub] : subs) server->send(client, line);
  }

  json status_json() {
    json j = json::object();
    auto l = current_link();
    std::optional<Status> st;
    if (l && l->rt_alive()) {
      st = l->status();
      j = rpc::status_to_json(*st);
    } else {
      j["state"] = "NO_RT";
    }
    {
      std::lock_guard<std::mutex> lock(link_mutex);
      json rt = {{"state", rt_state}, {"message", rt_message}, {"pid", rt_pid}};
      if (l) rt["heartbeat_age_ms"] = l->rt_heartbeat_age_s() * 1000.0;
      j["rt"] = rt;
    }
    {
      std::lock_guard<std::mutex> lock(job_mutex);
      j["job"] = job_info;
      j["last_job"] = last_job;
      j["job"]["active"] = job_active.load();
    }
    json offsets = json::object();
    for (int i = 0; i < 6; ++i) offsets[rpc::work_offset_name(i)] = rpc::vec3_to_json(config.gcode.work_offsets[static_cast<std::size_t>(i)]);
    j["work_offsets"] = offsets;
    j["jog"] = json{{"continuous", jog.has_value()}};
    j["resume"] = nullptr;
    if (st && st->state == MachineState::kHostLost) {
      if (auto jj = read_journal(journal, nullptr)) {
        j["resume"] = json{{"file", jj->file}, {"line", st->line}, {"block_seq", st->block_seq + jj->seq_base}};
      }
    }
    return j;
  }

  // ---- request dispatch (loop thread) ----
  void on_line(ClientId client, std::string_view line) {
    rpc::ParsedRequest parsed = rpc::parse_request(line);
    if (parsed.error) {
      server->send(client, rpc::format_error(parsed.request.id, *parsed.error));
      return;
    }
    const rpc::Request& req = parsed.request;
    Outcome o;
    try {
      o = dispatch(client, req);
    } catch (const std::exception& e) {
      o = Outcome::fail(rpc::Error{rpc::kInternalError, std::string("internal error: ") + e.what(), nullptr});
    }
    reply(client, req.id, o);
  }

  Outcome dispatch(ClientId client, const rpc::Request& req) {
    const std::string& m = req.method;
    if (m == "status" || m == "pause" || m == "resume" || m == "stop" || m == "estop" || m == "reset" || m == "jog_stop" ||
        m == "jog_keepalive") {
      if (auto e = rpc::check_no_params(m, req.params)) return Outcome::fail(*e);
    }
    if (m == "status") return Outcome::ok(status_json());
    if (m == "subscribe") return do_subscribe(client, req.params);
    if (m == "set_offset") return do_set_offset(req.params);
    if (m == "jog_keepalive") return do_jog_keepalive(client);

    rpc::Error err;
    auto l = require_link(err);
    if (!l) return Outcome::fail(err);
    const Status st = l->status();
    if (m == "run") return do_run(client, req.id, req.params, l, st);
    if (m == "pause") return do_pause(*l, st);
    if (m == "resume") return do_resume(client, req.id, l, st);
    if (m == "stop") return do_stop(*l, st);
    if (m == "estop") return do_estop(*l);
    if (m == "reset") return do_reset(*l, st);
    if (m == "override") return do_override(*l, req.params);
    if (m == "jog") return do_jog(client, req.id, *l, st, req.params);
    if (m == "jog_stop") return do_jog_stop(*l);
    return Outcome::fail(rpc::Error{rpc::kMethodNotFound, "unknown method '" + m + "'", nullptr});
  }

  Outcome sent(RtLink& l, Command c, json result) {
    const std::uint64_t id = l.send(c);
    if (id == 0) return Outcome::fail(rpc::Error{rpc::kMailboxFull, "pcnc-rt's command mailbox is full; try again", nullptr});
    result["command_id"] = id;
    return Outcome::ok(std::move(result));
  }

  static Command command(CommandKind kind) {
    Command c;
    c.kind = kind;
    return c;
  }

  Outcome do_pause(RtLink& l, const Status& st) {
    if (st.state == MachineState::kRunning) return sent(l, command(CommandKind::kPause), json{{"state", "PAUSED"}});
    if (st.state == MachineState::kJogging) return sent(l, command(CommandKind::kJogStop), json{{"state", "IDLE"}});
    return Outcome::fail(refused(std::string("nothing to pause: the machine is ") + to_string(st.state)));
  }

  Outcome do_stop(RtLink& l, const Status& st) {
    switch (st.state) {
      case MachineState::kRunning:
      case MachineState::kPaused:
      case MachineState::kStopping:
        job_interrupt = true;  // the worker stops feeding; the rt decelerates on the path
        return sent(l, command(CommandKind::kStop), json{{"state", "STOPPING"}});
      case MachineState::kJogging:
        jog.reset();
        if (st.program_active) {
          // a jog while the program is paused: stop ends the jog and the program (the rt
          // flushes it and takes up where the machine stands)
          job_interrupt = true;
          return sent(l, command(CommandKind::kStop), json{{"state", "STOPPING"}});
        }
        return sent(l, command(CommandKind::kJogStop), json{{"state", "IDLE"}});
      case MachineState::kHostLost:
        // The interrupted program is abandoned: leave HOST_LOST, forget the journal.
        remove_journal(journal);
        spdlog::info("stop: the program interrupted by the lost host is abandoned");
        return sent(l, command(CommandKind::kReset), json{{"state", "IDLE"}, {"abandoned", true}});
      default:
        if (job_active.load()) {
          job_interrupt = true;
          return Outcome::ok(json{{"state", to_string(st.state)}, {"note", "the program was stopped before it started"}});
        }
        return Outcome::ok(json{{"state", to_string(st.state)}, {"note", "nothing was moving"}});
    }
  }

  Outcome do_estop(RtLink& l) {
    jog.reset();
    job_interrupt = true;
    spdlog::warn("e-stop requested over the control socket");
    return sent(l, command(CommandKind::kEstop), json{{"state", "ESTOP"}});
  }

  Outcome do_reset(RtLink& l, const Status& st) {
    if (st.state != MachineState::kFault && st.state != MachineState::kEstop && st.state != MachineState::kHostLost) {
      return Outcome::fail(refused(std::string("nothing to reset: the machine is ") + to_string(st.state) +
                                   " (reset leaves FAULT, ESTOP or HOST_LOST)"));
    }
    if (st.state == MachineState::kHostLost) remove_journal(journal);
    return sent(l, command(CommandKind::kReset), json{{"state", "IDLE"}, {"was", to_string(st.state)}});
  }

  Outcome do_override(RtLink& l, const json& params) {
    auto p = rpc::check_override_params(params);
    if (!p.ok()) return Outcome::fail(p.error);
    Command c = command(CommandKind::kFeedOverride);
    c.value = p.value->percent / 100.0;
    return sent(l, c, json{{"percent", p.value->percent}});
  }

  Outcome do_subscribe(ClientId client, const json& params) {
    auto p = rpc::check_subscribe_params(params);
    if (!p.ok()) return Outcome::fail(p.error);
    if (p.value->rate_hz <= 0.0) {
      subs.erase(client);
      return Outcome::ok(json{{"rate_hz", 0}});
    }
    subs[client] = Subscription{1.0 / p.value->rate_hz, Clock::now()};
    return Outcome::ok(json{{"rate_hz", p.value->rate_hz}});
  }

  Outcome do_set_offset(const json& params) {
    auto p = rpc::check_set_offset_params(params);
    if (!p.ok()) return Outcome::fail(p.error);
    Vec3& o = config.gcode.work_offsets[static_cast<std::size_t>(p.value->index)];
    for (int i = 0; i < kAxes; ++i) {
      if (p.value->xyz[i]) o[static_cast<std::size_t>(i)] = *p.value->xyz[i];
    }
    spdlog::info("work offset {} set to X{} Y{} Z{} (used by programs started from now on)", rpc::work_offset_name(p.value->index), o[0],
                 o[1], o[2]);
    json r = rpc::vec3_to_json(o);
    r["offset"] = rpc::work_offset_name(p.value->index);
    return Outcome::ok(r);
  }

  // ---- jog ----
  Outcome do_jog(ClientId client, const json& id, RtLink& l, const Status& st, const json& params) {
    auto p = rpc::check_jog_params(params, config);
    if (!p.ok()) return Outcome::fail(p.error);
    const rpc::JogParams& jp = *p.value;
    const bool allowed = st.state == MachineState::kIdle || st.state == MachineState::kPaused || st.state == MachineState::kJogging;
    if (!allowed) {
      return Outcome::fail(refused(std::string("jog is refused while the machine is ") + to_string(st.state) +
                                   (st.state == MachineState::kRunning ? ": pause or stop the program first" : "")));
    }
    if (job_active.load() && st.state != MachineState::kPaused) {
      return Outcome::fail(refused("jog is refused while a program is starting or running"));
    }
    if (jog && jog->owner != client) return Outcome::fail(refused("another client's continuous jog is active"));
    const auto ax = static_cast<std::size_t>(jp.axis);
    const AxisConfig& ac = config.axes[ax];
    const double here = st.commanded[ax];
    const double dir = jp.continuous ? jp.direction : (jp.distance_mm > 0.0 ? 1.0 : -1.0);
    const double limit = dir > 0.0 ? ac.travel_max_mm : ac.travel_min_mm;
    json result = {{"axis", std::string(1, axis_name(jp.axis))},
                   {"mode", jp.continuous ? "continuous" : "incremental"},
                   {"feed", jp.feed_mm_min},
                   {"from", here}};
    if (jp.continuous) {
      result["direction"] = jp.direction > 0 ? "+" : "-";
    } else {
      result["distance"] = jp.distance_mm;
      const double target = here + jp.distance_mm;
      result["clamped"] = dir > 0.0 ? target > limit : target < limit;
      result["target"] = dir > 0.0 ? std::min(target, limit) : std::max(target, limit);
    }
    if (std::abs(here - limit) < 1e-9 && st.state != MachineState::kJogging) {
      // Already at the soft limit in this direction: nothing to move.
      result["clamped"] = true;
      result["target"] = limit;
      result["moved"] = false;
      result["note"] = std::string("axis ") + axis_name(jp.axis) + " is at its soft limit";
      return Outcome::ok(result);
    }
    Command c = command(jp.continuous ? CommandKind::kJogContinuous : CommandKind::kJogIncrement);
    c.axis = static_cast<std::uint8_t>(jp.axis);
    c.value = jp.continuous ? static_cast<double>(jp.direction) : jp.distance_mm;
    c.feed = jp.feed_mm_min / 60.0;
    const std::uint64_t cmd_id = l.send(c);
    if (cmd_id == 0) return Outcome::fail(rpc::Error{rpc::kMailboxFull, "pcnc-rt's command mailbox is full; try again", nullptr});
    result["command_id"] = cmd_id;
    if (jp.continuous) {
      const auto now = Clock::now();
      jog = ContinuousJog{client, now, now, now, cmd_id, false};
      result["deadman_s"] = config.process.jog_deadman_s;
    }
    pending_jogs.push_back(PendingJog{client, id, cmd_id, st.commanded, result, Clock::now() + std::chrono::milliseconds(1000)});
    return Outcome::later();
  }

  // Replies to jogs once the rt has taken (or ignored) them.
  void check_pending_jogs(const std::optional<Status>& st) {
    for (auto it = pending_jogs.begin(); it != pending_jogs.end();) {
      bool done = false;
      if (!st) {
        reply(it->client, it->id, Outcome::fail(rpc::Error{rpc::kRtUnavailable, "pcnc-rt was lost before it took the jog", nullptr}));
        done = true;
      } else if (st->last_command_id >= it->cmd_id) {
        if (st->state == MachineState::kJogging || st->commanded != it->before) {
          json r = it->result;
          r["moved"] = true;
          reply(it->client, it->id, Outcome::ok(r));
        } else {
          if (jog && jog->cmd_id == it->cmd_id) jog.reset();
          reply(it->client, it->id,
                Outcome::fail(refused(std::string("pcnc-rt did not start the jog (machine ") + to_string(st->state) + ")")));
        }
        done = true;
      } else if (Clock::now() > it->deadline) {
        reply(it->client, it->id, Outcome::fail(rpc::Error{rpc::kRtUnavailable, "pcnc-rt did not take the jog within 1 s", nullptr}));
        done = true;
      }
      it = done ? pending_jogs.erase(it) : std::next(it);
    }
  }

  Outcome do_jog_keepalive(ClientId client) {
    if (!jog || jog->owner != client) return Outcome::fail(refused("no continuous jog of this client is active"));
    jog->last_client = Clock::now();
    return Outcome::ok(json{{"ok", true}});
  }

  Outcome do_jog_stop(RtLink& l) {
    jog.reset();
    return sent(l, command(CommandKind::kJogStop), json{{"ok", true}});
  }

  void stop_continuous_jog(const char* why) {
    if (!jog) return;
    spdlog::info("continuous jog stopped: {}", why);
    if (auto l = current_link(); l && l->rt_alive()) l->send(command(CommandKind::kJogStop));
    broadcast_event(json{{"event", "jog_stopped"}, {"reason", why}});
    jog.reset();
  }

  void tick_jog(const std::optional<Status>& st) {
    if (!jog) return;
    if (!st) {
      jog.reset();
      return;
    }
    if (st->last_command_id >= jog->cmd_id) {
      if (st->state == MachineState::kJogging) {
        jog->seen_jogging = true;
      } else if (jog->seen_jogging || seconds_since(jog->started) > 1.0) {
        jog.reset();  // it ended on the rt (soft limit reached, stopped, refused)
        return;
      }
    }
    const double deadman = config.process.jog_deadman_s;
    if (seconds_since(jog->last_client) > deadman) {
      stop_continuous_jog("deadman: no keep-alive from the client within process.jog_deadman_s");
      return;
    }
    if (seconds_since(jog->last_rt) >= deadman / 4.0) {
      if (auto l = current_link()) l->send(command(CommandKind::kJogKeepAlive));
      jog->last_rt = Clock::now();
    }
  }

  // ---- run and resume ----
  bool start_worker(std::function<void()> fn) {
    if (job_active.load()) return false;
    if (worker.joinable()) worker.join();
    job_active = true;
    job_interrupt = false;
    worker = std::thread([this, fn = std::move(fn)] {
      try {
        fn();
      } catch (const std::exception& e) {
        spdlog::error("job worker: {}", e.what());
      }
      job_active = false;  // after an exception; normally end_job() already did
    });
    return true;
  }

  // The job is over as far as any client can tell: its record (the last job, when one ran)
  // and "not active" change together under job_mutex, before any reply or event says so, so
  // that a client's next run is never refused as "already running". A new worker may start
  // at once: start_worker() joins this thread first.
  void end_job(const json* last) {
    std::lock_guard<std::mutex> lock(job_mutex);
    if (last) last_job = *last;
    job_info = json::object();
    job_active = false;
  }

  Outcome do_run(ClientId client, const json& id, const json& params, std::shared_ptr<RtLink> l, const Status& st) {
    auto p = rpc::check_run_params(params);
    if (!p.ok()) return Outcome::fail(p.error);
    if (p.value->file.front() != '/') {
      return Outcome::fail(rpc::Error{rpc::kInvalidParams, "parameter 'file' of run must be an absolute path (the service's working "
                                                         "directory is not the client's); pcnc ctl run makes it absolute",
                                      nullptr});
    }
    if (job_active.load()) return Outcome::fail(refused("a program is already running; stop it first"));
    if (st.state != MachineState::kIdle) {
      std::string why = std::string("the machine is ") + to_string(st.state) + ", not IDLE";
      if (st.state == MachineState::kHostLost) why += ": resume or stop the program the lost host was running first";
      if (st.state == MachineState::kFault || st.state == MachineState::kEstop) why += ": reset first";
      return Outcome::fail(refused(why));
    }
    MachineConfig job_config = config;  // set_offset may change the service's copy meanwhile
    start_worker([this, client, id, rp = *p.value, l, job_config, start = st.commanded] {
      run_job(client, id, rp, l, job_config, start);
    });
    return Outcome::later();
  }

  void run_job(ClientId client, const json& id, const rpc::RunParams& rp, std::shared_ptr<RtLink> l, const MachineConfig& cfg,
               const Vec3& start) {
    JobOptions opts;
    opts.work_offset_index = rp.work_offset;
    opts.fit = rp.fit;
    opts.contouring = rp.contouring;
    opts.start_position = start;
    {
      std::lock_guard<std::mutex> lock(job_mutex);
      job_info = json{{"file", rp.file}, {"phase", "preflight"}};
    }
    CheckResult check = check_program(rp.file, cfg, opts);
    if (!check.ok) {
      std::size_t errors = 0;
      for (const auto& d : check.diagnostics) errors += d.severity == Diagnostic::Severity::kError;
      json data = {{"file", rp.file}, {"errors", diagnostics_json(check, Diagnostic::Severity::kError)}};
      spdlog::warn("run {} refused: preflight found {} error(s)", rp.file, errors);
      end_job(nullptr);  // no job ran
      post_reply(client, id,
                 Outcome::fail(rpc::Error{rpc::kPreflightFailed,
                                          rp.file + ": preflight found " + std::to_string(errors) + " error(s); nothing was moved",
                                          data}));
      return;
    }
    JobJournal jj;
    jj.file = rp.file;
    jj.work_offset = rp.work_offset;
    jj.work_offsets = cfg.gcode.work_offsets;
    jj.fit = rp.fit;
    jj.contouring = rp.contouring ? (*rp.contouring ? 1 : 0) : -1;
    jj.start_position = start;
    jj.host_pid = getpid();
    file_identity(rp.file, jj.file_size, jj.file_mtime_ns);
    std::string jerr;
    if (!write_journal(journal, jj, &jerr)) spdlog::warn("{}: a program interrupted by a host crash could not be resumed", jerr);

    json started = {{"started", true},
                    {"file", rp.file},
                    {"lines", check.lines},
                    {"moves", check.moves},
                    {"offset", rpc::vec3_to_json(check.transform.offset)},
                    {"scale", check.transform.scale},
                    {"warnings", diagnostics_json(check, Diagnostic::Severity::kWarning)}};
    follow_job(client, id, l, cfg, started, rp.file, [&](JobRunner& runner) { return runner.run(rp.file, opts, check, job_interrupt, progress_fn()); });
  }

  std::function<void(const JobProgress&)> progress_fn() {
    return [this](const JobProgress& p) {
      std::lock_guard<std::mutex> lock(job_mutex);
      job_info["lines_read"] = p.lines_read;
      job_info["bytes_read"] = p.bytes_read;
      job_info["total_bytes"] = p.total_bytes;
    };
  }

  // Runs a job to its end with replies, events, the last-job record and the journal.
  void follow_job(ClientId client, const json& id, std::shared_ptr<RtLink> l, const MachineConfig& cfg, json started,
                  const std::string& file, const std::function<JobResult(JobRunner&)>& body) {
    JobRunner runner(*l, cfg);
    bool replied = false;
    runner.set_on_started([&] {
      replied = true;
      {
        std::lock_guard<std::mutex> lock(job_mutex);
        job_info = json{{"file", file}, {"phase", "running"}};
      }
      spdlog::info("program {} started", file);
      post_reply(client, id, Outcome::ok(started));
      server->post([this, file] { broadcast_event(json{{"event", "program_started"}, {"file", file}}); });
    });
    const JobResult r = body(runner);
    const bool host_lost = r.final_status.state == MachineState::kHostLost;
    if (!host_lost) remove_journal(journal);  // before end_job: a next job writes its own
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
    if (!replied) post_reply(client, id, Outcome::fail(refused(r.message)));
    json ev = end;
    ev["event"] = "program_end";
    server->post([this, ev] { broadcast_event(ev); });
  }

  Outcome do_resume(ClientId client, const json& id, std::shared_ptr<RtLink> l, const Status& st) {
    if (st.state == MachineState::kPaused) return sent(*l, command(CommandKind::kResume), json{{"state", "RUNNING"}});
    if (st.state != MachineState::kHostLost) {
      return Outcome::fail(refused(std::string("nothing to resume: the machine is ") + to_string(st.state)));
    }
    if (job_active.load()) return Outcome::fail(refused("a program is already being resumed"));
    std::string why;
    auto jj = read_journal(journal, &why);
    if (!jj) {
      return Outcome::fail(refused("the machine is HOST_LOST but there is no record of the interrupted program (" + why +
                                   "); use stop or reset"));
    }
    MachineConfig job_config = config;
    job_config.gcode.work_offsets = jj->work_offsets;
    start_worker([this, client, id, l, job_config, j = *jj] { resume_job(client, id, l, job_config, j); });
    return Outcome::later();
  }

  void resume_job(ClientId client, const json& id, std::shared_ptr<RtLink> l, const MachineConfig& cfg, JobJournal jj) {
    auto fail = [&](std::string why) {
      spdlog::warn("resume refused: {}", why);
      end_job(nullptr);  // nothing runs
      post_reply(client, id, Outcome::fail(refused("cannot resume: " + why + "; use stop to abandon the program")));
    };
    std::uint64_t size = 0;
    std::int64_t mtime = 0;
    if (!file_identity(jj.file, size, mtime)) return fail(jj.file + " cannot be read any more");
    if (size != jj.file_size || mtime != jj.file_mtime_ns) return fail(jj.file + " changed since the program started");
    JobOptions opts;
    opts.work_offset_index = jj.work_offset;
    opts.fit = jj.fit;
    if (jj.contouring >= 0) opts.contouring = jj.contouring == 1;
    opts.start_position = jj.start_position;
    const CheckResult check = check_program(jj.file, cfg, opts);
    if (!check.ok) return fail(jj.file + " no longer passes preflight");

    const Status st = l->status();
    if (st.state != MachineState::kHostLost) return fail(std::string("the machine left HOST_LOST (now ") + to_string(st.state) + ")");
    // The program block the rt stood in (its seq in this run plus the blocks an earlier
    // resume skipped), and the machine position on it.
    const std::uint64_t k = st.block_seq == 0 ? jj.seq_base + 1 : st.block_seq + jj.seq_base;
    const Vec3 at = st.commanded;
    auto stream = std::make_shared<BlockStream>(jj.file, cfg, opts, check.transform);
    Block b{};
    for (std::uint64_t n = 0; n < k; ++n) {
      if (!stream->next(b)) return fail("the program has fewer blocks than where the machine stopped");
    }
    std::string why;
    const double tol = std::max(10.0 * cfg.motion.block_tolerance_mm, 0.005);
    auto cont = continue_block(b, at, cfg, tol, &why);
    if (!cont) return fail(why);
    // The continuation starts exactly where the machine stands.
    if (!cont->skip && b.kind != BlockKind::kDwell && b.kind != BlockKind::kEnd) cont->block.start = at;
    // Leave HOST_LOST (the rt keeps its position), then start the rest as a new program.
    const std::uint64_t reset_id = l->send(command(CommandKind::kReset));
    if (reset_id == 0) return fail("pcnc-rt's mailbox is full");
    for (int i = 0; i < 1000; ++i) {
      const Status s = l->status();
      if (s.last_command_id >= reset_id && s.state == MachineState::kIdle) break;
      if (!l->rt_alive()) return fail("pcnc-rt was lost");
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    jj.seq_base = cont->skip ? k : k - 1;
    jj.host_pid = getpid();
    std::string jerr;
    if (!write_journal(journal, jj, &jerr)) spdlog::warn("{}", jerr);
    spdlog::info("resuming {} at line {} (block {}) from X{:.4f} Y{:.4f} Z{:.4f}", jj.file, b.line, k, at[0], at[1], at[2]);

    auto first = std::make_shared<std::optional<Block>>();
    if (!cont->skip) *first = cont->block;
    BlockSource source;
    source.next = [stream, first](Block& out) {
      if (first->has_value()) {
        out = **first;
        first->reset();
        return true;
      }
      return stream->next(out);
    };
    source.progress = [stream] { return JobProgress{stream->lines_read(), stream->bytes_read(), stream->total_bytes(), Status{}}; };
    const bool contouring = jj.contouring >= 0 ? jj.contouring == 1 : cfg.motion.contouring_default;
    json started = {{"resumed", true}, {"file", jj.file}, {"line", b.line}, {"block", k}, {"from", rpc::vec3_to_json(at)}};
    follow_job(client, id, l, cfg, started, jj.file,
               [&](JobRunner& runner) { return runner.run_source(source, contouring, job_interrupt, progress_fn()); });
  }

  // ---- loop callbacks ----
  void on_tick() {
    auto l = current_link();
    std::optional<Status> st;
    if (l && l->rt_alive()) st = l->status();
    check_pending_jogs(st);
    tick_jog(st);
    if (subs.empty()) return;
    const auto now = Clock::now();
    std::optional<std::string> line;
    for (auto& [client, sub] : subs) {
      if (now < sub.next) continue;
      sub.next += std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(sub.period_s));
      if (sub.next < now) sub.next = now;
      if (!line) line = rpc::format_notification("status", status_json());
      server->send(client, *line);
    }
  }

  void on_disconnect(ClientId client) {
    subs.erase(client);
    if (jog && jog->owner == client) stop_continuous_jog("its client disconnected");
    for (auto& p : pending_jogs) {
      if (p.client == client) p.client = 0;  // reply goes nowhere
    }
  }

  MachineConfig config;
  ServiceOptions opt;
  std::string journal;
  std::unique_ptr<ControlServer> server;

  std::mutex link_mutex;  // guards link, rt_state, rt_message, rt_pid
  std::shared_ptr<RtLink> link;
  std::string rt_state = "waiting";
  std::string rt_message = "no pcnc-rt attached yet";
  int rt_pid = 0;
  std::thread monitor;
  std::atomic<bool> monitor_stop{false};

  std::thread worker;
  std::atomic<bool> job_active{false};
  std::atomic<bool> job_interrupt{false};
  std::mutex job_mutex;  // guards job_info, last_job
  json job_info = json::object();
  json last_job = nullptr;

  // loop thread only
  std::map<ClientId, Subscription> subs;
  std::optional<ContinuousJog> jog;
  std::vector<PendingJog> pending_jogs;
};

Service::Service(const MachineConfig& config, ServiceOptions options) : impl_(std::make_unique<Impl>(config, options)) {}

Service::~Service() = default;

void Service::run(const std::atomic<bool>& stop) {
  Impl& s = *impl_;
  ServerHandlers h;
  h.on_line = [&s](ClientId c, std::string_view line) { s.on_line(c, line); };
  h.on_disconnect = [&s](ClientId c) { s.on_disconnect(c); };
  h.on_tick = [&s] { s.on_tick(); };
  h.too_long_reply = [](std::size_t limit) {
    return rpc::format_error(nullptr, rpc::Error{rpc::kLineTooLong,
                                                 "request line longer than " + std::to_string(limit) + " bytes; closing the connection",
                                                 nullptr});
  };
  h.refused_reply = [](uid_t uid) {
    return rpc::format_error(nullptr, rpc::Error{rpc::kPermissionDenied,
                                                 "permission denied: uid " + std::to_string(uid) + " may not use this control socket",
                                                 nullptr});
  };
  s.server = std::make_unique<ControlServer>(s.config.process.socket_path, s.config.process.socket_mode, s.opt.limits, h);
  spdlog::info("serving the control socket {} (mode {:04o})", s.config.process.socket_path, s.config.process.socket_mode);
  s.monitor = std::thread([&s] { s.monitor_loop(); });
  s.server->run(stop, s.opt.tick_s);

  spdlog::info("shutting down the service");
  if (s.job_active.load()) s.job_interrupt = true;  // a running program is stopped along the path
  if (s.jog) s.stop_continuous_jog("the service is shutting down");
  if (s.worker.joinable()) s.worker.join();
  s.monitor_stop = true;
  if (s.monitor.joinable()) s.monitor.join();
  s.server.reset();
  std::lock_guard<std::mutex> lock(s.link_mutex);
  s.link.reset();
}

}  // namespace pcnc
