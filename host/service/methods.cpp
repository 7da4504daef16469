// methods.cpp — the method table and the handlers that need no part of their own (see
// methods.hpp).
#include "service/methods.hpp"

#include <spdlog/spdlog.h>

#include <cstdio>
#include <string>

#include "service/scope_signals.hpp"

namespace pcnc {

using rpc::json;

namespace {

// The reply to a command sent to the rt (`id` from RtLink::send): the result with the
// command's id, or "mailbox full".
Outcome sent(std::uint64_t id, json result) {
  if (id == 0) return Outcome::fail(mailbox_full());
  result["command_id"] = id;
  return Outcome::ok(std::move(result));
}

template <typename C>
Outcome sent(RtLink& l, C command, json result) {
  return sent(l.send(command), std::move(result));
}

// run's parameters, and a file path the service can use (its working directory is not the
// client's).
rpc::Checked<rpc::RunParams> check_run(const json& params) {
  auto p = rpc::check_run_params(params);
  if (p.ok() && p.value->file.front() != '/') {
    p.value.reset();
    p.error = rpc::Error{rpc::kInvalidParams, "parameter 'file' of run must be an absolute path (the service's working "
                                              "directory is not the client's); pcnc ctl run makes it absolute",
                         nullptr};
  }
  // Only a regular file is run: a FIFO, /dev/zero or a directory is refused here, on the
  // loop thread, without reading (the open does not block), before a job starts.
  if (p.ok()) {
    if (const std::string why = program_file_problem(p.value->file); !why.empty()) {
      p.value.reset();
      p.error = rpc::Error{rpc::kInvalidParams, "parameter 'file' of run: " + why, nullptr};
    }
  }
  return p;
}

Outcome do_pause(Call& c) {
  const MachineState s = c.status.state;
  if (s == MachineState::kRunning) return sent(*c.link, CommandKind::kPause, json{{"state", "PAUSED"}});
  if (s == MachineState::kJogging) return sent(*c.link, CommandKind::kJogStop, json{{"state", "IDLE"}});
  return Outcome::fail(refused(std::string("nothing to pause: the machine is ") + to_string(s)));
}

Outcome do_stop(Call& c, JobControl& jobs, JogControl& jogs) {
  RtLink& l = *c.link;
  const Status& st = c.status;
  switch (st.state) {
    case MachineState::kRunning:
    case MachineState::kPaused:
    case MachineState::kStopping:
      jobs.interrupt();  // the worker stops feeding; the rt decelerates on the path
      return sent(l, CommandKind::kStop, json{{"state", "STOPPING"}});
    case MachineState::kJogging:
      jogs.forget();
      if (st.program_active) {
        // a jog while the program is paused: stop ends the jog and the program (the rt
        // flushes it and takes up where the machine stands)
        jobs.interrupt();
        return sent(l, CommandKind::kStop, json{{"state", "STOPPING"}});
      }
      return sent(l, CommandKind::kJogStop, json{{"state", "IDLE"}});
    case MachineState::kHostLost:
      // The interrupted program is abandoned: leave HOST_LOST, forget the journal. A resume
      // still being checked or located ends there and never starts (job_control.cpp).
      if (jobs.active()) jobs.interrupt();
      jobs.abandon_interrupted();
      spdlog::info("stop: the program interrupted by the lost host is abandoned");
      return sent(l, CommandKind::kReset, json{{"state", "IDLE"}, {"abandoned", true}});
    default:
      if (jobs.active()) {
        jobs.interrupt();
        return Outcome::ok(json{{"state", to_string(st.state)}, {"note", "the program was stopped before it started"}});
      }
      return Outcome::ok(json{{"state", to_string(st.state)}, {"note", "nothing was moving"}});
  }
}

Outcome do_reset(Call& c, JobControl& jobs) {
  const MachineState s = c.status.state;
  if (s != MachineState::kFault && s != MachineState::kEstop && s != MachineState::kHostLost) {
    return Outcome::fail(refused(std::string("nothing to reset: the machine is ") + to_string(s) +
                                 " (reset leaves FAULT, ESTOP or HOST_LOST)"));
  }
  if (s == MachineState::kHostLost) jobs.abandon_interrupted();
  return sent(*c.link, CommandKind::kReset, json{{"state", "IDLE"}, {"was", to_string(s)}});
}

Outcome do_set_offset(WorkStore& work, const rpc::SetOffsetParams& p) {
  if (auto error = work.set_g5x(p.index, p.xyz)) {
    spdlog::error("set_offset {}: {}", rpc::work_offset_name(p.index), *error);
    return Outcome::fail(rpc::Error{rpc::kInternalError, "the work offset was not changed: " + *error, nullptr});
  }
  const Vec3& o = work.state().g5x[static_cast<std::size_t>(p.index)];
  spdlog::info("work offset {} set to X{} Y{} Z{} (used by programs started from now on; saved in {})",
               rpc::work_offset_name(p.index), o[0], o[1], o[2], work.path().empty() ? "memory only" : work.path());
  json r = rpc::vec3_to_json(o);
  r["offset"] = rpc::work_offset_name(p.index);
  return Outcome::ok(r);
}

// touch_off: refused while anything moves or a program is under way (the position it reads
// must stand still, and a running program keeps the offsets it started with).
Outcome do_touch_off(Call& c, WorkStore& work, const JobControl& jobs, const rpc::TouchOffParams& p) {
  const MachineState s = c.status.state;
  if (jobs.active() || s != MachineState::kIdle) {
    return Outcome::fail(refused(std::string("touch_off needs the machine IDLE with no program under way; it is ") + to_string(s) +
                                 (jobs.active() ? " running a program" : "")));
  }
  const Vec3 at = c.status.commanded;
  const std::string system = rpc::work_offset_name(work.state().active);
  if (auto error = work.touch_off(p.axis, p.value, at)) {
    spdlog::error("touch_off {}: {}", system, *error);
    return Outcome::fail(rpc::Error{rpc::kInternalError, "the work offset was not changed: " + *error, nullptr});
  }
  const WorkState& w = work.state();
  const Vec3& o = w.g5x[static_cast<std::size_t>(w.active)];
  const char axis = "XYZ"[p.axis];
  spdlog::info("touch-off {} {} = {}: {} is now X{} Y{} Z{} (saved in {})", axis, p.value, at[static_cast<std::size_t>(p.axis)],
               system, o[0], o[1], o[2], work.path().empty() ? "memory only" : work.path());
  json r = rpc::vec3_to_json(o);
  r["offset"] = system;
  r["axis"] = std::string(1, axis);
  r["value"] = p.value;
  r["machine"] = rpc::vec3_to_json(at);
  r["work_position"] = rpc::vec3_to_json(work_position(w, at));
  return Outcome::ok(r);
}

}  // namespace

std::vector<Method> method_table(ServiceParts parts) {
  // Each handler holds a copy of `parts` (references to the service's parts, which outlive
  // the table).
  const ServiceParts s = parts;
  constexpr bool kParams = true, kNoParams = false, kRt = true, kNoRt = false;
  return {
      {"status", kNoParams, kNoRt, [s](Call&) { return Outcome::ok(status_object(s)); }},
      {"run", kParams, kRt,
       with_params(check_run,
                   [s](Call& c, const rpc::RunParams& p) {
                     return s.jobs.run(c.client, c.id, p, c.link, c.status, s.config, s.work.state());
                   })},
      {"pause", kNoParams, kRt, do_pause},
      {"resume", kNoParams, kRt,
       [s](Call& c) {
         if (c.status.state == MachineState::kPaused) return sent(*c.link, CommandKind::kResume, json{{"state", "RUNNING"}});
         return s.jobs.resume(c.client, c.id, c.link, c.status, s.config);  // the program a lost host ran
       }},
      {"stop", kNoParams, kRt, [s](Call& c) { return do_stop(c, s.jobs, s.jogs); }},
      {"estop", kNoParams, kRt,
       [s](Call& c) {
         s.jogs.forget();
         s.jobs.interrupt();
         spdlog::warn("e-stop requested over the control socket");
         return sent(*c.link, CommandKind::kEstop, json{{"state", "ESTOP"}});
       }},
      {"reset", kNoParams, kRt, [s](Call& c) { return do_reset(c, s.jobs); }},
      {"override", kParams, kRt,
       with_params(rpc::check_override_params,
                   [](Call& c, const rpc::OverrideParams& p) {
                     Command cmd;
                     cmd.kind = CommandKind::kFeedOverride;
                     cmd.value = p.percent / 100.0;
                     return sent(*c.link, cmd, json{{"percent", p.percent}});
                   })},
      {"jog", kParams, kRt,
       with_params([s](const json& params) { return rpc::check_jog_params(params, s.config); },
                   [s](Call& c, const rpc::JogParams& p) {
                     return s.jogs.start(c.client, c.id, *c.link, c.status, p, s.jobs.active());
                   })},
      {"jog_keepalive", kNoParams, kNoRt, [s](Call& c) { return s.jogs.keepalive(c.client); }},
      {"jog_stop", kNoParams, kRt,
       [s](Call& c) {
         s.jogs.forget();
         return sent(*c.link, CommandKind::kJogStop, json{{"ok", true}});
       }},
      {"set_offset", kParams, kNoRt,
       with_params(rpc::check_set_offset_params, [s](Call&, const rpc::SetOffsetParams& p) { return do_set_offset(s.work, p); })},
      {"mdi", kParams, kRt,
       with_params(rpc::check_mdi_params,
                   [s](Call& c, const rpc::MdiParams& p) {
                     return s.jobs.mdi(c.client, c.id, p.text, c.link, c.status, s.config, s.work.state());
                   })},
      {"touch_off", kParams, kRt,
       with_params(rpc::check_touch_off_params,
                   [s](Call& c, const rpc::TouchOffParams& p) { return do_touch_off(c, s.work, s.jobs, p); })},
      {"subscribe", kParams, kNoRt,
       with_params(rpc::check_subscribe_params,
                   [s](Call& c, const rpc::SubscribeParams& p) {
                     s.subs.subscribe(c.client, p.rate_hz);
                     return Outcome::ok(p.rate_hz <= 0.0 ? json{{"rate_hz", 0}} : json{{"rate_hz", p.rate_hz}});
                   })},
      {"capture", kParams, kRt,
       with_params([s](const json& params) { return check_capture_params(params, s.config.motion.cycle_hz); },
                   [s](Call& c, const CaptureParams& p) {
                     if (!s.captures) return Outcome::fail(refused("capture is not available in this service"));
                     return s.captures->start(c.client, c.id, c.link, c.status, p);
                   })},
      // the grbl port's streamed program (stream_job.cpp, docs/grbl-protocol.md)
      {"stream_open", kParams, kRt,
       with_params(rpc::check_stream_open_params,
                   [s](Call& c, const rpc::StreamOpenParams& p) {
                     return s.jobs.stream_open(c.client, c.id, p.check, c.link, c.status, s.config, s.work.state());
                   })},
      {"stream_lines", kParams, kNoRt,
       with_params(rpc::check_stream_lines_params, [s](Call&, const rpc::StreamLinesParams& p) { return s.jobs.stream_lines(p.text); })},
      {"stream_close", kNoParams, kNoRt, [s](Call&) { return s.jobs.stream_close(); }},
      {"probe", kParams, kRt,
       with_params(rpc::check_probe_params,
                   [s](Call& c, const rpc::ProbeParams& p) {
                     // one G38.x move, incremental, as an MDI (docs/probe.md): by default to the
                     // end of the travel in that direction
                     const AxisConfig& ax = s.config.axes[static_cast<std::size_t>(p.axis)];
                     const double at = c.status.commanded[static_cast<std::size_t>(p.axis)];
                     const double room = p.direction < 0 ? at - ax.travel_min_mm : ax.travel_max_mm - at;
                     const double d = p.distance_mm.value_or(room);
                     char text[160];
                     std::snprintf(text, sizeof text, "G21 G91 G38.%d %c%.6f F%.6f\n", p.code - 380, axis_name(p.axis),
                                   p.direction * d, p.feed_mm_min);
                     return s.jobs.mdi(c.client, c.id, text, c.link, c.status, s.config, s.work.state());
                   })},
  };
}

json status_object(const ServiceParts& parts) {
  json j = json::object();
  auto l = parts.rt.current();
  std::optional<Status> st;
  if (l && l->rt_alive()) {
    st = l->status();
    j = rpc::status_to_json(*st);
  } else {
    j["state"] = "NO_RT";
  }
  const RtLinkState rs = parts.rt.state();
  json rt = {{"state", rs.state}, {"message", rs.message}, {"pid", rs.pid}};
  if (l) rt["heartbeat_age_ms"] = l->rt_heartbeat_age_s() * 1000.0;
  j["rt"] = rt;
  parts.jobs.describe(j, st);
  const WorkState& w = parts.work.state();
  json offsets = json::object();
  for (int i = 0; i < kWorkSystems; ++i) offsets[rpc::work_offset_name(i)] = rpc::vec3_to_json(w.g5x[static_cast<std::size_t>(i)]);
  j["work_offsets"] = offsets;
  j["work_state"] = json{{"active", rpc::work_offset_name(w.active)},
                         {"G92", rpc::vec3_to_json(w.g92)},
                         {"G92_applied", w.g92_applied},
                         {"G28", rpc::vec3_to_json(w.g28)},
                         {"G30", rpc::vec3_to_json(w.g30)},
                         {"tool", w.tool},
                         {"tool_offset_applied", w.tool_offset_applied},
                         {"tool_offset", rpc::vec3_to_json(w.tool_offset)},
                         {"file", parts.work.path().empty() ? json(nullptr) : json(parts.work.path())}};
  // Work coordinates of the positions (machine - the active G5x - the applied G92 - the tool
  // length offset in effect): what a program started now would read (a running program keeps
  // the offsets it started with, and its own tool).
  if (st) {
    j["work_position"] = json{{"commanded", rpc::vec3_to_json(work_position(w, st->commanded))},
                              {"actual", rpc::vec3_to_json(work_position(w, st->actual))}};
  }
  j["jog"] = json{{"continuous", parts.jogs.continuous_active()}};
  return j;
}

}  // namespace pcnc
