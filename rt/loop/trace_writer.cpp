// trace_writer.cpp — the trace queue's consumer thread (see trace_writer.hpp; the row's text is
// ipc/trace_format). Every fwrite, fputc, fflush and fclose is checked; the first failure is
// kept and reported once, then the queue is drained and discarded.
#include "loop/trace_writer.hpp"

#include <cerrno>
#include <chrono>
#include <cstring>
#include <stdexcept>

namespace pcnc {

namespace {
constexpr auto kFlushEvery = std::chrono::milliseconds(50);
}

TraceWriter::TraceWriter(const std::string& path, std::function<void(const std::string&)> on_failure)
    : path_(path), queue_(std::make_unique<SpscRing<TraceSample, kQueueSlots>>()), on_failure_(std::move(on_failure)) {
  file_ = std::fopen(path.c_str(), "w");
  if (!file_) throw std::runtime_error("cannot create trace file '" + path + "': " + std::strerror(errno));
  if (std::fprintf(file_, "%s\n", trace_csv_header()) < 0) fail("write", errno);
  thread_ = std::thread([this] { run(); });
}

TraceWriter::~TraceWriter() { close(); }

bool TraceWriter::push(const TraceSample& sample) {
  if (!queue_->try_push(sample)) {
    dropped_.fetch_add(1, std::memory_order_relaxed);
    return false;
  }
  return true;
}

void TraceWriter::push_wait(const TraceSample& sample) {
  while (!queue_->try_push(sample)) std::this_thread::sleep_for(std::chrono::microseconds(50));
}

std::string TraceWriter::failure() const { return failed() ? failure_ : std::string(); }

void TraceWriter::fail(const char* what, int err) {
  if (failed_.load(std::memory_order_relaxed)) return;
  if (err == 0) err = EIO;  // a stream error without errno: call it an I/O error
  lost_.fetch_add(unflushed_, std::memory_order_relaxed);
  unflushed_ = 0;
  failure_ = "trace file '" + path_ + "' could not be written (" + what + " failed: " + std::strerror(err) + ", errno " +
             std::to_string(err) + "); the trace is incomplete after about " +
             std::to_string(written_.load(std::memory_order_relaxed) - lost_.load(std::memory_order_relaxed)) + " rows";
  error_.store(err, std::memory_order_relaxed);
  failed_.store(true, std::memory_order_release);
  if (on_failure_) on_failure_(failure_);
}

void TraceWriter::drain() {
  TraceSample s;
  char buf[512];
  while (queue_->try_pop(s)) {
    if (failed_.load(std::memory_order_relaxed)) {
      lost_.fetch_add(1, std::memory_order_relaxed);  // keep the queue moving: the rt never waits on us
      continue;
    }
    const int n = format_trace_row(buf, sizeof buf, s);
    if (n > 0) {
      errno = 0;
      if (std::fwrite(buf, 1, static_cast<std::size_t>(n), file_) != static_cast<std::size_t>(n) ||
          std::fputc('\n', file_) == EOF) {
        fail("write", errno);
        lost_.fetch_add(1, std::memory_order_relaxed);
        continue;
      }
      ++unflushed_;
    }
    written_.fetch_add(1, std::memory_order_relaxed);
  }
}

void TraceWriter::flush() {
  if (failed_.load(std::memory_order_relaxed) || !file_) return;
  errno = 0;
  if (std::fflush(file_) != 0 || std::ferror(file_)) {
    fail("flush", errno);
    return;
  }
  unflushed_ = 0;
}

void TraceWriter::run() {
  auto last_flush = std::chrono::steady_clock::now();
  while (!stop_.load(std::memory_order_acquire)) {
    drain();
    const auto now = std::chrono::steady_clock::now();
    if (now - last_flush >= kFlushEvery) {
      flush();
      last_flush = now;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  drain();
  flush();
}

void TraceWriter::close() {
  if (thread_.joinable()) {
    stop_.store(true, std::memory_order_release);
    thread_.join();
  }
  if (file_) {
    errno = 0;
    const int r = std::fclose(file_);
    file_ = nullptr;
    if (r != 0) fail("close", errno);
  }
}

}  // namespace pcnc
