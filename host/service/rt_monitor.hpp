// rt_monitor.hpp — the service's hold on pcnc-rt: one thread that looks for the rt's segment
// until it can attach (rt_link.hpp), checks every few ms that the attached rt is alive, drops
// a link whose rt died and attaches to the next rt that appears. It keeps the link's state in
// words for the status object ("waiting", "attached", "lost", "refused", with a message and
// the rt's pid) and reports each attach and loss through callbacks.
//
// Data flows out of it only: request handlers and the job worker take the current link
// (a shared_ptr: a link stays valid while a handler or a job still holds it); the monitor
// never calls into the rest of the service except through its two callbacks.
//
// May include: rt_link.hpp, shared/.
#pragma once

#include <atomic>
#include <chrono>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "config/config.hpp"
#include "service/rt_link.hpp"

namespace pcnc {

struct RtMonitorEvents {
  // Both are called on the monitor thread; the service hands them to its loop.
  std::function<void(int pid, const Status& status)> attached;
  std::function<void(const std::string& why, double heartbeat_age_ms)> lost;
};

/// The link's state in words, for the status object.
struct RtLinkState {
  std::string state;    // waiting | attached | lost | refused
  std::string message;  // why, when not attached
  int pid = 0;          // the last rt attached to
};

class RtMonitor {
 public:
  RtMonitor(const MachineConfig& config, double period_s, double attach_retry_s, RtMonitorEvents events);
  ~RtMonitor();  // stops the thread and releases the link
  RtMonitor(const RtMonitor&) = delete;
  RtMonitor& operator=(const RtMonitor&) = delete;

  void start();
  /// Stops the monitor thread (the link, if any, is kept until release()).
  void stop();
  /// Drops the link (the host's heartbeat ends with the last holder).
  void release();

  /// The attached link, alive or not (nullptr when none).
  std::shared_ptr<RtLink> current() const;
  /// The attached link when its rt is alive; else nullptr, with `why` saying so in words
  /// ("pcnc-rt is not available (state): message").
  std::shared_ptr<RtLink> alive(std::string* why) const;
  RtLinkState state() const;

 private:
  void loop();
  void turn(std::chrono::steady_clock::time_point& next_attach, std::string& last_problem);
  void try_attach(std::string& last_problem);

  const MachineConfig config_;  // the links refer to it: the service ends its job worker, the
                                // last other holder of a link, before the monitor goes
  const double period_s_, attach_retry_s_;
  RtMonitorEvents events_;
  mutable std::mutex mutex_;  // guards link_ and state_
  std::shared_ptr<RtLink> link_;
  RtLinkState state_{"waiting", "no pcnc-rt attached yet", 0};
  std::thread thread_;
  std::atomic<bool> stop_{false};
};

}  // namespace pcnc
