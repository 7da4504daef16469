// bench_ring.cpp — figures for the motion ring between two real processes (issue 2):
//  1. throughput: a forked producer (the host's RingFeeder) and a consumer (in the rt's role)
//     pass N blocks as fast as they can; blocks per second.
//  2. wake-up latency: the consumer frees one slot every 500 µs, like the 2 kHz rt, while the
//     producer sleeps on the slot-freed semaphore; latency from the free to the producer's
//     next publish (the feeder's refill latency), p50/p99/max.
// Prints figures; never fails on them.
#include <sys/mman.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <cstdio>

#include "bench_cli.hpp"
#include "service/ring_feeder.hpp"
#include "ipc/segment.hpp"

using namespace pcnc;

namespace {

struct Shared {
  LatencyHistogram refill;  // written by the producer at its end, read by the parent
  std::uint64_t pushed = 0;
};

MachineConfig bench_config() {
  MachineConfig c;
  c.process.shm_name = "/pcnc-bench-ring-" + std::to_string(getpid());
  c.process.rt_timeout_s = 60.0;
  return c;
}

pid_t start_producer(const MachineConfig& config, std::uint64_t total, Shared* out) {
  const pid_t pid = fork();
  if (pid != 0) return pid;
  RtLink link(config);
  RingFeeder feeder(link);
  std::uint64_t n = 0;  // the fill is a stream: each call makes the next block
  auto fill = [&](Block& b) {
    if (n >= total) return false;
    ++n;
    b.line = static_cast<std::uint32_t>(n);
    b.kind = BlockKind::kLine;
    b.end = {static_cast<double>(n), 0.0, 0.0};
    return true;
  };
  while (feeder.push(fill) == FeedResult::kPushed) {
  }
  out->refill = feeder.refill_latency();
  out->pushed = feeder.pushed();
  _exit(0);
}

}  // namespace

int main(int argc, char** argv) {
  pcnc::BenchCli app{"bench_ring: two-process motion-ring throughput and host wake-up latency"};
  std::uint64_t blocks = 2000000;
  double seconds = 10.0;
  app.add_option("--blocks", blocks, "blocks for the throughput run")->show_default();
  app.add_option("--latency-seconds", seconds, "duration of the 2 kHz wake-up run")->show_default();
  if (const int rc = app.parse(argc, argv); rc >= 0) return rc;

  const MachineConfig config = bench_config();
  RtSegment rt(config.process.shm_name);
  SharedSegment& shm = rt.shm();
  auto* shared = static_cast<Shared*>(mmap(nullptr, sizeof(Shared), PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS, -1, 0));
  new (shared) Shared();

  // 1. throughput
  shm.header.rt_heartbeat_ns.store(monotonic_ns());
  const std::uint64_t t0 = monotonic_ns();
  pid_t producer = start_producer(config, blocks, shared);
  std::uint64_t got = 0, checksum = 0;
  while (got < blocks) {
    if (shm.motion.empty()) {
      shm.header.rt_heartbeat_ns.store(monotonic_ns());
      shm.block_published.wait_until([&] { return !shm.motion.empty(); }, 0.1);
      continue;
    }
    checksum += shm.motion.peek(0).line;
    shm.motion.pop();
    shm.slot_freed.notify();
    ++got;
  }
  const double secs = static_cast<double>(monotonic_ns() - t0) / 1e9;
  waitpid(producer, nullptr, 0);
  const bool intact = checksum == blocks * (blocks + 1) / 2;
  std::printf("ring throughput: %llu blocks (%zu-byte slots) in %.3f s = %.0f blocks/s%s\n",
              static_cast<unsigned long long>(blocks), sizeof(Block), secs, static_cast<double>(blocks) / secs,
              intact ? "" : "  (CHECKSUM MISMATCH)");

  // 2. wake-up latency at the rt's pace: free one slot every period, producer sleeping.
  const std::uint64_t period_ns = 500000;
  const auto n = static_cast<std::uint64_t>(seconds * 2000.0);
  new (shared) Shared();
  producer = start_producer(config, n + kRingSlots, shared);
  // let it fill the ring
  while (shm.motion.size() < kRingSlots) shm.block_published.wait_until([&] { return shm.motion.size() == kRingSlots; }, 0.1);
  std::uint64_t next = monotonic_ns() + period_ns;
  for (std::uint64_t i = 0; i < n + kRingSlots; ++i) {
    timespec ts{static_cast<time_t>(next / 1000000000ull), static_cast<long>(next % 1000000000ull)};
    clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr);
    next += period_ns;
    shm.header.rt_heartbeat_ns.store(monotonic_ns());
    if (shm.motion.empty()) continue;
    shm.motion.pop();
    shm.header.slot_freed_ns.store(monotonic_ns(), std::memory_order_release);
    shm.slot_freed.notify();
  }
  waitpid(producer, nullptr, 0);
  const LatencyHistogram& h = shared->refill;
  std::printf("host wake-up after a slot frees (2 kHz consumer, %llu wake-ups): p50 %.1f us  p99 %.1f us  max %.1f us  mean %.1f us\n",
              static_cast<unsigned long long>(h.count()), h.quantile(0.5), h.quantile(0.99), h.max(), h.mean());
  return 0;
}
