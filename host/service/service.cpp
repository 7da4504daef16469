// service.cpp — the operator service: builds its parts and wires them to the loop (see
// service.hpp and host/service/README.md). Each part has its own file:
//
//   control_server  the socket: clients, lines in and out, the loop thread
//   dispatch        a request line to its reply, through the table of methods (methods.cpp)
//   rt_monitor      attaching to pcnc-rt, noticing its loss, re-attaching
//   job_control     run and resume in a worker, the job record, the journal
//   jog_control     jogs, their replies, the continuous jog's deadman
//   subscriptions   status pushes and events for subscribed clients
//
// Everything a part reports from another thread (the rt monitor, the job worker) reaches
// the clients through ControlServer::post, on the loop thread.
#include "service/service.hpp"

#include <spdlog/spdlog.h>

#include <optional>
#include <string>

#include "service/dispatch.hpp"
#include "service/job_control.hpp"
#include "service/job_journal.hpp"
#include "service/jog_control.hpp"
#include "service/methods.hpp"
#include "service/rt_monitor.hpp"
#include "service/subscriptions.hpp"

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
        jobs(journal_path(c.process.socket_path),
             JobNotices{[this](ClientId client, json id, Outcome o) { post_reply(client, std::move(id), std::move(o)); },
                        [this](json event) { post_event(std::move(event)); }}),
        jogs(config, rt, [this](ClientId client, const json& id, const Outcome& o) { reply(client, id, o); },
             [this](const json& event) { subs.broadcast_event(event); }),
        parts{config, rt, jobs, jogs, subs},
        dispatcher(method_table(parts), rt) {}

  // ---- loop thread ----
  void reply(ClientId client, const json& id, const Outcome& o) {
    const std::string line = format_outcome(id, o);
    if (!line.empty()) server->send(client, line);
  }

  void on_line(ClientId client, std::string_view line) {
    const std::string r = dispatcher.handle(client, line);
    if (!r.empty()) server->send(client, r);
  }

  void on_tick() {
    std::optional<Status> st;
    if (auto l = rt.current(); l && l->rt_alive()) st = l->status();
    jogs.tick(st);
    subs.tick([this] { return status_object(parts); });
  }

  void on_disconnect(ClientId client) {
    subs.remove(client);
    jogs.client_gone(client);
  }

  // ---- any thread: delivered on the loop thread ----
  void post_reply(ClientId client, json id, Outcome o) {
    server->post([this, client, id = std::move(id), o = std::move(o)] { reply(client, id, o); });
  }

  void post_event(json event) {
    server->post([this, event = std::move(event)] { subs.broadcast_event(event); });
  }

  // Construction order is the order of dependence; destruction runs backwards, so the job
  // worker (the last holder of an rt link besides the monitor) ends before the monitor goes.
  MachineConfig config;  // the service's: set_offset changes its work offsets (loop thread)
  ServiceOptions opt;
  std::unique_ptr<ControlServer> server;  // created by run()
  RtMonitor rt;
  Subscriptions subs;
  JobControl jobs;
  JogControl jogs;
  ServiceParts parts;
  Dispatcher dispatcher;
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
  s.rt.start();
  s.server->run(stop, s.opt.tick_s);

  spdlog::info("shutting down the service");
  s.jobs.interrupt();  // a running program is stopped along the path
  s.jogs.stop_continuous("the service is shutting down");
  s.jobs.join();
  s.rt.stop();
  s.server.reset();
  s.rt.release();
}

}  // namespace pcnc
