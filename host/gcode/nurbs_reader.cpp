// nurbs_reader.cpp — minimal G5.2/G5.3 reader for the offline NURBS tool. See nurbs_reader.hpp.
#include "gcode/nurbs_reader.hpp"

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>

namespace pcnc {
namespace {

bool is_g(double g, double want) { return std::fabs(g - want) < 1e-6; }

}  // namespace

// Letter-number words of one line, comments in () and after ; removed.
bool split_gcode_words(const std::string& raw, GcodeWords& w, std::string& err) {
  std::string s;
  int depth = 0;
  for (char c : raw) {
    if (c == ';') break;
    if (c == '(') ++depth;
    if (depth == 0 && !std::isspace(static_cast<unsigned char>(c))) s += static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    if (c == ')' && depth > 0) --depth;
  }
  std::size_t i = 0;
  while (i < s.size()) {
    const char letter = s[i++];
    if (letter == '%') continue;
    if (!std::isalpha(static_cast<unsigned char>(letter))) {
      err = std::string("unexpected '") + letter + "'";
      return false;
    }
    // A plain decimal number (strtod alone would read "0X20P1" as a hex float).
    std::size_t j = i;
    if (j < s.size() && (s[j] == '+' || s[j] == '-')) ++j;
    while (j < s.size() && (std::isdigit(static_cast<unsigned char>(s[j])) || s[j] == '.')) ++j;
    const std::string number = s.substr(i, j - i);
    char* end = nullptr;
    const double v = std::strtod(number.c_str(), &end);
    if (number.empty() || end != number.c_str() + number.size()) {
      err = std::string("word ") + letter + " without a number";
      return false;
    }
    i = j;
    if (letter == 'G') {
      w.g.push_back(v);
    } else {
      w.value[letter] = v;
    }
  }
  return true;
}

NurbsProgram parse_nurbs_program(const std::string& text, KnotRule rule) {
  NurbsProgram out;
  std::istringstream in(text);
  std::string raw;
  int line_no = 0;
  Vec3 pos{0, 0, 0};
  double scale = 1.0;  // mm per program unit
  bool incremental = false;
  double feed = 0.0;
  int plane[2] = {0, 1};  // G17
  bool open = false;
  ProgramCurve cur;
  int order = 3;
  auto fail = [&](const std::string& why) {
    out.error = "line " + std::to_string(line_no) + ": " + why;
    return out;
  };
  while (std::getline(in, raw)) {
    ++line_no;
    GcodeWords w;
    std::string err;
    if (!split_gcode_words(raw, w, err)) return fail(err);
    bool g52 = false, g53 = false;
    for (const double g : w.g) {
      if (is_g(g, 17)) plane[0] = 0, plane[1] = 1;
      if (is_g(g, 18)) plane[0] = 2, plane[1] = 0;
      if (is_g(g, 19)) plane[0] = 1, plane[1] = 2;
      if (is_g(g, 20)) scale = 25.4;
      if (is_g(g, 21)) scale = 1.0;
      if (is_g(g, 90)) incremental = false;
      if (is_g(g, 91)) incremental = true;
      if (is_g(g, 5.2)) g52 = true;
      if (is_g(g, 5.3)) g53 = true;
    }
    if (w.has('F')) feed = w.value['F'] * scale / 60.0;
    // The end point of this line's axis words.
    Vec3 next = pos;
    bool moved = false;
    for (int a = 0; a < 3; ++a) {
      const char letter = "XYZ"[a];
      if (!w.has(letter)) continue;
      const double v = w.value[letter] * scale;
      next[static_cast<std::size_t>(a)] = incremental ? pos[static_cast<std::size_t>(a)] + v : v;
      moved = true;
    }
    if (g52) {
      if (open) return fail("G5.2 inside an open G5.2 group; expected G5.3 first");
      open = true;
      cur = ProgramCurve{};
      cur.line = line_no;
      cur.feed_mm_s = feed;
      order = w.has('L') ? static_cast<int>(std::lround(w.value['L'])) : 3;
      const double p = w.has('P') ? w.value['P'] : 1.0;
      cur.curve.points.push_back(pos);
      cur.curve.weights.push_back(moved ? 1.0 : p);
    }
    if (open && moved) {
      const char a0 = "XYZ"[plane[0]], a1 = "XYZ"[plane[1]];
      if (!w.has(a0) || !w.has(a1)) return fail(std::string("a control point needs both ") + a0 + " and " + a1);
      for (int a = 0; a < 3; ++a) {
        if (a != plane[0] && a != plane[1] && w.has("XYZ"[a])) {
          return fail(std::string("axis ") + "XYZ"[a] + " is not in the NURBS plane");
        }
      }
      if (!w.has('P')) return fail("control point without its weight P");
      cur.curve.points.push_back(next);
      cur.curve.weights.push_back(w.value['P']);
    }
    if (moved) pos = next;
    if (g53) {
      if (!open) return fail("G5.3 without an open G5.2 group");
      open = false;
      cur.curve = make_nurbs(cur.curve.points, cur.curve.weights, order, rule);
      if (std::string why = validate(cur.curve); !why.empty()) return fail(why);
      out.curves.push_back(cur);
    }
  }
  if (open) return fail("end of file inside a G5.2 group; expected G5.3");
  return out;
}

NurbsProgram read_nurbs_program(const std::string& path, KnotRule rule) {
  std::ifstream f(path);
  if (!f) {
    NurbsProgram out;
    out.error = "cannot read '" + path + "'";
    return out;
  }
  std::stringstream ss;
  ss << f.rdbuf();
  return parse_nurbs_program(ss.str(), rule);
}

}  // namespace pcnc
