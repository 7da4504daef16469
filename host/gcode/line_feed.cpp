// line_feed.cpp — text that grows while it is read (see line_feed.hpp).
#include "gcode/line_feed.hpp"

namespace pcnc {

std::size_t LineFeed::append(std::string_view text) {
  std::size_t n = 0;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (closed_ || text.empty()) return 0;
    text_.append(text);
    if (text_.back() != '\n') text_.push_back('\n');
    for (char c : text) n += c == '\n';
    if (text.back() != '\n') ++n;
    lines_ += n;
  }
  cv_.notify_all();
  return n;
}

void LineFeed::close() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    closed_ = true;
  }
  cv_.notify_all();
}

bool LineFeed::closed() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return closed_;
}

bool LineFeed::waiting() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return waiting_;
}

std::uint64_t LineFeed::done() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return done_;
}

bool LineFeed::line_at(std::uint64_t offset, std::uint64_t done, std::string& line) {
  std::unique_lock<std::mutex> lock(mutex_);
  if (done > done_) {
    done_ = done;
    if (on_done_) {
      lock.unlock();
      const bool go_on = on_done_(done);  // outside the lock: it posts events
      lock.lock();
      if (!go_on) return false;
    }
  }
  auto whole_line = [&] { return offset < text_.size() && text_.find('\n', offset) != std::string::npos; };
  waiting_ = !whole_line() && !closed_;
  cv_.wait(lock, [&] { return whole_line() || closed_; });
  waiting_ = false;
  if (!whole_line()) return false;
  const std::size_t nl = text_.find('\n', offset);
  line.assign(text_, static_cast<std::size_t>(offset), nl - static_cast<std::size_t>(offset));
  return true;
}

std::uint64_t LineFeed::lines_appended() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return lines_;
}

std::uint64_t LineFeed::bytes() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return text_.size();
}

}  // namespace pcnc
