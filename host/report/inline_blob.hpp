// inline_blob.hpp — bytes packed to sit inside one self-contained HTML page: gzip (zlib),
// then base64. The page unpacks them with the browser's DecompressionStream('gzip'), so the
// run report stays one file while carrying a script library and binary path data.
#pragma once

#include <string>
#include <string_view>

namespace pcnc {

/// The bytes gzip-compressed (RFC 1952, zlib level 4: half of the default level 6's time for
/// 1.3 % more page; on the 3D view's path record level 9 took 133 ms for 5 % less than 6,
/// three.js 31 ms for 0.3 % less; bench/bench_report).
/// Throws std::runtime_error when zlib fails (out of memory).
std::string gzip_bytes(std::string_view bytes);
/// The gzip stream back to its bytes (tests, and reading a report's data). Throws on a
/// corrupt stream.
std::string gunzip_bytes(std::string_view gz);

/// Base64 (RFC 4648, with padding, no line breaks) and back. decode throws on a character
/// outside the alphabet.
std::string base64_encode(std::string_view bytes);
std::string base64_decode(std::string_view text);

}  // namespace pcnc
