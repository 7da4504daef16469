// ring_feeder.cpp — the blocking part of the feeder: sleeping until the rt frees a slot.
#include "service/ring_feeder.hpp"

namespace pcnc {

const char* to_string(FeedResult r) {
  switch (r) {
    case FeedResult::kPushed: return "pushed";
    case FeedResult::kEndOfInput: return "end of input";
    case FeedResult::kRtLost: return "pcnc-rt lost";
    case FeedResult::kAborted: return "aborted";
  }
  return "?";
}

RingFeeder::RingFeeder(RtLink& link, double check_period_s, std::uint64_t spin_ns, std::uint64_t follow_rt_ns)
    : link_(link), check_period_s_(check_period_s), spin_ns_(spin_ns), follow_rt_ns_(follow_rt_ns) {}

bool RingFeeder::slot_free() {
  auto& shm = link_.shm();
  return via_stage_ ? shm.stage.begin_push() != nullptr : shm.motion.begin_push() != nullptr;
}

// Spins while the rt runs (its cycles count up the scope ring), for 1 ms at most: a block that lasts longer costs one wake-up
// (tens of µs) at its end, a small part of it, and the host's core is not held meanwhile.
bool RingFeeder::follow_rt() {
  constexpr std::uint64_t kFollowAtMostNs = 1000000;
  auto& shm = link_.shm();
  std::uint64_t beat = shm.scope.written();  // one more every rt cycle
  std::uint64_t moved = monotonic_ns();
  const std::uint64_t give_up = moved + kFollowAtMostNs;
  for (unsigned i = 1;; ++i) {
    if (slot_free()) return true;
#if defined(__x86_64__) || defined(__i386__)
    __builtin_ia32_pause();
#endif
    if ((i & 63) == 0) {
      const std::uint64_t now = monotonic_ns();
      const std::uint64_t b = shm.scope.written();
      if (b != beat) {
        beat = b;
        moved = now;
      } else if (now - moved >= follow_rt_ns_) {
        return false;
      }
      if (now >= give_up) return false;
    }
  }
}

FeedResult RingFeeder::wait_for_slot(const std::atomic<bool>* abort) {
  auto& shm = link_.shm();
  if (follow_rt_ns_ > 0 && follow_rt()) return FeedResult::kPushed;
  for (;;) {
    if (shm.slot_freed.wait_until([&] { return slot_free(); }, check_period_s_, spin_ns_)) {
      return FeedResult::kPushed;
    }
    if (while_waiting_) while_waiting_();
    if (abort && abort->load()) return FeedResult::kAborted;
    if (!link_.rt_alive()) return FeedResult::kRtLost;
  }
}

void RingFeeder::record_refill_latency() {
  const std::uint64_t freed = link_.shm().header.slot_freed_ns.load(std::memory_order_acquire);
  const std::uint64_t now = monotonic_ns();
  if (freed != 0 && now >= freed) refill_.add(static_cast<double>(now - freed) / 1000.0);
}

}  // namespace pcnc
