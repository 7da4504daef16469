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

RingFeeder::RingFeeder(RtLink& link, double check_period_s, std::uint64_t spin_ns, std::uint64_t yield_every_ns)
    : link_(link), check_period_s_(check_period_s), spin_ns_(spin_ns), yield_every_ns_(yield_every_ns) {}

FeedResult RingFeeder::wait_for_slot(const std::atomic<bool>* abort) {
  auto& shm = link_.shm();
  for (;;) {
    if (shm.slot_freed.wait_until([&] { return shm.motion.begin_push() != nullptr; }, check_period_s_, spin_ns_,
                                 yield_every_ns_)) {
      return FeedResult::kPushed;
    }
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
