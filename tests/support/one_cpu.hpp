// one_cpu.hpp — pins the calling process (and the processes it starts from then on, which
// inherit the mask) to the first CPU it may run on, and puts the old mask back when it goes:
// for tests of the two processes' hand-off on a single core, its harshest schedule.
#pragma once

#include <sched.h>

namespace pcnc::test {

class OneCpu {
 public:
  OneCpu() {
    if (sched_getaffinity(0, sizeof old_, &old_) != 0) return;
    int cpu = 0;
    while (cpu < CPU_SETSIZE && !CPU_ISSET(cpu, &old_)) ++cpu;
    cpu_set_t one;
    CPU_ZERO(&one);
    CPU_SET(cpu, &one);
    pinned_ = sched_setaffinity(0, sizeof one, &one) == 0;
  }
  ~OneCpu() {
    if (pinned_) sched_setaffinity(0, sizeof old_, &old_);
  }
  OneCpu(const OneCpu&) = delete;
  OneCpu& operator=(const OneCpu&) = delete;
  /// The pin took effect.
  bool pinned() const { return pinned_; }

 private:
  cpu_set_t old_{};
  bool pinned_ = false;
};

}  // namespace pcnc::test
