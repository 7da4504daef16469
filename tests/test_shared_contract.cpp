// test_shared_contract.cpp — the in-process properties of the shared-memory types: ring
// capacity and order, seqlock snapshots, the scope ring under a racing reader, the layout
// version (the config loader: test_config.cpp).
#include <gtest/gtest.h>

#include <cstddef>
#include <memory>
#include <thread>

#include "config/config.hpp"
#include "ipc/segment.hpp"
#include "test_paths.hpp"

namespace pcnc {
namespace {

TEST(SpscRing, HoldsExactlyItsCapacityAndKeepsOrder) {
  SpscRing<Block, kRingSlots> ring;
  static_assert(kRingSlots == 4, "the seed's 4-line buffer");
  for (std::uint64_t i = 1; i <= 4; ++i) {
    Block* slot = ring.begin_push();
    ASSERT_NE(slot, nullptr) << "slot " << i;
    slot->seq = i;
    ring.commit_push();
  }
  EXPECT_EQ(ring.begin_push(), nullptr) << "a fifth block must not fit";
  EXPECT_EQ(ring.size(), 4u);
  for (std::uint64_t i = 0; i < 4; ++i) EXPECT_EQ(ring.peek(i).seq, i + 1);
  ring.pop();
  Block* slot = ring.begin_push();
  ASSERT_NE(slot, nullptr);
  slot->seq = 5;
  ring.commit_push();
  for (std::uint64_t i = 0; i < 4; ++i) EXPECT_EQ(ring.peek(i).seq, i + 2);
  ring.pop_all();
  EXPECT_TRUE(ring.empty());
  EXPECT_EQ(ring.pushed(), 5u);
  EXPECT_EQ(ring.popped(), 5u);
}

TEST(Seqlock, ReaderNeverSeesATornSnapshot) {
  Seqlock<Status> lock;
  std::atomic<bool> done{false};
  std::thread writer([&] {
    Status s;
    for (std::uint64_t i = 0; i < 200000; ++i) {
      s.cycle = i;
      s.time_s = static_cast<double>(i);
      s.commanded = {static_cast<double>(i), static_cast<double>(i), static_cast<double>(i)};
      s.blocks_done = i;
      lock.store(s);
    }
    done = true;
  });
  std::uint64_t reads = 0, last = 0;
  while (!done) {
    Status s;
    ASSERT_TRUE(lock.load(s));
    // every field was written from the same i
    ASSERT_EQ(s.blocks_done, s.cycle);
    ASSERT_EQ(s.commanded[2], static_cast<double>(s.cycle));
    ASSERT_EQ(s.time_s, static_cast<double>(s.cycle));
    ASSERT_GE(s.cycle, last) << "snapshots go forward";
    last = s.cycle;
    ++reads;
  }
  writer.join();
  EXPECT_GT(reads, 0u);
}

// Layout version 8 (issue 16): a block's rotary joints and TCP data (Block::rotary), the status's
// joints (Status::rot_*); 7 (issue 15): a block's probe rule and the status's probe fields; 6 (issue 14): a NURBS block's schedule carries the tangential acceleration
// and the arc length of each point; 5 (issue 14): a block carries its path tolerance; 4 (issue 20): the segment
// ends with the scope's ring (3, issue 19: Status carries trace_failed). Any change of Block, Command, Status or the segment bumps
// kLayoutVersion, so that a host and an rt of different builds refuse each other, and a
// restarted rt takes no position from a segment it cannot read.
// Layout version 9 (issue 17): the ruled block: BlockKind::kRuled and its piece, Block::ruled,
// appended after the rotary data.
// Layout version 10 (issue 14): the replay stage, kStageSlots blocks after the motion ring
// that the host writes under the virtual clock and the rt empties into the ring itself.
TEST(SharedContract, LayoutVersionTenCarriesTheReplayStage) {
  EXPECT_EQ(kLayoutVersion, 11u);
  EXPECT_EQ(kRingSlots, 4u) << "the ring the rt runs from stays the seed's four slots";
  EXPECT_EQ(StageRing::kCapacity, kStageSlots);
  EXPECT_GT(offsetof(SharedSegment, stage), offsetof(SharedSegment, motion));
  const auto seg = std::make_unique<SharedSegment>();
  EXPECT_TRUE(seg->stage.empty());
  // the segment stays small enough to be created under the trace test's 450 KB file limit
  EXPECT_LT(sizeof(SharedSegment), 450000u);
}

TEST(SharedContract, LayoutVersionNineCarriesTheRuledPiece) {
  EXPECT_EQ(static_cast<int>(BlockKind::kRuled), 7);
  EXPECT_STREQ(to_string(BlockKind::kRuled), "ruled");
  const Block b{};
  EXPECT_EQ(b.ruled.segment_count, 0);
  EXPECT_EQ(b.ruled.schedule_count, 0);
  EXPECT_GT(offsetof(Block, ruled), offsetof(Block, rotary)) << "appended after the rotary data";
  EXPECT_EQ(sizeof(RuledGeometry), 6720u);
}

TEST(SharedContract, LayoutVersionEightCarriesTheRotaryJoints) {
  const Block r{};
  EXPECT_EQ(r.rotary.tcp, 0);
  EXPECT_EQ(r.rotary.end[2], 0.0);
  EXPECT_GT(offsetof(Block, rotary), offsetof(Block, nurbs)) << "appended after the NURBS data";
  EXPECT_EQ(Status{}.rotary_mask, 0);
  EXPECT_EQ(sizeof(Rot3), 3 * sizeof(double));
}

TEST(SharedContract, LayoutVersionSevenCarriesTheScheduleAccelerationAndTheProbe) {
  const Block b{};
  EXPECT_EQ(b.nurbs.schedule_accel[0], 0.0);
  EXPECT_EQ(b.nurbs.schedule_accel[kMaxFeedSchedule - 1], 0.0);
  EXPECT_EQ(b.nurbs.schedule_s[0], 0.0);
  EXPECT_EQ(offsetof(NurbsGeometry, schedule_accel), offsetof(NurbsGeometry, schedule_speed) + sizeof(b.nurbs.schedule_speed));
  EXPECT_EQ(offsetof(NurbsGeometry, schedule_s), offsetof(NurbsGeometry, schedule_accel) + sizeof(b.nurbs.schedule_accel));
  EXPECT_EQ(b.probe_rule, 0);
  EXPECT_EQ(Status{}.probe_count, 0u);
  EXPECT_EQ(Block{}.path_tolerance_mm, 0.0f);
  Status s{};
  EXPECT_EQ(s.trace_failed, 0);
  EXPECT_LT(offsetof(Status, trace_failed), offsetof(Status, line));
  EXPECT_GT(offsetof(SharedSegment, scope), offsetof(SharedSegment, status));
  EXPECT_EQ(decltype(SharedSegment::scope)::kSlots, kScopeSlots);
}

// A reader racing the writer gets whole samples in order, or is told it lost them: never a
// sample torn between two cycles or one from a later lap.
TEST(ScopeRing, AReaderRacingTheWriterGetsWholeSamplesOrLosses) {
  auto ring = std::make_unique<ScopeRing<64>>();
  constexpr std::uint64_t kSamples = 200000;
  std::thread writer([&] {
    TraceSample s{};
    for (std::uint64_t n = 0; n < kSamples; ++n) {
      s.t = static_cast<double>(n);
      s.commanded = {static_cast<double>(n), static_cast<double>(n), static_cast<double>(n)};
      s.speed = static_cast<double>(n);
      ring->publish(s);
    }
  });
  std::uint64_t next = 0, ok = 0, lost = 0;
  while (next < kSamples) {
    TraceSample s;
    const ScopeRead r = ring->read(next, s);
    if (r == ScopeRead::kNotYet) continue;
    if (r == ScopeRead::kLost) {
      ++lost;
    } else {
      ++ok;
      ASSERT_EQ(s.t, static_cast<double>(next));
      ASSERT_EQ(s.commanded[2], s.t);
      ASSERT_EQ(s.speed, s.t);
    }
    ++next;
  }
  writer.join();
  EXPECT_EQ(ok + lost, kSamples);
  EXPECT_GT(ok, 0u);
}

}  // namespace
}  // namespace pcnc
