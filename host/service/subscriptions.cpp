// subscriptions.cpp — status pushes and events for subscribed clients (see subscriptions.hpp).
#include "service/subscriptions.hpp"

#include <algorithm>
#include <optional>
#include <string>

namespace pcnc {

void Subscriptions::subscribe(ClientId client, double rate_hz) {
  if (rate_hz <= 0.0) {
    subs_.erase(client);
    return;
  }
  // The period as a clock duration: a rate the protocol accepts (0 < rate <= 50) can still be
  // so small (5e-324) that 1/rate is infinite or beyond the clock's range, and converting that
  // is undefined behaviour. Such a client gets one push a day.
  const double period_s = std::min(1.0 / rate_hz, kLongestPeriodS);
  subs_[client] = Subscription{std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(period_s)),
                               Clock::now()};
}

void Subscriptions::remove(ClientId client) { subs_.erase(client); }

void Subscriptions::broadcast_event(const rpc::json& event) {
  const std::string line = rpc::format_notification("event", event);
  for (auto& [client, sub] : subs_) send_(client, line);
}

void Subscriptions::tick(const std::function<rpc::json()>& status) {
  if (subs_.empty()) return;
  const auto now = Clock::now();
  std::optional<std::string> line;
  for (auto& [client, sub] : subs_) {
    if (now < sub.next) continue;
    sub.next += sub.period;
    if (sub.next < now) sub.next = now;
    if (!line) line = rpc::format_notification("status", status());
    send_(client, *line);
  }
}

}  // namespace pcnc
