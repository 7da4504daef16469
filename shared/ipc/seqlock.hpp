// seqlock.hpp — one writer publishes a trivially copyable snapshot; readers in another process
// copy it without ever blocking the writer (the rt). A reader retries while a write is in
// progress or when the sequence changed under it.
#pragma once

#include <sched.h>

#include <atomic>
#include <cstdint>
#include <cstring>
#include <type_traits>

namespace pcnc {

template <typename T>
class Seqlock {
  static_assert(std::is_trivially_copyable_v<T>);
  static_assert(std::atomic<std::uint64_t>::is_always_lock_free);

 public:
  void store(const T& value) {
    std::uint64_t w[kWords]{};
    std::memcpy(w, &value, sizeof(T));
    const std::uint64_t s = seq_.load(std::memory_order_relaxed);
    seq_.store(s + 1, std::memory_order_relaxed);  // odd: write in progress
    std::atomic_thread_fence(std::memory_order_release);
    for (std::size_t i = 0; i < kWords; ++i) __atomic_store_n(&words_[i], w[i], __ATOMIC_RELAXED);
    seq_.store(s + 2, std::memory_order_release);
  }

  /// Copies a consistent snapshot. Never blocks the writer; retries while a write is in
  /// flight (well under a microsecond), yielding the CPU every 64 tries so that a reader on
  /// a busy machine lets the writer finish. Returns false after `max_tries` torn reads.
  /// Readers are never the rt: only the rt writes.
  bool load(T& out, int max_tries = 1 << 24) const {
    std::uint64_t w[kWords];
    for (int attempt = 0; attempt < max_tries; ++attempt) {
      if ((attempt & 63) == 63) sched_yield();
      const std::uint64_t s1 = seq_.load(std::memory_order_acquire);
      if (s1 & 1) continue;
      for (std::size_t i = 0; i < kWords; ++i) w[i] = __atomic_load_n(&words_[i], __ATOMIC_RELAXED);
      std::atomic_thread_fence(std::memory_order_acquire);
      if (seq_.load(std::memory_order_relaxed) == s1) {
        std::memcpy(&out, w, sizeof(T));
        return true;
      }
    }
    return false;
  }

  /// Even: number of completed stores times two.
  std::uint64_t version() const { return seq_.load(std::memory_order_acquire); }

 private:
  // The snapshot is kept as words read and written with relaxed atomics, so that a racing
  // read is well defined (and quiet under ThreadSanitizer); the sequence check discards it.
  static constexpr std::size_t kWords = (sizeof(T) + 7) / 8;
  std::atomic<std::uint64_t> seq_{0};
  std::uint64_t words_[kWords]{};
};

}  // namespace pcnc
