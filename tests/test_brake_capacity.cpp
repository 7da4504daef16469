// test_brake_capacity.cpp — the executor's per-cycle brake capacity of a NURBS block
// (rt/motion/nurbs_follower.hpp BrakeCapacity: the schedule's whole intervals summed once per
// block) gives block_brake_capacity's answer bit for bit: walking along the block, jumping back
// and forth, at and between the schedule's points, before its start and past its end, on
// schedules with repeated points and short ones, and on a schedule whose arc lengths fall
// (never sent by the host: then it answers with block_brake_capacity itself).
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>

#include "motion/nurbs_follower.hpp"

using namespace pcnc;

namespace {

NurbsGeometry schedule(std::mt19937_64& rng, int n, bool repeats) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  NurbsGeometry g{};
  g.schedule_count = static_cast<std::uint16_t>(n);
  double s = 0.0;
  for (int i = 0; i < n; ++i) {
    if (i > 0 && !(repeats && unit(rng) < 0.2)) s += 0.001 + 2.0 * unit(rng) * unit(rng);
    g.schedule_s[i] = s;
    g.schedule_accel[i] = unit(rng) < 0.1 ? 0.0 : 50.0 + 3000.0 * unit(rng);
  }
  return g;
}

void expect_same(const NurbsGeometry& g, BrakeCapacity& walker, double s) {
  const double want = block_brake_capacity(g, s);
  const double got = walker.at(g, s);
  ASSERT_EQ(std::bit_cast<std::uint64_t>(got), std::bit_cast<std::uint64_t>(want)) << "s " << s << ": " << got << " vs " << want;
}

}  // namespace

TEST(BrakeCapacity, TheWalkIsBlockBrakeCapacityBitForBit) {
  std::mt19937_64 rng(14);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int k = 0; k < 400; ++k) {
    const int n = k % 10 == 0 ? 1 + k % 3 : 2 + static_cast<int>(unit(rng) * (kMaxFeedSchedule - 2));
    const NurbsGeometry g = schedule(rng, n, k % 2 == 0);
    const double end = g.schedule_s[n - 1];
    BrakeCapacity walker;
    walker.start(g);
    // along the block as the executor walks it (the point a few cycles ahead, rising)
    for (double s = -0.01; s < end + 0.05; s += 0.0005 + 0.02 * unit(rng)) expect_same(g, walker, s);
    // exactly at every point, and anywhere in any order
    for (int i = 0; i < n; ++i) expect_same(g, walker, g.schedule_s[i]);
    for (int i = 0; i < 50; ++i) expect_same(g, walker, (unit(rng) * 1.2 - 0.1) * end);
    expect_same(g, walker, std::numeric_limits<double>::quiet_NaN());
    expect_same(g, walker, 0.0);
  }
}

TEST(BrakeCapacity, AScheduleWhoseArcLengthsFallIsAnsweredAsBefore) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  NurbsGeometry g = schedule(rng, 20, false);
  std::swap(g.schedule_s[7], g.schedule_s[12]);
  BrakeCapacity walker;
  walker.start(g);
  for (int i = 0; i < 200; ++i) expect_same(g, walker, unit(rng) * g.schedule_s[19]);
}
