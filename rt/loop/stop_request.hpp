// stop_request.hpp — SIGTERM/SIGINT to pcnc-rt as a request the loop reads each cycle: the
// first signal asks for a controlled stop (whatever moves is brought to rest along its path,
// then the process exits), a second one for an exit at once. Power is never cut to a moving
// process by the first signal.
//
// note_signal() runs in a signal handler: it touches only lock-free atomics and
// clock_gettime (async-signal-safe); the loop reads level() with one relaxed load.
//
// A signal that arrives within kRepeatWindowNs of the first counts as the same request: a
// terminal's Ctrl-C reaches every process of the foreground group while a launcher may
// forward it too, and a service manager may signal the whole group as well as the main
// process. A second request is a signal sent on purpose, later.
#pragma once

#include <atomic>
#include <cstdint>

#include "ipc/segment.hpp"

namespace pcnc {

class StopRequest {
 public:
  static constexpr std::uint64_t kRepeatWindowNs = 200'000'000;  // 200 ms

  /// From a signal handler (or a test): one more stop signal.
  void note_signal(int sig) noexcept {
    const std::uint64_t now = monotonic_ns();
    std::uint64_t first = 0;
    if (first_ns_.compare_exchange_strong(first, now)) {
      signal_.store(sig, std::memory_order_relaxed);
      level_.store(1, std::memory_order_release);
      return;
    }
    if (now - first < kRepeatWindowNs) return;  // the same request, delivered twice
    second_signal_.store(sig, std::memory_order_relaxed);
    level_.store(2, std::memory_order_release);
  }

  /// 0: run on; 1: bring the machine to rest, then exit; 2: exit at once.
  int level() const noexcept { return level_.load(std::memory_order_acquire); }
  /// The first signal's number (0 before any), and the second's.
  int signal() const noexcept { return signal_.load(std::memory_order_relaxed); }
  int second_signal() const noexcept { return second_signal_.load(std::memory_order_relaxed); }

 private:
  static_assert(std::atomic<int>::is_always_lock_free);
  static_assert(std::atomic<std::uint64_t>::is_always_lock_free);
  std::atomic<int> level_{0};
  std::atomic<int> signal_{0};
  std::atomic<int> second_signal_{0};
  std::atomic<std::uint64_t> first_ns_{0};
};

}  // namespace pcnc
