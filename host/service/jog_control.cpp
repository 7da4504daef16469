// jog_control.cpp — jogs, their delayed replies, the continuous jog's keep-alive and deadman
// (see jog_control.hpp).
#include "service/jog_control.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace pcnc {

using rpc::json;

namespace {
double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}
}  // namespace

JogControl::JogControl(const MachineConfig& config, RtMonitor& rt, Reply reply, Event event)
    : config_(config), rt_(rt), reply_(std::move(reply)), event_(std::move(event)) {}

Outcome JogControl::start(ClientId client, const json& id, RtLink& link, const Status& st, const rpc::JogParams& jp,
                          bool job_active) {
  const bool allowed = st.state == MachineState::kIdle || st.state == MachineState::kPaused || st.state == MachineState::kJogging;
  if (!allowed) {
    return Outcome::fail(refused(std::string("jog is refused while the machine is ") + to_string(st.state) +
                                 (st.state == MachineState::kRunning ? ": pause or stop the program first" : "")));
  }
  if (job_active && st.state != MachineState::kPaused) {
    return Outcome::fail(refused("jog is refused while a program is starting or running"));
  }
  if (jog_ && jog_->owner != client) return Outcome::fail(refused("another client's continuous jog is active"));
  const bool rotary = jp.axis >= kAxes;  // a rotary joint: degrees here, rad in the command
  if (rotary && st.state != MachineState::kIdle && st.state != MachineState::kJogging) {
    return Outcome::fail(refused("a rotary joint jogs only when the machine is idle"));
  }
  const auto ax = static_cast<std::size_t>(rotary ? jp.axis - kAxes : jp.axis);
  double here = 0.0, lo = 0.0, hi = 0.0;
  if (rotary) {
    const RotaryAxisConfig& rc = *config_.rotary[ax];
    here = st.rot_commanded[ax] * kDegPerRad;
    lo = rc.continuous ? -1e12 : rc.travel_min_rad * kDegPerRad;
    hi = rc.continuous ? 1e12 : rc.travel_max_rad * kDegPerRad;
  } else {
    here = st.commanded[ax];
    lo = config_.axes[ax].travel_min_mm;
    hi = config_.axes[ax].travel_max_mm;
  }
  const double dir = jp.continuous ? jp.direction : (jp.distance_mm > 0.0 ? 1.0 : -1.0);
  const double limit = dir > 0.0 ? hi : lo;
  const char name = rotary ? joint_letter(jp.axis - kAxes) : axis_name(jp.axis);
  json result = {{"axis", std::string(1, name)},
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
    result["note"] = std::string("axis ") + name + " is at its soft limit";
    return Outcome::ok(result);
  }
  Command c;
  c.kind = jp.continuous ? CommandKind::kJogContinuous : CommandKind::kJogIncrement;
  c.axis = static_cast<std::uint8_t>(jp.axis);
  c.value = jp.continuous ? static_cast<double>(jp.direction) : jp.distance_mm * (rotary ? kRadPerDeg : 1.0);
  c.feed = jp.feed_mm_min / 60.0 * (rotary ? kRadPerDeg : 1.0);
  const std::uint64_t cmd_id = link.send(c);
  if (cmd_id == 0) return Outcome::fail(mailbox_full());
  result["command_id"] = cmd_id;
  if (jp.continuous) {
    const auto now = Clock::now();
    jog_ = ContinuousJog{client, now, now, now, cmd_id, false};
    result["deadman_s"] = config_.process.jog_deadman_s;
  }
  pending_.push_back(
      PendingJog{client, id, cmd_id, st.commanded, result, Clock::now() + std::chrono::milliseconds(1000), st.rot_commanded});
  return Outcome::later();
}

Outcome JogControl::keepalive(ClientId client) {
  if (!jog_ || jog_->owner != client) return Outcome::fail(refused("no continuous jog of this client is active"));
  jog_->last_client = Clock::now();
  return Outcome::ok(json{{"ok", true}});
}

void JogControl::stop_continuous(const char* why) {
  if (!jog_) return;
  spdlog::info("continuous jog stopped: {}", why);
  if (auto l = rt_.current(); l && l->rt_alive()) l->send(CommandKind::kJogStop);
  event_(json{{"event", "jog_stopped"}, {"reason", why}});
  jog_.reset();
}

void JogControl::tick(const std::optional<Status>& st) {
  check_pending(st);
  tick_continuous(st);
}

void JogControl::client_gone(ClientId client) {
  if (jog_ && jog_->owner == client) stop_continuous("its client disconnected");
  for (auto& p : pending_) {
    if (p.client == client) p.client = 0;  // reply goes nowhere
  }
}

// Replies to jogs once the rt has taken (or ignored) them.
void JogControl::check_pending(const std::optional<Status>& st) {
  for (auto it = pending_.begin(); it != pending_.end();) {
    bool done = false;
    if (!st) {
      reply_(it->client, it->id, Outcome::fail(rpc::Error{rpc::kRtUnavailable, "pcnc-rt was lost before it took the jog", nullptr}));
      done = true;
    } else if (st->last_command_id >= it->cmd_id) {
      if (st->state == MachineState::kJogging || st->commanded != it->before || st->rot_commanded != it->before_rot) {
        json r = it->result;
        r["moved"] = true;
        reply_(it->client, it->id, Outcome::ok(r));
      } else {
        if (jog_ && jog_->cmd_id == it->cmd_id) jog_.reset();
        reply_(it->client, it->id,
               Outcome::fail(refused(std::string("pcnc-rt did not start the jog (machine ") + to_string(st->state) + ")")));
      }
      done = true;
    } else if (Clock::now() > it->deadline) {
      reply_(it->client, it->id, Outcome::fail(rpc::Error{rpc::kRtUnavailable, "pcnc-rt did not take the jog within 1 s", nullptr}));
      done = true;
    }
    it = done ? pending_.erase(it) : std::next(it);
  }
}

void JogControl::tick_continuous(const std::optional<Status>& st) {
  if (!jog_) return;
  if (!st) {
    jog_.reset();
    return;
  }
  if (st->last_command_id >= jog_->cmd_id) {
    if (st->state == MachineState::kJogging) {
      jog_->seen_jogging = true;
    } else if (jog_->seen_jogging || seconds_since(jog_->started) > 1.0) {
      jog_.reset();  // it ended on the rt (soft limit reached, stopped, refused)
      return;
    }
  }
  const double deadman = config_.process.jog_deadman_s;
  if (seconds_since(jog_->last_client) > deadman) {
    stop_continuous("deadman: no keep-alive from the client within process.jog_deadman_s");
    return;
  }
  if (seconds_since(jog_->last_rt) >= deadman / 4.0) {
    if (auto l = rt_.current()) l->send(CommandKind::kJogKeepAlive);
    jog_->last_rt = Clock::now();
  }
}

}  // namespace pcnc
