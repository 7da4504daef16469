// number_format.hpp — one printf-style number as a string, for the offline tools' reports.
#pragma once

#include <cstdio>
#include <string>

namespace pcnc {

/// `format` holds one double conversion, e.g. "%.6f".
inline std::string format_number(const char* format, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

}  // namespace pcnc
