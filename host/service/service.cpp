// service.cpp — the operator service: builds its parts and wires them to the loop (see
// service.hpp and host/service/README.md). Each part has its own file:
//
//   control_server  the socket: clients, lines in and out, the loop thread
//   dispatch        a request line to its reply, through the table of methods (methods.cpp)
//   rt_monitor      attaching to pcnc-rt, noticing its loss, re-attaching
//   job_control     run and resume in a worker, the job record, the journal
//   jog_control     jogs, their replies, the continuous jog's deadman
//   subscriptions   status pushes and events for subscribed clients
//   work_store      the work-coordinate state (G54..G59.3): its file, set_offset
//   capture_control the scope: captures of the rt's per-cycle samples
//
// Everything a part reports from another thread (the rt monitor, the job worker) reaches
// the clients through ControlServer::post, on the loop thread.
#include "service/service.hpp"

#include <spdlog/spdlog.h>
#include <unistd.h>

#include <map>
#include <optional>
#include <string>

#include "config/runtime_paths.hpp"
#include "service/dispatch.hpp"
#include "service/job_control.hpp"
#include "service/job_journal.hpp"
#include "service/jog_control.hpp"
#include "service/methods.hpp"
#include "service/rt_monitor.hpp"
#include "service/subscriptions.hpp"
#include "service/work_store.hpp"

namespace pcnc {

using rpc::json;

struct Service::Impl {
  Impl(const MachineConfig& c, ServiceOptions o)
      : config(c),
        opt(o),
        rt(c, o.monitor_period_s, o.attach_retry_s,
           RtMonitorEvents{[this](int pid, const Status& st) {
                             post_event(json{{"event", "rt_attached"}, {"pid", pid}, {"state", to_string(st.state)}});
                           },
                           [this](const std::string& why, double age_ms) {
                             post_event(json{{"event", "rt_lost"}, {"message", why}, {"heartbeat_age_ms", age_ms}});
                           }}),
        subs([this](ClientId client, std::string_view line) { server->send(client, line); }),
        work(work_state_path(c), default_work_state(c)),
        jobs(journal_path(state_dir(c)),
             JobNotices{[this](ClientId client, json id, Outcome o) { post_reply(client, std::move(id), std::move(o)); },
                        [this](json event) { post_event(std::move(event)); },
                        [this](WorkState before, WorkState after, std::function<void()> applied) {
                          post_work(std::move(before), std::move(after), std::move(applied));
                        }}),
        jogs(config, rt, [this](ClientId client, const json& id, const Outcome& o) { reply(client, id, o); },
             [this](const json& event) { subs.broadcast_event(event); }),
        captures(c.motion.cycle_hz,
                 [this](ClientId client, json id, Outcome o) { post_reply(client, std::move(id), std::move(o)); }),
        parts{config, work, rt, jobs, jogs, subs, &captures},
        dispatcher(method_table(parts), rt) {}

  // ---- loop thread ----
  void reply(ClientId client, const json& id, const Outcome& o) {
    if (auto it = awaiting.find(client); it != awaiting.end() && it->second > 0 && --it->second == 0) awaiting.erase(it);
    const std::string line = format_outcome(id, o);
    if (!line.empty()) server->send(client, line);
  }

  void on_line(ClientId client, std::string_view line) {
    const std::string r = dispatcher.handle(client, line);
    if (r.empty()) {
      ++awaiting[client];  // its reply comes later: the client is not idle meanwhile
    } else {
      server->send(client, r);
    }
  }

  bool busy(ClientId client) const { return subs.has(client) || awaiting.count(client) != 0; }

  void on_tick() {
    std::optional<Status> st;
    if (auto l = rt.current(); l && l->rt_alive()) st = l->status();
    jogs.tick(st);
    subs.tick([this] { return status_object(parts); });
  }

  void on_disconnect(ClientId client) {
    awaiting.erase(client);
    subs.remove(client);
    jogs.client_gone(client);
    captures.client_gone(client);
  }

  // ---- any thread: delivered on the loop thread ----
  void post_reply(ClientId client, json id, Outcome o) {
    server->post([this, client, id = std::move(id), o = std::move(o)] { reply(client, id, o); });
  }

  void post_event(json event) {
    server->post([this, event = std::move(event)] { subs.broadcast_event(event); });
  }

  // What a program or MDI changed (G10, G92...) goes into the service's work state and is
  // saved; what set_offset changed meanwhile stays (merge_work_change).
  void post_work(WorkState before, WorkState after, std::function<void()> applied) {
    server->post([this, before, after, applied = std::move(applied)] {
      const WorkState next = merge_work_change(work.state(), before, after);
      if (!(next == work.state())) {
        if (auto error = work.replace(next)) {
          spdlog::error("the work offsets the program left were not saved: {}", *error);
        } else {
          spdlog::info("work offsets as the program left them saved in {}", work.path().empty() ? "memory only" : work.path());
        }
      }
      if (applied) applied();
    });
  }

  // Construction order is the order of dependence; destruction runs backwards, so the job
  // worker (the last holder of an rt link besides the monitor) ends before the monitor goes.
  const MachineConfig config;  // the service's; its gcode.g54..g59 are only the work state's defaults
  ServiceOptions opt;
  std::unique_ptr<ControlServer> server;  // created by run()
  RtMonitor rt;
  Subscriptions subs;
  WorkStore work;  // G54..G59.3 and the rest (loop thread): loaded in run(), changed by set_offset
  JobControl jobs;
  JogControl jogs;
  CaptureControl captures;  // the scope: capture threads reading the rt's sample ring
  ServiceParts parts;
  Dispatcher dispatcher;
  std::map<ClientId, int> awaiting;  // delayed replies (run, resume, jog) not yet sent, per client (loop thread)
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
  h.busy = [&s](ClientId c) { return s.busy(c); };
  h.reserve_allows = [](std::string_view line) { return Dispatcher::always_answered(line); };
  h.full_reply = [](std::size_t max_clients) {
    return rpc::format_error(nullptr, rpc::Error{rpc::kServerFull,
                                                 std::to_string(max_clients) +
                                                     " clients are connected: only stop, estop and status are served on a new "
                                                     "connection now; closing it",
                                                 nullptr});
  };
  h.idle_reply = [](double idle_s) {
    return rpc::format_error(nullptr, rpc::Error{rpc::kIdleTimeout,
                                                 "no request for " + std::to_string(static_cast<long>(idle_s)) +
                                                     " s (process.client_idle_timeout_s); closing the connection",
                                                 nullptr});
  };
  h.refused_reply = [](uid_t uid) {
    return rpc::format_error(nullptr, rpc::Error{rpc::kPermissionDenied,
                                                 "permission denied: uid " + std::to_string(uid) + " may not use this control socket",
                                                 nullptr});
  };
  // Runtime files only in directories another user cannot write to (issue 19): the default
  // socket in the runtime directory we create (0750, the socket group), a configured socket
  // path after checking its directory, the journal in the private state directory (0700).
  const std::string socket = control_socket_path(s.config);
  const gid_t group = socket_group_gid(s.config);
  if (s.config.process.socket_path.empty()) {
    ensure_private_dir(default_runtime_dir(s.config), 0750, group == static_cast<gid_t>(-1) ? getegid() : group);
  } else {
    check_socket_dir(socket);
  }
  ensure_private_dir(state_dir(s.config), 0700);
  // The work offsets the operator set survive a restart; a file that cannot be trusted stops
  // the start here (never zeros in its place).
  try {
    s.work.load(s.config);
  } catch (const WorkStateError& e) {
    throw WorkStateError(std::string(e.what()) + "; the service does not start (fix the file, or remove it to start from the "
                                                 "config's gcode.g54..g59)");
  }
  const Vec3& g54 = s.work.state().g5x[0];
  spdlog::info("work offsets: {} (G54 X{} Y{} Z{}; {} selected)", s.work.path(), g54[0], g54[1], g54[2],
               work_system_name(s.work.state().active));
  ServerLimits limits = s.opt.limits;
  limits.idle_timeout_s = s.config.process.client_idle_timeout_s;
  s.server = std::make_unique<ControlServer>(socket, s.config.process.socket_mode, group, limits, h);
  spdlog::info("serving the control socket {} (mode {:04o}); journal and work offsets in {}", socket,
               s.config.process.socket_mode, state_dir(s.config));
  s.rt.start();
  s.server->run(stop, s.opt.tick_s);

  spdlog::info("shutting down the service");
  s.jobs.interrupt();  // a running program is stopped along the path
  s.jogs.stop_continuous("the service is shutting down");
  s.jobs.join();
  s.captures.cancel_all();  // before the server goes: a capture thread posts its reply through it
  s.rt.stop();
  s.server.reset();
  s.rt.release();
}

}  // namespace pcnc
