// trace_writer.hpp — the per-cycle trace (DESIGN.md trace format) written off the rt thread.
//
// The rt loop owns a TraceWriter and calls push() once per cycle: it copies the sample into
// a lock-free single-producer/single-consumer queue and never blocks, allocates or does I/O;
// when the queue is full the sample is dropped and counted (under --clock virtual the loop
// uses push_wait, which waits for room instead: the trace of a replay is complete). A background thread drains the
// queue into a CSV file in the trace format (ipc/trace_format.hpp, the row and header shared
// with the report's reader). close() (or the destructor) drains what is left and joins.
//
// It writes the full CSV (--trace), the compact trace the run report reads (--trace-digest:
// ipc/trace_compact.hpp, built here from every row with its joints, off the rt thread; its summary records
// are written at close()), or both.
//
// Every write, flush and close is checked (the buffer is flushed at least every 50 ms, so a
// full disk shows within that). The first failure is recorded (errno), reported once through
// the on_failure callback from the writer thread (never the rt thread), and failed() turns
// true for the loop to read; the writer keeps draining the queue after it, discarding, so the
// rt never waits on it. A trace that failed is incomplete: rows after the failure are lost.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "ipc/spsc_ring.hpp"
#include "ipc/trace_compact.hpp"
#include "ipc/trace_format.hpp"

namespace pcnc {

/// The files a TraceWriter writes; either may be empty (none), not both.
struct TraceFiles {
  std::string csv;      // the per-cycle CSV
  std::string compact;  // the compact trace for the report
  RotaryMask rotary = 0;  // the machine's rotary joints: their columns in the CSV
};

class TraceWriter {
 public:
  static constexpr std::size_t kQueueSlots = 8192;  // ~4 s of cycles at 2 kHz

  /// Opens `path` for writing and starts the writer thread. Throws std::runtime_error when
  /// the file cannot be created.
  /// `on_failure` (optional) receives one line naming the path and the error, from the
  /// writer thread (or from close()), once.
  explicit TraceWriter(const std::string& path, std::function<void(const std::string&)> on_failure = {});
  /// The CSV, the compact trace, or both (TraceFiles).
  explicit TraceWriter(const TraceFiles& files, std::function<void(const std::string&)> on_failure = {});
  ~TraceWriter();
  TraceWriter(const TraceWriter&) = delete;
  TraceWriter& operator=(const TraceWriter&) = delete;

  /// rt thread: non-blocking. Returns false (and counts a drop) when the queue is full. The row
  /// is written into the queue's slot in place (a 3-axis machine's slot keeps its empty joints).
  bool push(const TraceSample& sample, const TraceJoints& joints);
  bool push(const TraceEntry& e) { return push(e.sample, e.joints); }
  bool push(const TraceSample& sample) { return push(sample, TraceJoints{}); }
  /// Virtual clock only (not real time): waits for room instead of dropping, so a replayed
  /// program's trace is complete and deterministic.
  void push_wait(const TraceSample& sample, const TraceJoints& joints);
  void push_wait(const TraceEntry& e) { push_wait(e.sample, e.joints); }
  void push_wait(const TraceSample& sample) { push_wait(sample, TraceJoints{}); }

  /// Drains the queue, flushes and closes the file, joins the thread. Idempotent.
  void close();

  std::uint64_t dropped() const { return dropped_.load(std::memory_order_relaxed); }
  std::uint64_t written() const { return written_.load(std::memory_order_relaxed); }
  /// The CSV's path, else the compact trace's.
  const std::string& path() const { return files_.csv.empty() ? files_.compact : files_.csv; }

  /// A write, flush or close failed: the file holds the header and `written()` rows at most.
  bool failed() const { return failed_.load(std::memory_order_acquire); }
  /// errno of the first failure (0 before any).
  int error() const { return error_.load(std::memory_order_relaxed); }
  /// Rows lost: taken from the queue after the failure, or in the buffer it failed to write.
  std::uint64_t lost() const { return lost_.load(std::memory_order_relaxed); }
  /// What failed, in words ("" before any failure; final once failed() is true).
  std::string failure() const;

 private:
  void run();
  void put(TraceEntry& slot, const TraceSample& sample, const TraceJoints& joints) const;
  void drain();
  void take(const TraceEntry& e);  // one row into the files
  void flush();
  void fail(const std::string& path, const char* what, int err);
  void write_compact_run(const CompactRun& run);
  void finish_compact();
  bool write_joint_section(const CompactTotals& totals);

  TraceFiles files_;
  std::FILE* file_ = nullptr;     // the CSV (null: none)
  std::FILE* compact_ = nullptr;  // the compact trace (null: none)
  std::unique_ptr<CompactTraceBuilder> builder_;
  std::unique_ptr<SpscRing<TraceEntry, kQueueSlots>> queue_;
  std::atomic<bool> stop_{false};
  std::mutex wake_mutex_;  // with wake_: close() ends the writer's 2 ms sleep at once (never the rt thread)
  std::condition_variable wake_;
  std::atomic<std::uint64_t> dropped_{0};
  std::atomic<std::uint64_t> written_{0};
  std::atomic<std::uint64_t> lost_{0};
  std::atomic<bool> failed_{false};
  std::atomic<int> error_{0};
  std::uint64_t unflushed_ = 0;  // rows handed to stdio since the last successful flush
  std::function<void(const std::string&)> on_failure_;
  std::string failure_;  // set once, before failed_ turns true
  std::thread thread_;
};

}  // namespace pcnc
