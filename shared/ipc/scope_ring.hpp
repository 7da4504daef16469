// scope_ring.hpp — the rt's per-cycle samples for the scope (`pcnc ctl capture`): a
// flight recorder in the shared segment that pcnc-rt overwrites every cycle and any number
// of host readers copy from, without the rt ever knowing or waiting.
//
// Sample n (n = 0, 1, 2, ... counted from the rt's start) goes to slot n % N. Each slot has
// its own sequence: 2n+1 while sample n is being written, 2n+2 once it is complete. A reader
// that wants sample n checks the sequence before and after copying the words: equal to 2n+2
// both times means the copy is sample n, whole. Anything newer means the writer lapped the
// reader (the host read too slowly, more than N cycles behind): the sample is lost, and the
// reader is told so, never handed a torn or a later sample in its place.
//
// The writer (the rt cycle) does N-independent constant work: a handful of relaxed atomic
// word stores and two sequence stores; no system call, no wait, no allocation. The words are
// relaxed atomics, as in seqlock.hpp, so a racing read is well defined.
#pragma once

#include <atomic>
#include <cstdint>
#include <cstring>
#include <type_traits>

#include "ipc/trace_format.hpp"

namespace pcnc {

enum class ScopeRead : std::uint8_t {
  kOk = 0,      // `out` holds sample n
  kNotYet = 1,  // sample n has not been written yet
  kLost = 2,    // sample n was overwritten before (or while) it was read
};

template <std::size_t N>
class ScopeRing {
  static_assert(std::is_trivially_copyable_v<TraceSample>);
  static_assert(std::atomic<std::uint64_t>::is_always_lock_free);
  static_assert(N >= 2);

 public:
  static constexpr std::size_t kSlots = N;

  // ---- writer: the rt, once per cycle ----
  void publish(const TraceSample& s) {
    const std::uint64_t n = written_.load(std::memory_order_relaxed);
    Slot& slot = slots_[n % N];
    std::uint64_t w[kWords]{};
    std::memcpy(w, &s, sizeof s);
    slot.seq.store(2 * n + 1, std::memory_order_relaxed);  // odd: being written
    std::atomic_thread_fence(std::memory_order_release);
    for (std::size_t i = 0; i < kWords; ++i) __atomic_store_n(&slot.words[i], w[i], __ATOMIC_RELAXED);
    slot.seq.store(2 * n + 2, std::memory_order_release);
    written_.store(n + 1, std::memory_order_release);
  }

  // ---- readers: the host, any number ----
  /// Samples published so far (the next one to be written has this number).
  std::uint64_t written() const { return written_.load(std::memory_order_acquire); }

  /// Copies sample n into `out`; see ScopeRead.
  ScopeRead read(std::uint64_t n, TraceSample& out) const {
    const Slot& slot = slots_[n % N];
    const std::uint64_t want = 2 * n + 2;
    const std::uint64_t s1 = slot.seq.load(std::memory_order_acquire);
    if (s1 < want - 1) return ScopeRead::kNotYet;  // an older sample (or empty): n not written
    if (s1 != want) return s1 == want - 1 ? ScopeRead::kNotYet : ScopeRead::kLost;
    std::uint64_t w[kWords];
    for (std::size_t i = 0; i < kWords; ++i) w[i] = __atomic_load_n(&slot.words[i], __ATOMIC_RELAXED);
    std::atomic_thread_fence(std::memory_order_acquire);
    if (slot.seq.load(std::memory_order_relaxed) != want) return ScopeRead::kLost;  // lapped during the copy
    std::memcpy(&out, w, sizeof out);
    return ScopeRead::kOk;
  }

 private:
  static constexpr std::size_t kWords = (sizeof(TraceSample) + 7) / 8;
  struct Slot {
    std::atomic<std::uint64_t> seq{0};
    std::uint64_t words[kWords]{};
  };
  alignas(64) std::atomic<std::uint64_t> written_{0};
  alignas(64) Slot slots_[N]{};
};

}  // namespace pcnc
