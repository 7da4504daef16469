// rt_loop.cpp — the 2 kHz loop around Machine: timing, mailbox, host wake-ups, status.
#include "loop/rt_loop.hpp"

#include <time.h>

#include <algorithm>
#include <cerrno>
#include <cmath>

#include "loop/trace_writer.hpp"

namespace pcnc {

namespace {
constexpr std::uint64_t kNsPerS = 1000000000ull;
constexpr int kVirtualPublishCycles = 8;  // 4 ms of machine time, a few µs of wall time
// Virtual clock, waiting for the host's next block: spin up to 10 µs, then sleep until the
// host publishes it. A host with the block staged copies it in within 1-2 µs; one that is
// still making it (a smoothed curve) or has no core (a busy machine) may take milliseconds,
// and a longer spin would only take the core from it (or from the trace writer). With both
// processes pinned to one CPU, LHchips4 at tolerance 0 replayed in 0.46 s with this spin,
// 0.62 s with 20 µs (the host's wait as now), 5 s when both sides spun 200 µs (docs/replay.md).
constexpr std::uint64_t kVirtualSpinNs = 10000;
constexpr std::uint32_t kVirtualTimedCycles = 8;  // cycles timed with one clock read (run())

timespec to_timespec(std::uint64_t ns) {
  timespec t{};
  t.tv_sec = static_cast<time_t>(ns / kNsPerS);
  t.tv_nsec = static_cast<long>(ns % kNsPerS);
  return t;
}
}  // namespace

RtLoop::RtLoop(const MachineConfig& config, SharedSegment& shm, const RtLoopOptions& options)
    : config_(config),
      shm_(shm),
      options_(options),
      machine_(std::make_unique<Machine>(config)),
      timing_(std::make_unique<CycleTiming>()),
      host_timeout_ns_(static_cast<std::uint64_t>(config.process.host_timeout_s * 1e9)),
      summary_period_(std::max(1, static_cast<int>(config.motion.cycle_hz / 10.0))),
      settle_cycles_(std::max(1, static_cast<int>(config.motion.cycle_hz / 100.0))) {
  if (!options_.trace_path.empty() || !options_.trace_digest_path.empty()) {
    trace_ = std::make_unique<TraceWriter>(TraceFiles{options_.trace_path, options_.trace_digest_path, config.rotary_mask()},
                                           options_.on_trace_failure);
  }
  if (options_.start_position) machine_->take_up_position(*options_.start_position);
  if (options_.start_rotary) machine_->take_up_rotary(*options_.start_rotary);
}

std::string RtLoop::close_trace() {
  if (!trace_) return "";
  trace_->close();
  return trace_->failure();
}

RtLoop::~RtLoop() = default;

bool RtLoop::host_alive(std::uint64_t now_ns) const {
  const std::uint64_t beat = shm_.header.host_heartbeat_ns.load(std::memory_order_acquire);
  return beat != 0 && now_ns < beat + host_timeout_ns_;
}

bool RtLoop::stop_now(const StopRequest& stop) {
  const int level = stop.level();
  if (level == 0) return false;
  const Status& s = machine_->status();
  const std::uint64_t now = monotonic_ns();
  ShutdownReport& r = shutdown_;
  if (!r.requested) {
    r.requested = true;
    r.signal = stop.signal();
    r.state_at_request = s.state;
    r.speed_at_request = s.path_speed;
    r.was_moving = !machine_->motion_at_rest();
    stop_begin_ns_ = now;
    stop_begin_cycle_ = s.cycle;
    stop_seen_cycle_ = s.cycle;
    stop_last_actual_ = s.actual;
    still_cycles_ = 0;
    machine_->begin_shutdown();
  }
  const double dt = config_.cycle_period_s();
  auto finish = [&] {
    r.wall_s = static_cast<double>(now - stop_begin_ns_) * 1e-9;
    r.settled_s = static_cast<double>(s.cycle - stop_begin_cycle_) * dt;
    r.final_state = s.state;
    r.final_speed = s.path_speed;
    return true;
  };
  if (level >= 2) {
    r.immediate = true;
    r.second_signal = stop.second_signal();
    return finish();
  }
  if (s.cycle != stop_seen_cycle_) {  // one new cycle since the last look
    stop_seen_cycle_ = s.cycle;
    bool still = machine_->motion_at_rest();
    if (still && rest_cycle_ == 0) {
      rest_cycle_ = s.cycle;
      r.motion_rest_s = static_cast<double>(s.cycle - stop_begin_cycle_) * dt;
    }
    if (!still) rest_cycle_ = 0;
    for (int i = 0; i < kAxes; ++i) {
      // one encoder count of dither is standing still
      const double count = std::max(config_.axes[i].encoder_resolution_mm, 1e-7);
      if (std::abs(s.actual[i] - stop_last_actual_[i]) > 1.5 * count) still = false;
    }
    stop_last_actual_ = s.actual;
    still_cycles_ = still ? still_cycles_ + 1 : 0;
    if (still_cycles_ >= settle_cycles_) {
      r.at_rest = true;
      return finish();
    }
  }
  if (static_cast<double>(now - stop_begin_ns_) * 1e-9 >= options_.shutdown_timeout_s) {
    r.timed_out = true;
    return finish();
  }
  return false;
}

void RtLoop::take_commands(std::uint64_t now_ns) {
  shm_.header.rt_heartbeat_ns.store(now_ns, std::memory_order_release);
  Command cmd;
  while (shm_.commands.try_pop(cmd)) machine_->command(cmd);
  machine_->set_host_alive(host_alive(now_ns));
}

void RtLoop::cycle(std::uint64_t now_ns) {
  take_commands(now_ns);
  if (trace_ && !trace_failed_ && trace_->failed()) {  // one atomic load; the writer thread logged it
    trace_failed_ = true;
    machine_->trace_failed(config_.process.trace_failure_stops);
  }

  const std::uint64_t popped_before = shm_.motion.popped();
  machine_->cycle(shm_.motion);
  if (shm_.motion.popped() != popped_before) {
    // the virtual clock's now_ns is the start of a timed run (run()): read the clock here, the
    // host's refill latency is measured from it
    shm_.header.slot_freed_ns.store(options_.virtual_clock ? monotonic_ns() : now_ns, std::memory_order_release);
    shm_.slot_freed.notify();
  }
  const TraceSample& sample = machine_->trace_sample();
  shm_.scope.publish(sample);  // the scope's flight recorder: never waits
  if (trace_) {
    if (options_.virtual_clock) {
      trace_->push_wait(sample, machine_->trace_joints());
    } else {
      trace_->push(sample, machine_->trace_joints());
    }
  }

  if (options_.virtual_clock) {
    publish_status_virtual(false);
  } else {
    publish_status();
  }
}

void RtLoop::publish_status_virtual(bool force) {
  const Status& s = machine_->status();
  if (!force && ++unpublished_cycles_ < kVirtualPublishCycles && s.state == published_state_ &&
      s.program_done == published_done_) {
    return;
  }
  if (force && unpublished_cycles_ == 0) return;  // nothing new since the last one
  publish_status();
}

void RtLoop::publish_status() {
  Status s = machine_->status();
  // The quantiles scan histograms: refresh them ten times a second of machine time, not
  // every cycle.
  if (summary_age_ == 0) timing_summary_ = timing_->summary();
  if (++summary_age_ >= summary_period_) summary_age_ = 0;
  s.timing = timing_summary_;
  s.clock_virtual = options_.virtual_clock ? 1 : 0;
  s.ring_fill = static_cast<std::uint8_t>(shm_.motion.size());
  shm_.status.store(s);
  unpublished_cycles_ = 0;
  published_state_ = s.state;
  published_done_ = s.program_done;
}

std::uint64_t RtLoop::run(const StopRequest& stop) {
  const std::uint64_t period_ns = static_cast<std::uint64_t>(1e9 / config_.motion.cycle_hz + 0.5);
  std::uint64_t cycles = 0;

  if (options_.virtual_clock) {
    // Same cycle, no sleeping: time is simulated. Before every cycle the ring is filled from
    // the replay stage the host writes into (take_staged, ipc/segment.hpp). While a program
    // needs blocks that the host has not written yet, wait for the host instead of advancing
    // time, so that replays are deterministic. When the machine is at rest with nothing to
    // do, wait too (10 ms steps) instead of burning a core.
    // Compute time is measured over runs of up to kVirtualTimedCycles cycles with no wait
    // between them, loop overhead included, and each cycle of a run counts with the run's
    // mean: one clock read per run instead of one per cycle (the clock is a good part of a
    // 0.5 µs cycle). `last` is the clock at the run's start; the cycles take it as their time
    // (the heartbeat), a few µs old at most.
    std::uint64_t last = monotonic_ns();
    std::uint32_t run_cycles = 0;
    auto end_timed_run = [&] {
      if (run_cycles == 0) return;
      const std::uint64_t now = monotonic_ns();
      timing_->compute.add(static_cast<double>(now - last) / 1000.0 / run_cycles, run_cycles);
      last = now;
      run_cycles = 0;
    };
    while (!stop_now(stop)) {
      if (!shm_.commands.empty()) {
        take_commands(last);
        publish_status();  // the host sees its commands taken even before time advances
      }
      take_staged(shm_);
      const MachineState st = machine_->status().state;
      const bool at_rest = (st != MachineState::kRunning && st != MachineState::kJogging &&
                            st != MachineState::kStopping && st != MachineState::kPaused && shm_.motion.empty()) ||
                           machine_->paused_at_rest();
      if (machine_->wants_more_blocks(shm_.motion)) {
        end_timed_run();
        publish_status_virtual(true);
        shm_.block_published.wait_until(
            [&] {
              return !shm_.commands.empty() || !shm_.stage.empty() || !machine_->wants_more_blocks(shm_.motion) ||
                     stop.level() > 0;
            },
            0.01, kVirtualSpinNs);
        take_staged(shm_);
        last = monotonic_ns();
        // Still waiting for the host (and it is alive): do not advance time.
        if (machine_->wants_more_blocks(shm_.motion) && host_alive(last) && stop.level() == 0) continue;
      } else if (at_rest) {
        // Idle: sleep until something arrives, running a cycle now and then so that the
        // plant settles and status and heartbeat stay fresh.
        end_timed_run();
        publish_status_virtual(true);
        const bool paused = st == MachineState::kPaused;
        shm_.block_published.wait_until(
            [&] {
              return !shm_.commands.empty() || (!paused && !(shm_.motion.empty() && shm_.stage.empty())) ||
                     stop.level() > 0;
            },
            0.01);
        take_staged(shm_);
        last = monotonic_ns();
        if (!shm_.commands.empty()) continue;  // take them before stepping time
      }
      cycle(last);
      if (++run_cycles == kVirtualTimedCycles) end_timed_run();
      ++cycles;
    }
    end_timed_run();
    publish_status_virtual(true);
    return cycles;
  }

  // Sleep to `spin` before the deadline, then spin to it (process.rt_spin_us; never the
  // whole period).
  const std::uint64_t spin_ns =
      std::min(static_cast<std::uint64_t>(config_.process.rt_spin_us * 1000.0), period_ns * 9 / 10);
  std::uint64_t next = monotonic_ns() + period_ns;
  while (!stop_now(stop)) {
    // A signal interrupts the sleep: the first one is taken at the next cycle (the machine
    // comes to rest first), a second one ends the loop at once.
    const timespec deadline = to_timespec(next - spin_ns);
    while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &deadline, nullptr) == EINTR) {
      if (stop.level() >= 2) {
        stop_now(stop);
        return cycles;
      }
    }
    if (spin_ns > 0) {
      while (monotonic_ns() < next) {
#if defined(__x86_64__) || defined(__i386__)
        __builtin_ia32_pause();
#endif
      }
    }
    const std::uint64_t woke = monotonic_ns();
    const std::uint64_t late = woke > next ? woke - next : 0;
    timing_->wake.add(static_cast<double>(late) / 1000.0);
    cycle(woke);
    const std::uint64_t done = monotonic_ns();
    timing_->compute.add(static_cast<double>(done - woke) / 1000.0);
    ++cycles;
    next += period_ns;
    if (done > next) {
      // Missed the next deadline: count it and re-anchor instead of running a burst of
      // late cycles back to back.
      ++timing_->overruns;
      const std::uint64_t behind = (done - next) / period_ns + 1;
      next += behind * period_ns;
    }
  }
  return cycles;
}

}  // namespace pcnc
