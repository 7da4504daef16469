// ring_feeder.hpp — puts preprocessed blocks into the 4-slot motion ring, in order, with
// sequence numbers. When the ring is full it sleeps on the rt's slot-freed wake-up (no
// polling), waking at most every `check_period_s` to notice a dead rt or an abort request.
// Under the virtual clock it writes into the replay stage instead (set_via_stage), which the
// rt empties into its ring.
//
// May include: rt_link.hpp, shared/ipc.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <vector>

#include "ipc/latency_histogram.hpp"
#include "service/rt_link.hpp"

namespace pcnc {

enum class FeedResult {
  kPushed,      // the block is in the ring
  kEndOfInput,  // the fill function had no more blocks
  kRtLost,      // the rt stopped beating
  kAborted,     // the abort flag was raised, or the rt left the running state (fault, stop)
};

const char* to_string(FeedResult r);

class RingFeeder {
 public:
  /// `spin_ns`: how long to spin before sleeping when the ring is full.
  explicit RingFeeder(RtLink& link, double check_period_s = 0.02, std::uint64_t spin_ns = 20000);

  /// Under the virtual clock: write into the replay stage (SharedSegment::stage), from which
  /// the rt fills its ring before each cycle, instead of into the ring itself. The ring the
  /// rt sees is the same; the host waits when the stage (kStageSlots blocks) is full, not the
  /// ring, and then naps until the rt has drained it to kStageLowWater (wait_for_stage_room).
  void set_via_stage(bool on) { via_stage_ = on; }

  /// Puts the next block into the ring (or the stage). `fill(Block&)` is a stream: each call
  /// writes the next block and returns true, or returns false when there are no more; the
  /// feeder may call it several times in one push (staging) and never again after it returned
  /// false. With a slot free and nothing staged, the block is filled in place. While the ring
  /// is full, the feeder fills up to kStageDepth blocks ahead
  /// into a local staging queue and copies them in as slots free: a slot is then refilled
  /// by one copy, not by parsing and preprocessing, and short blocks (which the rt finishes
  /// faster than the host prepares them) draw on the blocks prepared during long ones.
  /// The feeder assigns seq = 1, 2, 3, ...
  template <typename Fill>
  FeedResult push(Fill&& fill, const std::atomic<bool>* abort = nullptr) {
    return via_stage_ ? push_into(link_.shm().stage, fill, abort) : push_into(link_.shm().motion, fill, abort);
  }

  /// Staging off: fill is called only with a free slot in hand. For a source that may wait
  /// for its input (a streamed program): blocks it made are never held back in staging while
  /// it waits for lines, so the machine runs everything received.
  void set_staging(bool on) { staging_ = on; }

  /// Called every check period while the feeder waits for a slot, before it looks at the
  /// abort flag (the job runner answers a program pause here, and raises the flag).
  void set_while_waiting(std::function<void()> fn) { while_waiting_ = std::move(fn); }

  /// Restart numbering for a new program (the rt expects seq 1 after kProgramStart).
  void reset_sequence() { seq_ = 0; }
  /// The fill stream has more after all (a probing move's result arrived, docs/probe.md):
  /// push() calls it again.
  void resume_input() { input_ended_ = false; }
  std::uint64_t pushed() const { return seq_; }
  /// Host refill latency: from the rt freeing a slot of a full ring to the next block
  /// being published, microseconds.
  const LatencyHistogram& refill_latency() const { return refill_; }

 private:
  template <typename Ring, typename Fill>
  FeedResult push_into(Ring& ring, Fill& fill, const std::atomic<bool>* abort) {
    Block* slot = ring.begin_push();
    const bool waited = slot == nullptr;
    if (waited) {
      if (staged_.empty()) staged_.resize(kStageDepth);
      while (staging_ && staged_count_ < kStageDepth && !input_ended_ && ring.begin_push() == nullptr) {
        if (fill(staged_[(staged_head_ + staged_count_) % kStageDepth])) {
          ++staged_count_;
        } else {
          input_ended_ = true;
        }
      }
      if (ring.begin_push() == nullptr) {
        if (staged_count_ == 0 && input_ended_) return FeedResult::kEndOfInput;
        const FeedResult result = wait_for_slot(abort);
        if (result != FeedResult::kPushed) return result;  // staged blocks are kept for the next push
      }
      slot = ring.begin_push();
    }
    if (staged_count_ > 0) {
      *slot = staged_[staged_head_];
      staged_head_ = (staged_head_ + 1) % kStageDepth;
      --staged_count_;
    } else if (input_ended_ || !fill(*slot)) {
      input_ended_ = true;
      return FeedResult::kEndOfInput;
    }
    slot->seq = ++seq_;
    ring.commit_push();
    link_.shm().block_published.notify();
    if (waited) record_refill_latency();
    return FeedResult::kPushed;
  }

  FeedResult wait_for_slot(const std::atomic<bool>* abort);
  FeedResult wait_for_stage_room(const std::atomic<bool>* abort);
  bool slot_free();  // a free slot in the ring (or the stage) the feeder writes to
  void record_refill_latency();

  RtLink& link_;
  double check_period_s_;
  std::uint64_t spin_ns_;
  std::uint64_t seq_ = 0;
  bool staging_ = true;
  bool via_stage_ = false;
  LatencyHistogram refill_;
  static constexpr std::size_t kStageDepth = 16;
  std::vector<Block> staged_;  // blocks prepared while the ring was full, oldest at staged_head_
  std::size_t staged_head_ = 0;
  std::size_t staged_count_ = 0;
  bool input_ended_ = false;  // fill returned false
  std::function<void()> while_waiting_;
};

}  // namespace pcnc
