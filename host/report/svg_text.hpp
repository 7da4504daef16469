// svg_text.hpp — small text helpers the report's SVG and HTML share: escaping, axis tick
// steps and their decimals, one-decimal coordinates (appended to the markup being built: the
// path strokes and plot lines hold most of a page's numbers).
#pragma once

#include <algorithm>
#include <cmath>
#include <string>

#include "config/fixed_text.hpp"

namespace pcnc::svg {

inline std::string escape(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

/// A 1-2-5 step giving about `target` ticks over `range`.
inline double nice_step(double range, int target) {
  if (!(range > 0.0)) return 1.0;
  const double raw = range / std::max(target, 1);
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  const double r = raw / mag;
  return (r < 1.5 ? 1.0 : r < 3.5 ? 2.0 : r < 7.5 ? 5.0 : 10.0) * mag;
}

/// Decimals that show a tick step exactly.
inline int decimals_for(double step) { return std::max(0, static_cast<int>(std::ceil(-std::log10(step) - 1e-9))); }

inline std::string f1(double v) { return fixed(v, 1); }

/// "x,y" with one decimal each, appended.
inline void append_xy(std::string& out, double x, double y) {
  append_fixed(out, x, 1);
  out += ',';
  append_fixed(out, y, 1);
}

}  // namespace pcnc::svg
