// interpreter_text.hpp — small helpers the interpreter's files share (internal to
// host/gcode/interpreter*.cpp): numbers in messages, the motion modes by G number, and the
// arc centre letters.
#pragma once

#include <cstdio>
#include <string>

namespace pcnc::interp {

constexpr double kTwoPi = 6.283185307179586476925;
constexpr double kInch = 25.4;  // mm per inch (G20)

/// A number as a message shows it: 4 decimals, trailing zeros trimmed (12.5, 3, -0.25).
inline std::string num(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.4f", v);
  // trim trailing zeros for readability: 12.5000 -> 12.5, 3.0000 -> 3
  std::string s(buf);
  if (s.find('.') != std::string::npos) {
    while (!s.empty() && s.back() == '0') s.pop_back();
    if (!s.empty() && s.back() == '.') s.pop_back();
  }
  if (s == "-0") s = "0";
  return s;
}

/// Motion modes by G number (x10): G2/G3 arcs, G0/G1 straight moves.
inline bool is_arc(int motion) { return motion == 20 || motion == 30; }
inline bool is_straight(int motion) { return motion == 0 || motion == 10; }
inline bool is_probe(int motion) { return motion >= 382 && motion <= 385; }  // G38.2-G38.5
/// The canned cycles pcnc expands (G73, G81, G82, G83, G85, G89).
inline bool is_cycle(int motion) {
  return motion == 730 || motion == 810 || motion == 820 || motion == 830 || motion == 850 || motion == 890;
}
/// The arc centre offset letter of an axis: I for X, J for Y, K for Z.
inline char center_letter(int axis) { return static_cast<char>('I' + axis); }

}  // namespace pcnc::interp
