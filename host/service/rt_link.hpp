// rt_link.hpp — pcnc-host's attachment to pcnc-rt: the opened segment, the host heartbeat
// (a background thread), the mailbox sender, status reads, and rt liveness.
//
// May include: shared/ (ipc, config) only.
#pragma once

#include <atomic>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "ipc/command.hpp"
#include "config/config.hpp"
#include "ipc/segment.hpp"
#include "ipc/status.hpp"

namespace pcnc {

class RtLink {
 public:
  /// Opens the segment (throws SegmentError with the reason) and starts the heartbeat.
  explicit RtLink(const MachineConfig& config);
  ~RtLink();
  RtLink(const RtLink&) = delete;
  RtLink& operator=(const RtLink&) = delete;

  /// Like the constructor, but retries for up to `wait_s` while the segment is absent or not
  /// yet initialised (the rt starting up). A segment that is refused (wrong magic/version/size)
  /// fails at once.
  static std::unique_ptr<RtLink> attach(const MachineConfig& config, double wait_s);

  SharedSegment& shm() { return segment_.shm(); }
  const SharedSegment& shm() const { return segment_.shm(); }

  /// Queues a command for the rt and wakes it if it waits (virtual clock). Returns its id,
  /// or 0 if the mailbox is full. Safe to call from several threads (the mailbox ring has a
  /// single producer; a mutex serialises the host's senders).
  std::uint64_t send(Command cmd);
  /// The same for a command without arguments (pause, resume, stop, reset, jog stop...).
  std::uint64_t send(CommandKind kind) {
    Command c;
    c.kind = kind;
    return send(c);
  }
  /// The rt's latest status snapshot.
  Status status() const;
  /// The rt heartbeat is fresh (within process.rt_timeout_s) and its pid is alive.
  bool rt_alive() const;
  /// Seconds since the rt's last cycle.
  double rt_heartbeat_age_s() const;
  /// Why rt_alive() is false, in words ("" while alive).
  std::string rt_loss_reason() const;
  int rt_pid() const { return shm().header.rt_pid.load(); }

  /// Whether an attach failure (a SegmentError's message) may go away by itself: the
  /// segment does not exist yet or is not initialised yet (the rt starting up). A segment
  /// refused for its magic, version or size is not.
  static bool transient_failure(const std::string& why);

 private:
  void beat();
  const MachineConfig& config_;
  HostSegment segment_;
  std::atomic<bool> stop_{false};
  std::mutex beat_mutex_;               // with beat_wake_: the destructor ends the heartbeat's sleep at once
  std::condition_variable beat_wake_;
  std::thread heartbeat_;
  std::atomic<std::uint64_t> next_id_{1};
  std::mutex send_mutex_;
};

}  // namespace pcnc
