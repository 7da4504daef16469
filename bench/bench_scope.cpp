// bench_scope.cpp — what the scope costs the rt: the time of one ScopeRing::publish (the only
// work the cycle does for the scope, every cycle, capture or not), alone and while a reader
// thread drains the ring the way a capture does (every 5 ms, all new samples), and whether
// that reader lost any sample. Prints figures; never fails.
//   bench_scope [--cycles N]
#include <time.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <memory>
#include <thread>
#include <vector>

#include "bench_cli.hpp"
#include "ipc/segment.hpp"

using namespace pcnc;

namespace {

std::uint64_t now_ns() {
  timespec t{};
  clock_gettime(CLOCK_MONOTONIC, &t);
  return static_cast<std::uint64_t>(t.tv_sec) * 1000000000ull + static_cast<std::uint64_t>(t.tv_nsec);
}

struct Figures {
  double p50 = 0, p99 = 0, max = 0;
};

// Publishes `cycles` samples paced at `period_ns` (busy-waiting, like a spinning rt) and
// times each publish.
Figures run(ScopeRing<kScopeSlots>& ring, std::uint64_t cycles, std::uint64_t period_ns) {
  std::vector<double> ns;
  ns.reserve(cycles);
  TraceSample s{};
  std::uint64_t next = now_ns();
  for (std::uint64_t i = 0; i < cycles; ++i) {
    while (now_ns() < next) {
    }
    next += period_ns;
    s.t = static_cast<double>(i) * 0.0005;
    s.commanded[0] = static_cast<double>(i);
    const std::uint64_t a = now_ns();
    ring.publish(s);
    ns.push_back(static_cast<double>(now_ns() - a));
  }
  std::sort(ns.begin(), ns.end());
  return {ns[ns.size() / 2], ns[ns.size() * 99 / 100], ns.back()};
}

}  // namespace

int main(int argc, char** argv) {
  pcnc::BenchCli app{"cost of the rt's scope ring publish, with and without a reader"};
  std::uint64_t cycles = 20000;
  double period_us = 50.0;
  app.add_option("--cycles", cycles, "samples per run")->show_default();
  app.add_option("--period-us", period_us, "pace of the publishes (the rt's is 500 us)")->show_default();
  if (const int rc = app.parse(argc, argv); rc >= 0) return rc;
  const auto period_ns = static_cast<std::uint64_t>(period_us * 1000.0);

  auto ring = std::make_unique<ScopeRing<kScopeSlots>>();
  const Figures alone = run(*ring, cycles, period_ns);

  std::atomic<bool> stop{false};
  std::uint64_t read = 0, lost = 0;
  std::thread reader([&] {
    std::uint64_t next = ring->written();
    while (!stop.load()) {
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
      const std::uint64_t w = ring->written();
      if (w > next + kScopeSlots) lost += w - kScopeSlots - next, next = w - kScopeSlots;
      for (; next < w; ++next) {
        TraceSample s;
        const ScopeRead r = ring->read(next, s);
        if (r == ScopeRead::kOk) ++read;
        if (r == ScopeRead::kLost) ++lost;
        if (r == ScopeRead::kNotYet) break;
      }
    }
  });
  const Figures with = run(*ring, cycles, period_ns);
  stop = true;
  reader.join();

  std::printf("scope ring publish (%zu slots of %zu bytes), %llu samples every %.0f us:\n", kScopeSlots, sizeof(TraceSample),
              static_cast<unsigned long long>(cycles), period_us);
  std::printf("  no reader:              p50 %6.0f ns  p99 %6.0f ns  max %8.0f ns\n", alone.p50, alone.p99, alone.max);
  std::printf("  a capture reading (5 ms): p50 %6.0f ns  p99 %6.0f ns  max %8.0f ns; read %llu, lost %llu\n", with.p50, with.p99,
              with.max, static_cast<unsigned long long>(read), static_cast<unsigned long long>(lost));
  return 0;
}
