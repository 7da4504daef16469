// ruled_reader.cpp — the G5.4 ... G5.5 groups read from lexed lines. See ruled_reader.hpp.
#include "gcode/ruled_reader.hpp"

#include <cmath>
#include <cstdio>
#include <string>

namespace pcnc {
namespace {

// A G or M word's number x10 ("G5.4" -> 54); -1 for a number that is not a multiple of 0.1 or
// lies beyond any code (G888888888 must not overflow the int).
int code10(double v) {
  if (!(std::abs(v) < 1e6)) return -1;
  const double r = std::round(v * 10.0);
  return std::abs(v * 10.0 - r) < 1e-6 ? static_cast<int>(r) : -1;
}

std::string word_name(const Word& w) {
  char buf[48];
  if (w.letter == 'G' || w.letter == 'M') {
    const int c = code10(w.value);
    if (c >= 0 && c % 10 == 0) std::snprintf(buf, sizeof buf, "%c%d", w.letter, c / 10);
    else if (c >= 0) std::snprintf(buf, sizeof buf, "%c%d.%d", w.letter, c / 10, c % 10);
    else std::snprintf(buf, sizeof buf, "%c%.10g", w.letter, w.value);
  } else {
    std::snprintf(buf, sizeof buf, "%c", w.letter);
  }
  return buf;
}

std::string fmt(const char* f, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}

bool is_g(const Word& w, int c10) { return w.letter == 'G' && code10(w.value) == c10; }

}  // namespace

bool RuledGroupReader::take(const LexedLine& line, int line_no, const RuledModal& modal, DiagnosticSink& sink) {
  int g54 = -1, g55 = -1;
  for (int i = 0; i < line.count; ++i) {
    if (is_g(line.words[i], 54)) g54 = i;
    if (is_g(line.words[i], 55)) g55 = i;
  }
  if (!open_) {
    if (g54 >= 0) {
      open_group(line, line_no, modal, sink);
      return true;
    }
    if (g55 >= 0) {
      sink.error(line_no, line.words[g55].column, "G5.5 without a G5.4 group to close");
      return true;
    }
    return false;
  }
  if (g55 >= 0) {
    close_group(line, line_no, sink);
  } else if (g54 >= 0) {
    sink.error(line_no, line.words[g54].column,
               "G5.4 inside the G5.4 group opened at line " + std::to_string(group_.line) + ": close it with G5.5 first");
    failed_ = true;
  } else {
    set_point(line, line_no, sink);
  }
  return true;
}

void RuledGroupReader::open_group(const LexedLine& line, int line_no, const RuledModal& modal, DiagnosticSink& sink) {
  group_ = RuledGroup{};
  group_.line = line_no;
  group_.feed = modal.feed;
  open_ = true;
  failed_ = false;
  ready_ = false;
  int g54_col = 1;
  bool bad = false;
  for (int i = 0; i < line.count; ++i) {
    const Word& w = line.words[i];
    if (is_g(w, 54)) {
      g54_col = w.column;
    } else if (w.letter == 'F') {
      if (!(w.value > 0.0)) {
        sink.error(line_no, w.column, "G5.4 with F" + fmt("%g", w.value) + ": the feed must be positive");
        bad = true;
      }
      group_.feed = w.value;
    } else if (w.letter != 'N') {
      sink.error(line_no, w.column, word_name(w) + " on the G5.4 line: only F (and a line number) may go with it");
      bad = true;
    }
  }
  if (line.assignment_count > 0) {
    sink.error(line_no, line.assignments[0].column, "a parameter assignment on the G5.4 line");
    bad = true;
  }
  if (!modal.tcp) {
    sink.error(line_no, g54_col,
               "G5.4 needs tool-centre-point control (M428 or G43.4): its set points are tool tips");
    bad = true;
  }
  if (modal.incremental) {
    sink.error(line_no, g54_col, "G5.4 under G91: its set points are absolute (G90)");
    bad = true;
  }
  if (modal.inverse_time) {
    sink.error(line_no, g54_col, "G5.4 needs G94: F is the tool tip's speed along the directrix");
    bad = true;
  }
  if (modal.spline_group) {
    sink.error(line_no, g54_col, "G5.4 inside a NURBS group (G5.2 ... G5.3): close it first");
    bad = true;
  }
  if (!bad && !(group_.feed > 0.0)) {
    sink.error(line_no, g54_col, "G5.4 without a feed: no F in effect");
    bad = true;
  }
  failed_ = bad;
}

void RuledGroupReader::set_point(const LexedLine& line, int line_no, DiagnosticSink& sink) {
  static constexpr char kLetters[6] = {'X', 'Y', 'Z', 'I', 'J', 'K'};
  double v[6] = {};
  int col[6] = {};
  bool seen[6] = {};
  bool bad = false;
  if (line.assignment_count > 0) {
    sink.error(line_no, line.assignments[0].column, "a parameter assignment inside the G5.4 group opened at line " +
                                                        std::to_string(group_.line));
    bad = true;
  }
  for (int i = 0; i < line.count && !bad; ++i) {
    const Word& w = line.words[i];
    int k = -1;
    for (int j = 0; j < 6; ++j) {
      if (kLetters[j] == w.letter) k = j;
    }
    if (k >= 0) {
      if (seen[k]) {
        sink.error(line_no, w.column, std::string("two ") + w.letter + " words on one set point");
        bad = true;
      }
      seen[k] = true;
      v[k] = w.value;
      col[k] = w.column;
    } else if (w.letter == 'A' || w.letter == 'B' || w.letter == 'C') {
      sink.error(line_no, w.column,
                 std::string(1, w.letter) +
                     " inside a G5.4 group: set points give the tool tip and axis (X Y Z I J K); the joints are the "
                     "kinematics'");
      bad = true;
    } else if (w.letter == 'G' || w.letter == 'M') {
      sink.error(line_no, w.column,
                 word_name(w) + " inside the G5.4 group opened at line " + std::to_string(group_.line) +
                     ": only set points (X Y Z I J K) and G5.5");
      bad = true;
    } else if (w.letter != 'N') {
      sink.error(line_no, w.column, std::string(1, w.letter) + " on a set point: only X Y Z I J K (and a line number)");
      bad = true;
    }
  }
  if (bad) {
    failed_ = true;
    return;
  }
  if (line.count == 0 || (line.count == 1 && line.words[0].letter == 'N')) return;  // a comment or blank line
  for (int j = 0; j < 6; ++j) {
    if (!seen[j]) {
      sink.error(line_no, line.words[0].column,
                 std::string("set point without ") + kLetters[j] +
                     ": every line of a G5.4 group gives all of X Y Z I J K (no modal carry-over)");
      failed_ = true;
      return;
    }
  }
  const Vec3 p{v[0], v[1], v[2]};
  const Vec3 a{v[3], v[4], v[5]};
  const double len = norm(a);
  if (!(std::abs(len - 1.0) <= kRuledAxisTolerance)) {
    sink.error(line_no, col[3], "tool vector I J K of length " + fmt("%.4g", len) + ": expected a unit vector");
    failed_ = true;
    return;
  }
  if (!group_.points.empty() && !(norm(p - group_.points.back()) >= kRuledMinPointDistance)) {
    sink.error(line_no, col[0],
               "set point at the one before (line " + std::to_string(group_.point_lines.back()) +
                   "): consecutive set points must be at least 1e-6 mm apart");
    failed_ = true;
    return;
  }
  for (int j = 0; j < 6; ++j) {
    if (!std::isfinite(v[j])) {
      sink.error(line_no, col[j], std::string(1, kLetters[j]) + " is not a finite number");
      failed_ = true;
      return;
    }
  }
  group_.points.push_back(p);
  group_.axes.push_back((1.0 / len) * a);
  group_.point_lines.push_back(line_no);
}

void RuledGroupReader::close_group(const LexedLine& line, int line_no, DiagnosticSink& sink) {
  bool bad = false;
  for (int i = 0; i < line.count; ++i) {
    const Word& w = line.words[i];
    if (!is_g(w, 55) && w.letter != 'N') {
      sink.error(line_no, w.column, word_name(w) + " on the G5.5 line: G5.5 goes alone (with a line number)");
      bad = true;
    }
  }
  if (!failed_ && !bad && group_.points.size() < 2) {
    sink.error(line_no, 1,
               "the G5.4 group opened at line " + std::to_string(group_.line) + " has " +
                   std::to_string(group_.points.size()) + " set point" + (group_.points.size() == 1 ? "" : "s") +
                   ": at least 2");
    bad = true;
  }
  open_ = false;
  ready_ = !failed_ && !bad;
  failed_ = false;
}

bool RuledGroupReader::take_group(RuledGroup& out) {
  if (!ready_) return false;
  out = std::move(group_);
  group_ = RuledGroup{};
  ready_ = false;
  return true;
}

void RuledGroupReader::finish(DiagnosticSink& sink) {
  if (!open_) return;
  sink.error(group_.line, 0, "the G5.4 group opened here is not closed by G5.5 before the end of the program");
  open_ = false;
  ready_ = false;
}

std::vector<RuledGroup> read_ruled_groups(std::string_view text, DiagnosticSink& sink) {
  std::vector<RuledGroup> out;
  RuledGroupReader reader;
  RuledModal modal;
  LexedLine lexed;
  int line_no = 0;
  std::size_t pos = 0;
  while (pos <= text.size()) {
    const std::size_t end = std::min(text.find('\n', pos), text.size());
    std::string_view raw = text.substr(pos, end - pos);
    if (!raw.empty() && raw.back() == '\r') raw.remove_suffix(1);
    ++line_no;
    pos = end + 1;
    if (end == text.size() && raw.empty()) break;
    if (!lex_line(raw, line_no, lexed, sink)) continue;
    if (reader.take(lexed, line_no, modal, sink)) {
      RuledGroup g;
      if (reader.take_group(g)) out.push_back(std::move(g));
      continue;
    }
    // The modal state the rules need, from the other lines.
    for (int i = 0; i < lexed.count; ++i) {
      const Word& w = lexed.words[i];
      const int c = w.letter == 'G' || w.letter == 'M' ? code10(w.value) : -1;
      if (w.letter == 'M' && c == 4280) modal.tcp = true;
      if (w.letter == 'M' && c == 4290) modal.tcp = false;
      if (w.letter == 'G' && c == 434) modal.tcp = true;
      if (w.letter == 'G' && c == 490) modal.tcp = false;
      if (w.letter == 'G' && c == 900) modal.incremental = false;
      if (w.letter == 'G' && c == 910) modal.incremental = true;
      if (w.letter == 'G' && (c == 930 || c == 950)) modal.inverse_time = true;
      if (w.letter == 'G' && c == 940) modal.inverse_time = false;
      if (w.letter == 'G' && c == 52) modal.spline_group = true;
      if (w.letter == 'G' && c == 53) modal.spline_group = false;
      if (w.letter == 'F') modal.feed = w.value;
    }
  }
  reader.finish(sink);
  return out;
}

}  // namespace pcnc
