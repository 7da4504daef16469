// line_assembler.hpp — the grbl port's receive side, pure: bytes from the serial line are
// split into real-time commands (handed out at once, wherever they fall, even inside a line)
// and lines (ended by '\n' or '\r'; an empty line between "\r\n" is not a line). It also keeps
// the account senders keep when they stream by character counting: the bytes of the lines
// received but not answered yet (each with its newline) must stay within grbl's 128-byte
// receive buffer. pcnc never drops bytes; a sender that overfills the buffer is only counted
// (overflows()), the way a real grbl would lose them.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <string>
#include <string_view>
#include <vector>

namespace pcnc::grbl {

constexpr std::size_t kRxBufferSize = 128;
constexpr std::size_t kMaxLineLength = 255;  // longer lines: error:11 (line overflow)

struct ReceivedLine {
  std::string text;       // without the line end
  std::size_t bytes = 0;  // what it occupies in the receive buffer (its newline included)
  bool overflow = false;  // longer than kMaxLineLength (the text is cut)
};
/// One thing received: a real-time byte, or a line.
struct RxItem {
  bool realtime = false;
  std::uint8_t byte = 0;  // realtime
  ReceivedLine line;      // otherwise
};

class LineAssembler {
 public:
  /// Splits `data`; real-time bytes and complete lines are appended to `out` in arrival order.
  void feed(std::string_view data, std::vector<RxItem>& out);
  /// A line was answered (ok or error): its bytes leave the receive buffer.
  void answered(std::size_t bytes);
  /// Everything received is dropped (soft reset): the buffer is empty again.
  void clear();

  std::size_t buffered() const { return buffered_; }  // bytes of unanswered lines
  std::size_t available() const { return buffered_ >= kRxBufferSize ? 0 : kRxBufferSize - buffered_; }
  std::uint64_t overflows() const { return overflows_; }

 private:
  std::string partial_;
  std::size_t partial_bytes_ = 0;
  bool last_was_cr_ = false;
  std::size_t buffered_ = 0;
  std::uint64_t overflows_ = 0;
};

}  // namespace pcnc::grbl
