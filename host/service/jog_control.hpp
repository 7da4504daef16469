// jog_control.hpp — jogging over the control socket: starts incremental and continuous jogs
// on the rt (clamped to the soft limits), answers a jog only once the rt has taken it (or
// did not), keeps a continuous jog alive on the rt while its client sends keep-alives, and
// stops it when the client falls silent (the deadman, process.jog_deadman_s) or goes away.
//
// Loop thread only. Replies that wait for the rt and the "jog_stopped" event go out through
// the callbacks it is given; it reads the rt through the monitor and never blocks on it.
//
// May include: outcome.hpp, rpc.hpp, rt_monitor.hpp, control_server.hpp (ClientId), shared/.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include "config/config.hpp"
#include "service/control_server.hpp"
#include "service/outcome.hpp"
#include "service/rt_monitor.hpp"

namespace pcnc {

class JogControl {
 public:
  using Reply = std::function<void(ClientId, const rpc::json& id, const Outcome&)>;
  using Event = std::function<void(const rpc::json& event)>;
  /// `config` is the service's (its axes and jog deadman); it must outlive this.
  JogControl(const MachineConfig& config, RtMonitor& rt, Reply reply, Event event);

  /// The `jog` method: refused unless the machine is IDLE, PAUSED or JOGGING (and a program
  /// is not starting), or when another client's continuous jog is active. The reply comes
  /// later, once the rt has taken the command (or not within 1 s).
  Outcome start(ClientId client, const rpc::json& id, RtLink& link, const Status& st, const rpc::JogParams& jp,
                bool job_active);
  /// The `jog_keepalive` method.
  Outcome keepalive(ClientId client);
  /// Forgets the continuous jog: the caller sends the command that ends it on the rt.
  void forget() { jog_.reset(); }
  /// Stops a continuous jog on the rt and tells subscribers why.
  void stop_continuous(const char* why);
  bool continuous_active() const { return jog_.has_value(); }

  /// Every loop tick, with the rt's status (none when no live rt): replies to the jogs the
  /// rt has taken, keeps the continuous jog alive on the rt, applies the deadman.
  void tick(const std::optional<Status>& st);
  void client_gone(ClientId client);

 private:
  using Clock = std::chrono::steady_clock;
  struct ContinuousJog {
    ClientId owner = 0;
    Clock::time_point last_client{}, last_rt{}, started{};
    std::uint64_t cmd_id = 0;
    bool seen_jogging = false;
  };
  // A jog whose acceptance by the rt is checked before replying.
  struct PendingJog {
    ClientId client = 0;
    rpc::json id;
    std::uint64_t cmd_id = 0;
    Vec3 before{};
    rpc::json result;
    Clock::time_point deadline{};
    Rot3 before_rot{};
  };

  void check_pending(const std::optional<Status>& st);
  void tick_continuous(const std::optional<Status>& st);

  const MachineConfig& config_;
  RtMonitor& rt_;
  Reply reply_;
  Event event_;
  std::optional<ContinuousJog> jog_;
  std::vector<PendingJog> pending_;
};

}  // namespace pcnc
