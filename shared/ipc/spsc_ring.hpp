// spsc_ring.hpp — a fixed-capacity single-producer / single-consumer ring of trivially
// copyable values, usable in shared memory (no pointers, lock-free atomics only).
//
// The motion ring (4 blocks), the command mailbox and the rt's trace queue are all this type.
// The producer fills a slot in place (begin_push / commit_push) and the consumer reads slots
// in place (peek / pop), so a block is written once and never copied through the ring.
// head counts pushes, tail counts pops; both only grow, so fill = head - tail and a slot is
// free exactly when fill < N: the producer can never overwrite an unconsumed slot.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <type_traits>

namespace pcnc {

template <typename T, std::size_t N>
class SpscRing {
  static_assert(std::is_trivially_copyable_v<T>, "ring slots are shared memory");
  static_assert(N > 0);
  static_assert(std::atomic<std::uint64_t>::is_always_lock_free, "ring indices must be lock-free");

 public:
  static constexpr std::size_t kCapacity = N;

  // ---- producer side ----
  /// The free slot to fill, or nullptr when the ring is full. Call commit_push() to publish.
  T* begin_push() {
    const std::uint64_t h = head_.load(std::memory_order_relaxed);
    if (h - tail_.load(std::memory_order_acquire) >= N) return nullptr;
    return &slots_[h % N];
  }
  /// Publishes the slot begin_push() gave. Sequentially consistent by default: a producer that
  /// then checks a sleeper's flag (wakeup.hpp) needs this store ordered before that load. A queue
  /// whose consumer only polls (the rt's trace queue) may pass release: on x86 a plain store, where
  /// seq_cst is a locked exchange that stalls the producer until the slot's own stores drain.
  void commit_push(std::memory_order order = std::memory_order_seq_cst) {
    head_.store(head_.load(std::memory_order_relaxed) + 1, order);
  }
  bool try_push(const T& value) {
    T* slot = begin_push();
    if (!slot) return false;
    *slot = value;
    commit_push();
    return true;
  }

  // ---- consumer side ----
  /// Number of published, unconsumed values.
  std::size_t size() const {
    return static_cast<std::size_t>(head_.load(std::memory_order_acquire) - tail_.load(std::memory_order_relaxed));
  }
  bool empty() const { return size() == 0; }
  /// The i-th unconsumed value (0 = oldest); i < size().
  const T& peek(std::size_t i = 0) const { return slots_[(tail_.load(std::memory_order_relaxed) + i) % N]; }
  void pop() { tail_.store(tail_.load(std::memory_order_relaxed) + 1, std::memory_order_seq_cst); }
  /// Consumer only: the n oldest values (n <= size()) at once, after reading them in place with
  /// peek(0..n-1): one store for the batch, so the producer's core sees the index change once.
  void pop_n(std::size_t n) { tail_.store(tail_.load(std::memory_order_relaxed) + n, std::memory_order_seq_cst); }
  bool try_pop(T& out) {
    if (empty()) return false;
    out = peek(0);
    pop();
    return true;
  }
  /// Consumer only: drop everything published so far.
  void pop_all() { tail_.store(head_.load(std::memory_order_acquire), std::memory_order_seq_cst); }

  // ---- either side, for status ----
  std::size_t fill_approx() const {
    return static_cast<std::size_t>(head_.load(std::memory_order_relaxed) - tail_.load(std::memory_order_relaxed));
  }
  std::uint64_t pushed() const { return head_.load(std::memory_order_acquire); }
  std::uint64_t popped() const { return tail_.load(std::memory_order_acquire); }

 private:
  alignas(64) std::atomic<std::uint64_t> head_{0};
  alignas(64) std::atomic<std::uint64_t> tail_{0};
  alignas(64) T slots_[N]{};
};

}  // namespace pcnc
