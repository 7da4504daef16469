// line_reader.hpp — the input of the front-end pipeline (gcode/pipeline.hpp): streams a G-code
// file (or text in memory) line by line in bounded memory.
//
// Reads the file in fixed chunks with read(2) and hands out string_views into its buffer: no
// allocation per line, no iostreams. Lines end at '\n' (a '\r' before it is dropped). A line
// longer than kMaxLine is cut there and flagged so the caller can report it. A UTF-8 byte
// order mark before the first line is dropped.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "gcode/diagnostics.hpp"

namespace pcnc {

class LineFeed;

/// Opens a G-code file for reading: a regular file only. The open never blocks (O_NONBLOCK, so a
/// FIFO or a device is refused after fstat, before anything is read). Returns the descriptor,
/// or -1 with `why` naming the file and the reason (cannot open; a directory, FIFO, device...).
int open_program_file(const std::string& path, std::string* why);

class LineReader {
 public:
  static constexpr std::size_t kChunk = 1 << 16;
  static constexpr std::size_t kMaxLine = 1 << 16;

  /// Opens `path` (open_program_file); throws std::runtime_error naming the file and the reason
  /// when it cannot be opened or is not a regular file.
  explicit LineReader(const std::string& path);
  /// Reads from text that outlives the reader.
  struct FromText {};
  LineReader(FromText, std::string_view text);
  /// Reads lines as they arrive in `feed` (a streamed program, gcode/line_feed.hpp): next()
  /// waits for the next line; the end of input is the feed's close().
  struct FromFeed {};
  LineReader(FromFeed, std::shared_ptr<LineFeed> feed);
  /// Reads a program the front end made from another file form (a JSON ruled-surface program
  /// as its G-code form, gcode/ruled_json_input.hpp): the reader owns `text`; `places` says, for
  /// each of its lines, where that line came from in the file (diagnostics and blocks name it).
  struct Generated {};
  LineReader(Generated, std::string text, std::shared_ptr<const SourcePlaces> places);
  ~LineReader();
  LineReader(const LineReader&) = delete;
  LineReader& operator=(const LineReader&) = delete;

  /// Next line; false at end of input. `too_long` is set when the line was cut at kMaxLine. A
  /// UTF-8 byte order mark at the start of the first line is not part of it.
  bool next(std::string_view& line, bool& too_long);

  /// Where the next line starts: saved by the control flow (a loop's head, a subroutine's
  /// body, a call's return) and given back to seek().
  struct Position {
    std::uint64_t offset = 0;  // bytes from the start of the input
    std::uint64_t line = 0;    // the number of the line before it
    std::uint32_t file = 0;    // which file (the control flow's: 0 = the program, then subroutine files)
  };
  Position tell() const { return {consumed_, line_no_}; }
  /// Goes back (or forward) to a position tell() gave. False when the input cannot be read
  /// there (the file shrank, a read error).
  bool seek(const Position& pos);

  std::uint64_t line_number() const { return line_no_; }  // of the line last returned
  const std::string& path() const { return path_; }        // empty for text in memory
  /// Generated: where each line came from; null otherwise.
  const std::shared_ptr<const SourcePlaces>& source_places() const { return places_; }
  std::uint64_t bytes_read() const { return consumed_; }
  std::uint64_t total_bytes() const { return total_; }

 private:
  bool next_raw(std::string_view& line, bool& too_long);  // next() before the byte order mark is dropped
  bool fill();  // reads more into the buffer; false at end of file
  bool hand_out(std::string_view l, std::string_view& line, bool& too_long);
  int fd_ = -1;
  std::vector<char> buf_;
  std::uint64_t buf_offset_ = 0;  // file offset of buf_[0]
  std::size_t begin_ = 0;  // start of unread data in buf_
  std::size_t end_ = 0;    // end of valid data in buf_
  bool eof_ = false;
  bool skipping_ = false;  // discarding the rest of an over-long line
  std::string owned_;  // Generated: the text text_ points into
  std::shared_ptr<const SourcePlaces> places_;
  std::string_view text_;
  std::string_view full_text_;
  std::string path_;
  bool from_text_ = false;
  std::shared_ptr<LineFeed> feed_;
  std::string feed_line_;  // the feed's last line (next()'s view points into it)
  std::uint64_t line_no_ = 0;
  std::uint64_t consumed_ = 0;
  std::uint64_t total_ = 0;
};

}  // namespace pcnc
