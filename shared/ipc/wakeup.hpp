// wakeup.hpp — a process-shared "something changed, wake up" signal for one sleeper.
//
// The sleeper (e.g. the host waiting for a free ring slot) announces itself, re-checks its
// condition, then sleeps on a POSIX semaphore; the notifier (the rt, after freeing a slot)
// posts only when a sleeper announced itself. sem_post never blocks, so the rt may call
// notify() from its cycle. Announce-then-recheck on one side and change-then-check on the
// other (both sequentially consistent) mean no wake-up is lost; a stale post only causes one
// spurious return, which callers handle by re-checking their condition.
#pragma once

#include <semaphore.h>

#include <atomic>
#include <cerrno>
#include <cstdint>
#include <ctime>

namespace pcnc {

class Wakeup {
 public:
  /// Must be called once on the shared memory before either side uses it.
  void init() {
    waiting_.store(0);
    sem_init(&sem_, /*pshared=*/1, 0);
  }
  void destroy() { sem_destroy(&sem_); }

  /// Notifier: call after changing the condition the sleeper waits on.
  void notify() {
    if (waiting_.load(std::memory_order_seq_cst) != 0 && waiting_.exchange(0, std::memory_order_seq_cst) != 0) {
      sem_post(&sem_);
    }
  }

  /// Sleeper: blocks until `ready()` is true or `timeout_s` passes. Returns ready().
  /// It first spins for up to `spin_ns` (default 20 µs): when the other side is about to
  /// change the condition, that saves two system calls and a context switch; after that it
  /// sleeps on the semaphore.
  template <typename Ready>
  bool wait_until(Ready&& ready, double timeout_s, std::uint64_t spin_ns = 20000) {
    if (ready()) return true;
    if (spin_ns > 0) {
      const std::uint64_t spin_end = now_ns() + spin_ns;
      for (unsigned i = 1;; ++i) {
        cpu_relax();
        if (ready()) return true;
        if ((i & 63) == 0 && now_ns() >= spin_end) break;
      }
    }
    timespec deadline{};
    clock_gettime(CLOCK_MONOTONIC, &deadline);
    add_seconds(deadline, timeout_s);
    for (;;) {
      waiting_.store(1, std::memory_order_seq_cst);
      if (ready()) {
        waiting_.store(0, std::memory_order_relaxed);
        return true;
      }
      const int rc = sem_clockwait(&sem_, CLOCK_MONOTONIC, &deadline);
      if (ready()) return true;
      if (rc != 0 && errno == ETIMEDOUT) return false;
    }
  }

 private:
  static void cpu_relax() {
#if defined(__x86_64__) || defined(__i386__)
    __builtin_ia32_pause();
#endif
  }
  static std::uint64_t now_ns() {
    timespec t{};
    clock_gettime(CLOCK_MONOTONIC, &t);
    return static_cast<std::uint64_t>(t.tv_sec) * 1000000000ull + static_cast<std::uint64_t>(t.tv_nsec);
  }
  static void add_seconds(timespec& t, double s) {
    const auto whole = static_cast<time_t>(s);
    t.tv_sec += whole;
    t.tv_nsec += static_cast<long>((s - static_cast<double>(whole)) * 1e9);
    if (t.tv_nsec >= 1000000000L) {
      t.tv_sec += 1;
      t.tv_nsec -= 1000000000L;
    }
  }
  std::atomic<std::uint32_t> waiting_{0};
  sem_t sem_;
};

}  // namespace pcnc
