// trace_writer.cpp — the trace queue's consumer thread (see trace_writer.hpp; the row's text is
// ipc/trace_format, the compact trace ipc/trace_compact). Every fwrite, fputc, fflush and
// fclose is checked; the first failure is kept and reported once, then the queue is drained
// and discarded.
#include "loop/trace_writer.hpp"

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <stdexcept>

namespace pcnc {

namespace {
constexpr auto kFlushEvery = std::chrono::milliseconds(50);
}

TraceWriter::TraceWriter(const std::string& path, std::function<void(const std::string&)> on_failure)
    : TraceWriter(TraceFiles{path, ""}, std::move(on_failure)) {}

TraceWriter::TraceWriter(const TraceFiles& files, std::function<void(const std::string&)> on_failure)
    : files_(files), queue_(std::make_unique<SpscRing<TraceEntry, kQueueSlots>>()), on_failure_(std::move(on_failure)) {
  if (!files_.csv.empty()) {
    file_ = std::fopen(files_.csv.c_str(), "w");
    if (!file_) throw std::runtime_error("cannot create trace file '" + files_.csv + "': " + std::strerror(errno));
    if (std::fprintf(file_, "%s\n", trace_csv_header(files_.rotary).c_str()) < 0) fail(files_.csv, "write", errno);
  }
  if (!files_.compact.empty()) {
    compact_ = std::fopen(files_.compact.c_str(), "wb");
    if (!compact_) {
      const int err = errno;
      if (file_) std::fclose(file_);
      throw std::runtime_error("cannot create compact trace file '" + files_.compact + "': " + std::strerror(err));
    }
    const CompactHeader header;
    errno = 0;
    if (std::fwrite(&header, sizeof header, 1, compact_) != 1) fail(files_.compact, "write", errno);
    builder_ = std::make_unique<CompactTraceBuilder>([this](const CompactRun& r) { write_compact_run(r); }, files_.rotary);
  }
  thread_ = std::thread([this] { run(); });
}

TraceWriter::~TraceWriter() { close(); }

// The row goes into the slot in place, published with a release store (the writer polls the
// queue; no wake-up is ordered after it): a seq_cst store would stall the rt's core until the
// row's stores reached the cache. With no joints on the machine and none in the row, the
// slot's joints are left as they are (their mask 0: neither file reads the rest), half the
// bytes of a row.
void TraceWriter::put(TraceEntry& slot, const TraceSample& sample, const TraceJoints& joints) const {
  slot.sample = sample;
  if (joints.mask != 0 || files_.rotary != 0) {
    slot.joints = joints;
  } else {
    slot.joints.mask = 0;
  }
}

bool TraceWriter::push(const TraceSample& sample, const TraceJoints& joints) {
  TraceEntry* slot = queue_->begin_push();
  if (!slot) {
    dropped_.fetch_add(1, std::memory_order_relaxed);
    return false;
  }
  put(*slot, sample, joints);
  queue_->commit_push(std::memory_order_release);
  return true;
}

void TraceWriter::push_wait(const TraceSample& sample, const TraceJoints& joints) {
  TraceEntry* slot = nullptr;
  while (!(slot = queue_->begin_push())) std::this_thread::sleep_for(std::chrono::microseconds(50));
  put(*slot, sample, joints);
  queue_->commit_push(std::memory_order_release);
}

std::string TraceWriter::failure() const { return failed() ? failure_ : std::string(); }

void TraceWriter::fail(const std::string& path, const char* what, int err) {
  if (failed_.load(std::memory_order_relaxed)) return;
  if (err == 0) err = EIO;  // a stream error without errno: call it an I/O error
  lost_.fetch_add(unflushed_, std::memory_order_relaxed);
  unflushed_ = 0;
  failure_ = "trace file '" + path + "' could not be written (" + what + " failed: " + std::strerror(err) + ", errno " +
             std::to_string(err) + "); the trace is incomplete after about " +
             std::to_string(written_.load(std::memory_order_relaxed) - lost_.load(std::memory_order_relaxed)) + " rows";
  error_.store(err, std::memory_order_relaxed);
  failed_.store(true, std::memory_order_release);
  if (on_failure_) on_failure_(failure_);
}

void TraceWriter::drain() {
  // In batches read in place and freed with one store (SpscRing::pop_n): the rt's push reads
  // the queue's tail every cycle, and a tail that changed with every row cost it a cache miss
  // per row. A batch is small enough that the rt never waits long for room.
  constexpr std::size_t kBatch = 256;
  for (;;) {
    const std::size_t n = std::min(queue_->size(), kBatch);
    if (n == 0) return;
    for (std::size_t i = 0; i < n; ++i) take(queue_->peek(i));
    queue_->pop_n(n);
  }
}

void TraceWriter::take(const TraceEntry& e) {
  const TraceSample& s = e.sample;
  if (failed_.load(std::memory_order_relaxed)) {
    lost_.fetch_add(1, std::memory_order_relaxed);  // keep the queue moving: the rt never waits on us
    return;
  }
  if (file_) {
    char buf[640];
    const int n = format_trace_row(buf, sizeof buf, s, e.joints);
    if (n > 0) {
      errno = 0;
      if (std::fwrite(buf, 1, static_cast<std::size_t>(n), file_) != static_cast<std::size_t>(n) ||
          std::fputc('\n', file_) == EOF) {
        fail(files_.csv, "write", errno);
        lost_.fetch_add(1, std::memory_order_relaxed);
        return;
      }
    }
  }
  if (builder_) builder_->add(s, e.joints);  // may write a completed run
  ++unflushed_;
  written_.fetch_add(1, std::memory_order_relaxed);
}

void TraceWriter::write_compact_run(const CompactRun& run) {
  if (failed_.load(std::memory_order_relaxed)) return;
  errno = 0;
  if (std::fwrite(&run, sizeof run, 1, compact_) != 1) fail(files_.compact, "write", errno);
}

void TraceWriter::flush() {
  if (failed_.load(std::memory_order_relaxed)) return;
  for (auto [f, path] : {std::pair{file_, &files_.csv}, std::pair{compact_, &files_.compact}}) {
    if (!f) continue;
    errno = 0;
    if (std::fflush(f) != 0 || std::ferror(f)) {
      fail(*path, "flush", errno);
      return;
    }
  }
  unflushed_ = 0;
}

// After the last row: the last run, the totals, slices, path, the joints (rotary machines) and the footer that marks the
// file complete (a reader refuses a compact trace without it).
void TraceWriter::finish_compact() {
  const CompactTotals totals = builder_->finish();
  if (failed_.load(std::memory_order_relaxed)) return;
  errno = 0;
  const long offset = std::ftell(compact_);
  CompactFooter footer;
  footer.totals_offset = offset < 0 ? 0 : static_cast<std::uint64_t>(offset);
  const auto& slices = builder_->slices();
  const auto& points = builder_->points();
  if (offset < 0 || std::fwrite(&totals, sizeof totals, 1, compact_) != 1 ||
      std::fwrite(slices.data(), sizeof(CompactSlice), slices.size(), compact_) != slices.size() ||
      std::fwrite(points.data(), sizeof(CompactPoint), points.size(), compact_) != points.size() ||
      !write_joint_section(totals) || std::fwrite(&footer, sizeof footer, 1, compact_) != 1) {
    fail(files_.compact, "write", errno);
  }
}

// A rotary machine's joint section (ipc/trace_compact.hpp); nothing for a 3-axis machine.
bool TraceWriter::write_joint_section(const CompactTotals& totals) {
  if (totals.rotary_mask == 0) return true;
  const CompactJointTotals& jt = builder_->joint_totals();
  const auto& slices = builder_->joint_slices();
  const auto& points = builder_->joint_points();
  return std::fwrite(&jt, sizeof jt, 1, compact_) == 1 &&
         std::fwrite(slices.data(), sizeof(CompactJointSlice), slices.size(), compact_) == slices.size() &&
         std::fwrite(points.data(), sizeof(CompactJointPoint), points.size(), compact_) == points.size();
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
    std::unique_lock<std::mutex> lock(wake_mutex_);
    wake_.wait_for(lock, std::chrono::milliseconds(2), [this] { return stop_.load(std::memory_order_acquire); });
  }
  drain();
  if (builder_) finish_compact();
  flush();
}

void TraceWriter::close() {
  if (thread_.joinable()) {
    {
      std::lock_guard<std::mutex> lock(wake_mutex_);
      stop_.store(true, std::memory_order_release);
    }
    wake_.notify_all();
    thread_.join();
  }
  for (auto [f, path] : {std::pair{&file_, &files_.csv}, std::pair{&compact_, &files_.compact}}) {
    if (!*f) continue;
    errno = 0;
    const int r = std::fclose(*f);
    *f = nullptr;
    if (r != 0) fail(*path, "close", errno);
  }
}

}  // namespace pcnc
