// line_assembler.cpp — real-time bytes out, lines in, the receive buffer's account (see
// line_assembler.hpp).
#include "grbl/line_assembler.hpp"

#include "grbl/realtime.hpp"

namespace pcnc::grbl {

void LineAssembler::feed(std::string_view data, std::vector<RxItem>& out) {
  for (char ch : data) {
    const auto b = static_cast<std::uint8_t>(ch);
    if (is_realtime(b)) {
      RxItem item;
      item.realtime = true;
      item.byte = b;
      out.push_back(std::move(item));
      continue;
    }
    if (b == '\n' || b == '\r') {
      const bool crlf = b == '\n' && last_was_cr_;
      last_was_cr_ = b == '\r';
      if (crlf) continue;  // the '\n' of "\r\n": the line ended at the '\r'
      ReceivedLine line;
      line.bytes = partial_bytes_ + 1;
      line.overflow = partial_bytes_ > kMaxLineLength;
      line.text = std::move(partial_);
      partial_.clear();
      partial_bytes_ = 0;
      buffered_ += 1;  // the newline; the line's own bytes were counted as they came
      if (buffered_ > kRxBufferSize) ++overflows_;
      RxItem item;
      item.line = std::move(line);
      out.push_back(std::move(item));
      continue;
    }
    last_was_cr_ = false;
    ++partial_bytes_;
    ++buffered_;
    if (buffered_ > kRxBufferSize) ++overflows_;
    if (partial_.size() < kMaxLineLength) partial_.push_back(ch);
  }
}

void LineAssembler::answered(std::size_t bytes) { buffered_ = bytes > buffered_ ? 0 : buffered_ - bytes; }

void LineAssembler::clear() {
  partial_.clear();
  partial_bytes_ = 0;
  buffered_ = 0;
  last_was_cr_ = false;
}

}  // namespace pcnc::grbl
