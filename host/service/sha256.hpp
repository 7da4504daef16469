// sha256.hpp — SHA-256 (FIPS 180-4) of a byte stream or a file, for the journal's record of
// the program it ran: a resumed run checks that the file is still the same program.
//
// May include: the C++ and POSIX libraries only.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace pcnc {

class Sha256 {
 public:
  Sha256();
  void update(const void* data, std::size_t len);
  void update(std::string_view s) { update(s.data(), s.size()); }
  /// The digest as 64 lowercase hex digits; the object is spent afterwards.
  std::string hex();

 private:
  void block(const std::uint8_t* p);
  std::array<std::uint32_t, 8> h_;
  std::array<std::uint8_t, 64> buf_{};
  std::size_t used_ = 0;
  std::uint64_t length_ = 0;  // bytes
};

/// SHA-256 of a regular file's content (hex); empty with `error` set when it cannot be read
/// (opened like a program: never blocks on a FIFO or device, refuses non-regular files).
std::string sha256_file(const std::string& path, std::string* error);

}  // namespace pcnc
