// test_shared_contract.cpp — the in-process properties of the shared-memory types: ring
// capacity and order, seqlock snapshots, and the config loader's strictness.
#include <gtest/gtest.h>

#include <cstddef>
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

// Layout version 3 (issue 19): Status carries trace_failed. Any change of Block, Command,
// Status or the segment bumps kLayoutVersion, so that a host and an rt of different builds
// refuse each other, and a restarted rt takes no position from a segment it cannot read.
TEST(SharedContract, LayoutVersionThreeCarriesTraceFailed) {
  EXPECT_EQ(kLayoutVersion, 3u);
  Status s{};
  EXPECT_EQ(s.trace_failed, 0);
  EXPECT_LT(offsetof(Status, trace_failed), offsetof(Status, line));
}

TEST(Config, OnTraceFailureIsStopOrContinue) {
  EXPECT_TRUE(load_config(test::default_config()).process.trace_failure_stops) << "stop by default";
  EXPECT_TRUE(parse_config("", "t").process.trace_failure_stops);
  EXPECT_FALSE(parse_config("[process]\non_trace_failure = \"continue\"\n", "t").process.trace_failure_stops);
  EXPECT_TRUE(parse_config("[process]\non_trace_failure = \"stop\"\n", "t").process.trace_failure_stops);
  EXPECT_THROW(parse_config("[process]\non_trace_failure = \"pause\"\n", "t"), ConfigError);
  EXPECT_THROW(parse_config("[process]\non_trace_failure = true\n", "t"), ConfigError);
}

TEST(Config, DefaultConfigLoadsWithItsTravel) {
  const MachineConfig c = load_config(test::default_config());
  for (int i = 0; i < kAxes; ++i) {
    EXPECT_LT(c.axes[i].travel_min_mm, c.axes[i].travel_max_mm);
    EXPECT_NEAR(c.axes[i].travel_max_mm - c.axes[i].travel_min_mm, 25.0, 5.0) << "about 25 mm of travel";
    EXPECT_GT(c.axes[i].max_velocity_mm_s, 0.0);
  }
  EXPECT_DOUBLE_EQ(c.motion.cycle_hz, 2000.0);
  EXPECT_DOUBLE_EQ(c.motion.contouring_angle_deg, 10.0);
  EXPECT_EQ(c.process.socket_mode, 0600);
}

TEST(Config, UnknownKeyIsAnErrorNamingIt) {
  try {
    parse_config("[motion]\ncycle_hz = 2000.0\ncontuoring_angle_deg = 5.0\n", "typo.toml");
    FAIL() << "a misspelt key must not pass";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("motion.contuoring_angle_deg"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("typo.toml"), std::string::npos) << e.what();
  }
}

TEST(Config, OutOfRangeAndWrongTypeAreErrors) {
  EXPECT_THROW(parse_config("[motion]\ncycle_hz = -1.0\n", "t"), ConfigError);
  EXPECT_THROW(parse_config("[motion]\ncycle_hz = \"fast\"\n", "t"), ConfigError);
  EXPECT_THROW(parse_config("[axis.x]\ntravel_min_mm = 10.0\ntravel_max_mm = 5.0\n", "t"), ConfigError);
  EXPECT_THROW(parse_config("[process]\nshm_name = \"no-slash\"\n", "t"), ConfigError);
  EXPECT_THROW(parse_config("[motion\n", "t"), ConfigError);
  EXPECT_THROW(parse_config("[motion]\ncorner_tolerance_mm = -0.01\n", "t"), ConfigError);
  EXPECT_THROW(parse_config("[process]\nrt_spin_us = -5.0\n", "t"), ConfigError);
  EXPECT_EQ(parse_config("[motion]\ncorner_tolerance_mm = 0.01\n", "t").motion.corner_tolerance_mm, 0.01);
  EXPECT_EQ(parse_config("[process]\nrt_spin_us = 200.0\n", "t").process.rt_spin_us, 200.0);
  EXPECT_NO_THROW(parse_config("", "empty"));
}

}  // namespace
}  // namespace pcnc
