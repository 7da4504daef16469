// trace_writer.hpp — the per-cycle trace (DESIGN.md trace format) written off the rt thread.
//
// The rt loop owns a TraceWriter and calls push() once per cycle: it copies the sample into
// a lock-free single-producer/single-consumer queue and never blocks, allocates or does I/O;
// when the queue is full the sample is dropped and counted (under --clock virtual the loop
// uses push_wait, which waits for room instead: the trace of a replay is complete). A background thread drains the
// queue into a CSV file in the trace format (ipc/trace_format.hpp, the row and header shared
// with the report's reader). close() (or the destructor) drains what is left and joins.
#pragma once

#include <atomic>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>
#include <thread>

#include "ipc/spsc_ring.hpp"
#include "ipc/trace_format.hpp"

namespace pcnc {

class TraceWriter {
 public:
  static constexpr std::size_t kQueueSlots = 8192;  // ~4 s of cycles at 2 kHz

  /// Opens `path` for writing and starts the writer thread. Throws std::runtime_error when
  /// the file cannot be created.
  explicit TraceWriter(const std::string& path);
  ~TraceWriter();
  TraceWriter(const TraceWriter&) = delete;
  TraceWriter& operator=(const TraceWriter&) = delete;

  /// rt thread: non-blocking. Returns false (and counts a drop) when the queue is full.
  bool push(const TraceSample& sample);
  /// Virtual clock only (not real time): waits for room instead of dropping, so a replayed
  /// program's trace is complete and deterministic.
  void push_wait(const TraceSample& sample);

  /// Drains the queue, flushes and closes the file, joins the thread. Idempotent.
  void close();

  std::uint64_t dropped() const { return dropped_.load(std::memory_order_relaxed); }
  std::uint64_t written() const { return written_.load(std::memory_order_relaxed); }
  const std::string& path() const { return path_; }

 private:
  void run();
  void drain();

  std::string path_;
  std::FILE* file_ = nullptr;
  std::unique_ptr<SpscRing<TraceSample, kQueueSlots>> queue_;
  std::atomic<bool> stop_{false};
  std::atomic<std::uint64_t> dropped_{0};
  std::atomic<std::uint64_t> written_{0};
  std::thread thread_;
};

}  // namespace pcnc
