// line_reader.cpp — chunked, allocation-free line splitting over read(2).
#include "gcode/line_reader.hpp"

#include "gcode/line_feed.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace pcnc {

int open_program_file(const std::string& path, std::string* why) {
  // O_NONBLOCK: opening a FIFO with no writer (or a device) must not wait; nothing is read
  // before fstat says it is a regular file.
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK | O_NOCTTY);
  if (fd < 0) {
    if (why) *why = path + ": cannot open: " + std::strerror(errno);
    return -1;
  }
  struct stat st {};
  if (::fstat(fd, &st) != 0) {
    if (why) *why = path + ": cannot stat: " + std::strerror(errno);
    ::close(fd);
    return -1;
  }
  if (!S_ISREG(st.st_mode)) {
    const char* kind = S_ISDIR(st.st_mode)    ? "a directory"
                       : S_ISFIFO(st.st_mode) ? "a FIFO"
                       : S_ISCHR(st.st_mode)  ? "a character device"
                       : S_ISBLK(st.st_mode)  ? "a block device"
                       : S_ISSOCK(st.st_mode) ? "a socket"
                                              : "not a regular file";
    if (why) *why = path + ": is " + kind + ", expected a G-code file (only regular files are read)";
    ::close(fd);
    return -1;
  }
  // A regular file never blocks; clear the flag anyway so reads behave as usual.
  (void)::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) & ~O_NONBLOCK);
  return fd;
}

LineReader::LineReader(const std::string& path) : path_(path) {
  std::string why;
  fd_ = open_program_file(path, &why);
  if (fd_ < 0) throw std::runtime_error(why);
  struct stat st {};
  if (::fstat(fd_, &st) == 0) total_ = static_cast<std::uint64_t>(st.st_size);
  buf_.resize(kChunk + kMaxLine);
}

LineReader::LineReader(FromText, std::string_view text)
    : text_(text), full_text_(text), from_text_(true), total_(text.size()) {}

LineReader::LineReader(Generated, std::string text, std::shared_ptr<const SourcePlaces> places)
    : owned_(std::move(text)), places_(std::move(places)), from_text_(true) {
  text_ = full_text_ = owned_;
  total_ = owned_.size();
}

LineReader::LineReader(FromFeed, std::shared_ptr<LineFeed> feed) : feed_(std::move(feed)) {}

bool LineReader::seek(const Position& pos) {
  if (pos.offset > total_ && from_text_) return false;
  if (feed_) {
    if (pos.offset > feed_->bytes()) return false;
    line_no_ = pos.line;
    consumed_ = pos.offset;
    return true;
  }
  skipping_ = false;
  line_no_ = pos.line;
  consumed_ = pos.offset;
  if (from_text_) {
    text_ = full_text_.substr(static_cast<std::size_t>(pos.offset));
    return true;
  }
  // A loop's head is usually still in the buffer: no system call then.
  if (pos.offset >= buf_offset_ && pos.offset <= buf_offset_ + end_) {
    begin_ = static_cast<std::size_t>(pos.offset - buf_offset_);
    return true;
  }
  if (::lseek(fd_, static_cast<off_t>(pos.offset), SEEK_SET) < 0) return false;
  buf_offset_ = pos.offset;
  begin_ = end_ = 0;
  eof_ = false;
  return true;
}

LineReader::~LineReader() {
  if (fd_ >= 0) ::close(fd_);
}

bool LineReader::fill() {
  if (eof_) return false;
  if (begin_ > 0) {  // move the partial line to the front
    std::memmove(buf_.data(), buf_.data() + begin_, end_ - begin_);
    buf_offset_ += begin_;
    end_ -= begin_;
    begin_ = 0;
  }
  if (end_ == buf_.size()) return false;  // full: caller handles the long line
  while (true) {
    const ssize_t n = ::read(fd_, buf_.data() + end_, buf_.size() - end_);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      eof_ = true;
      return false;
    }
    end_ += static_cast<std::size_t>(n);
    return true;
  }
}

// A whole line held in memory (text or the feed's copy): cut at kMaxLine, '\r' dropped.
bool LineReader::hand_out(std::string_view l, std::string_view& line, bool& too_long) {
  if (l.size() > kMaxLine) {
    l = l.substr(0, kMaxLine);
    too_long = true;
  }
  if (!l.empty() && l.back() == '\r') l.remove_suffix(1);
  line = l;
  ++line_no_;
  return true;
}

bool LineReader::next(std::string_view& line, bool& too_long) {
  if (!next_raw(line, too_long)) return false;
  // A UTF-8 byte order mark before the first line (editors on Windows write one) is the file's
  // encoding, not its text: columns count from after it.
  constexpr std::string_view kBom = "\xEF\xBB\xBF";
  if (line_no_ == 1 && line.substr(0, kBom.size()) == kBom) line.remove_prefix(kBom.size());
  return true;
}

bool LineReader::next_raw(std::string_view& line, bool& too_long) {
  too_long = false;
  if (feed_) {
    if (!feed_->line_at(consumed_, line_no_, feed_line_)) return false;
    consumed_ += feed_line_.size() + 1;
    total_ = consumed_;
    return hand_out(feed_line_, line, too_long);
  }
  if (from_text_) {
    if (text_.empty()) return false;
    const std::size_t nl = text_.find('\n');
    std::string_view l = nl == std::string_view::npos ? text_ : text_.substr(0, nl);
    const std::size_t used = nl == std::string_view::npos ? text_.size() : nl + 1;
    text_.remove_prefix(used);
    consumed_ += used;
    return hand_out(l, line, too_long);
  }
  while (true) {
    const char* data = buf_.data();
    const void* hit = std::memchr(data + begin_, '\n', end_ - begin_);
    if (hit) {
      const std::size_t nl = static_cast<std::size_t>(static_cast<const char*>(hit) - data);
      std::string_view l(data + begin_, nl - begin_);
      consumed_ += nl + 1 - begin_;
      begin_ = nl + 1;
      if (skipping_) {  // tail of an over-long line: drop it
        skipping_ = false;
        continue;
      }
      if (!l.empty() && l.back() == '\r') l.remove_suffix(1);
      line = l;
      ++line_no_;
      return true;
    }
    if (end_ - begin_ >= kMaxLine) {  // no newline within kMaxLine: cut the line
      std::string_view l(data + begin_, kMaxLine);
      consumed_ += end_ - begin_;
      begin_ = end_;
      if (skipping_) continue;
      skipping_ = true;
      line = l;
      too_long = true;
      ++line_no_;
      // the view stays valid until the next call (fill() moves data only then)
      return true;
    }
    if (!fill()) {
      if (end_ > begin_) {  // last line without '\n'
        std::string_view l(data + begin_, end_ - begin_);
        consumed_ += end_ - begin_;
        begin_ = end_;
        if (skipping_) {
          skipping_ = false;
          return false;
        }
        if (!l.empty() && l.back() == '\r') l.remove_suffix(1);
        line = l;
        ++line_no_;
        return true;
      }
      return false;
    }
  }
}

}  // namespace pcnc
