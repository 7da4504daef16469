// ring_feeder.cpp — the blocking part of the feeder: sleeping until the rt frees a slot.
#include "service/ring_feeder.hpp"

#include <time.h>

#include <algorithm>

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

RingFeeder::RingFeeder(RtLink& link, double check_period_s, std::uint64_t spin_ns)
    : link_(link), check_period_s_(check_period_s), spin_ns_(spin_ns) {}

bool RingFeeder::slot_free() {
  auto& shm = link_.shm();
  return via_stage_ ? shm.stage.begin_push() != nullptr : shm.motion.begin_push() != nullptr;
}

// The replay stage (virtual clock): nap on the host's own timer until the rt has drained the
// stage to its low-water mark, then let the caller refill it. The rt never wakes the host
// here: a wake-up per block cost the rt a system call each (tens of µs in a virtual machine),
// and following the rt by spinning held a core the rt's trace writer and the report need.
// A nap is about 30 µs plus the timer's slack; the stage's other blocks last longer than that
// on a CAM program, and when they do not, the rt waits for the host as it always may (the
// replay stays deterministic). While the stage does not move (a pause, a dwell, a long slow
// block) each nap doubles, up to 2 ms, so that a paused replay does not wake the host 10,000s
// of times a second; the first block the rt takes brings the naps back to 30 µs.
FeedResult RingFeeder::wait_for_stage_room(const std::atomic<bool>* abort) {
  constexpr long kNapNs = 30000, kLongestNapNs = 2000000;
  auto& shm = link_.shm();
  const std::uint64_t check_ns = static_cast<std::uint64_t>(check_period_s_ * 1e9);
  std::size_t seen = kStageSlots + 1;  // none yet: the first nap is the short one
  long nap_ns = kNapNs;
  for (;;) {
    const std::uint64_t until = monotonic_ns() + check_ns;
    do {
      const std::size_t staged = shm.stage.size();
      if (staged <= kStageLowWater) return FeedResult::kPushed;
      nap_ns = staged == seen ? std::min(2 * nap_ns, kLongestNapNs) : kNapNs;
      seen = staged;
      const timespec nap{0, nap_ns};
      nanosleep(&nap, nullptr);
    } while (monotonic_ns() < until);
    if (while_waiting_) while_waiting_();
    if (abort && abort->load()) return FeedResult::kAborted;
    if (!link_.rt_alive()) return FeedResult::kRtLost;
  }
}

FeedResult RingFeeder::wait_for_slot(const std::atomic<bool>* abort) {
  if (via_stage_) return wait_for_stage_room(abort);
  auto& shm = link_.shm();
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
