// line_feed.hpp — G-code text that arrives while the pipeline reads it: the input of a
// streamed program (the grbl port's lines, docs/grbl-protocol.md). A sender appends whole
// lines; the pipeline's LineReader (FromFeed) waits for the next line until it arrives or the
// feed is closed. The text received is kept, so the control flow can go back to a loop's head
// or a subroutine's body that has arrived (a subroutine can be called once its definition has
// been received, as in a file).
//
// Threads: append(), close() and the counters from any thread; line_at() from the reader.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <string>
#include <string_view>

namespace pcnc {

class LineFeed {
 public:
  /// Appends text: whole lines, each ending in '\n' (one is added when missing). Returns the
  /// number of lines appended. Ignored once closed.
  std::size_t append(std::string_view text);
  /// The end of input: a reader waiting at the end gets false.
  void close();
  bool closed() const;

  /// The line that starts at byte `offset` (without its '\n'), once it has arrived; false
  /// when the feed is closed and no line starts there. `done` is the number of the reader's
  /// last line: asking for the next one means the pipeline is done with lines 1..done (their
  /// moves have passed the interpreter and the preflight).
  bool line_at(std::uint64_t offset, std::uint64_t done, std::string& line);
  /// Called (on the reader's thread, outside the lock) each time `done` grows; returning
  /// false ends the input there (line_at returns false: the pipeline has found an error and
  /// must not wait for more lines).
  void set_on_done(std::function<bool(std::uint64_t done)> fn) { on_done_ = std::move(fn); }
  std::uint64_t done() const;
  /// The reader is waiting for a line that has not arrived (everything received is read).
  bool waiting() const;

  std::uint64_t lines_appended() const;
  std::uint64_t bytes() const;

 private:
  mutable std::mutex mutex_;
  std::condition_variable cv_;
  std::string text_;
  std::uint64_t lines_ = 0;
  bool closed_ = false;
  std::uint64_t done_ = 0;
  bool waiting_ = false;
  std::function<bool(std::uint64_t)> on_done_;
};

}  // namespace pcnc
