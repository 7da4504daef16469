// trace_writer.cpp — the trace queue's consumer thread (see trace_writer.hpp; the row's text is ipc/trace_format).
#include "loop/trace_writer.hpp"

#include <cerrno>
#include <chrono>
#include <cstring>
#include <stdexcept>

namespace pcnc {

TraceWriter::TraceWriter(const std::string& path)
    : path_(path), queue_(std::make_unique<SpscRing<TraceSample, kQueueSlots>>()) {
  file_ = std::fopen(path.c_str(), "w");
  if (!file_) throw std::runtime_error("cannot create trace file '" + path + "': " + std::strerror(errno));
  std::fprintf(file_, "%s\n", trace_csv_header());
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

void TraceWriter::drain() {
  TraceSample s;
  char buf[512];
  while (queue_->try_pop(s)) {
    const int n = format_trace_row(buf, sizeof buf, s);
    if (n > 0) {
      std::fwrite(buf, 1, static_cast<std::size_t>(n), file_);
      std::fputc('\n', file_);
    }
    written_.fetch_add(1, std::memory_order_relaxed);
  }
}

void TraceWriter::run() {
  while (!stop_.load(std::memory_order_acquire)) {
    drain();
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  drain();
}

void TraceWriter::close() {
  if (thread_.joinable()) {
    stop_.store(true, std::memory_order_release);
    thread_.join();
  }
  if (file_) {
    std::fclose(file_);
    file_ = nullptr;
  }
}

}  // namespace pcnc
