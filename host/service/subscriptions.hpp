// subscriptions.hpp — the clients that asked for pushed messages (`subscribe`): each gets the
// status object as a "status" notification at its own rate, and every event (rt attached or
// lost, program started or ended, jog stopped) as an "event" notification.
//
// Loop thread only. It sends through the function it is given (the control server's send)
// and asks for the status object only when some subscriber is due.
//
// May include: rpc.hpp, control_server.hpp (ClientId).
#pragma once

#include <chrono>
#include <functional>
#include <map>
#include <string_view>

#include "service/control_server.hpp"
#include "service/rpc.hpp"

namespace pcnc {

class Subscriptions {
 public:
  using Send = std::function<void(ClientId, std::string_view line)>;
  explicit Subscriptions(Send send) : send_(std::move(send)) {}

  /// Pushes status to `client` at `rate_hz` from now on (replacing an earlier rate);
  /// a rate <= 0 ends its subscription.
  void subscribe(ClientId client, double rate_hz);
  void remove(ClientId client);
  bool has(ClientId client) const { return subs_.count(client) != 0; }
  /// Sends an event notification to every subscriber.
  void broadcast_event(const rpc::json& event);
  /// Sends the status object to each subscriber that is due; `status` is called at most once.
  void tick(const std::function<rpc::json()>& status);

 private:
  using Clock = std::chrono::steady_clock;
  static constexpr double kLongestPeriodS = 86400.0;  // a rate below 1/day pushes once a day
  struct Subscription {
    Clock::duration period{};
    Clock::time_point next{};
  };
  Send send_;
  std::map<ClientId, Subscription> subs_;
};

}  // namespace pcnc
