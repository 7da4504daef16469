// lexer.cpp — hand-written line lexer: no regex; on a straight-line program no allocation
// per line (the line's vectors keep their capacity).
#include "gcode/lexer.hpp"

#include <cmath>
#include <string>

#include "gcode/expression.hpp"

namespace pcnc {
namespace {

constexpr double kMaxMagnitude = 1e9;  // larger word values are typos or corruption

inline bool lex_digit(char c) { return c >= '0' && c <= '9'; }
inline bool lex_alpha(char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z'); }
inline char lex_upper(char c) { return (c >= 'a' && c <= 'z') ? static_cast<char>(c - 32) : c; }
inline char lower(char c) { return (c >= 'A' && c <= 'Z') ? static_cast<char>(c + 32) : c; }

std::string describe_char(char c) {
  if (c >= 33 && c <= 126) return std::string("'") + c + "'";
  static const char* hex = "0123456789abcdef";
  const auto u = static_cast<unsigned char>(c);
  return std::string("byte 0x") + hex[u >> 4] + hex[u & 15];
}

bool is_function_name(const char* p, const char* e) {
  static constexpr const char* kNames[] = {"ABS", "ACOS", "ASIN", "ATAN",  "COS",  "EXP", "FIX",
                                           "FUP", "LN",   "ROUND", "SIN", "SQRT", "TAN", "EXISTS"};
  const char* s = p;
  while (p < e && lex_alpha(*p)) ++p;
  const std::string_view name(s, static_cast<std::size_t>(p - s));
  for (const char* n : kNames) {
    const std::string_view want(n);
    if (name.size() != want.size()) continue;
    bool same = true;
    for (std::size_t i = 0; i < name.size(); ++i) same = same && lex_upper(name[i]) == want[i];
    if (same) return true;
  }
  return false;
}

struct Keyword {
  const char* name;
  OKind kind;
};
constexpr Keyword kKeywords[] = {
    {"sub", OKind::kSub},       {"endsub", OKind::kEndsub},     {"return", OKind::kReturn},
    {"call", OKind::kCall},     {"if", OKind::kIf},             {"elseif", OKind::kElseif},
    {"else", OKind::kElse},     {"endif", OKind::kEndif},       {"while", OKind::kWhile},
    {"endwhile", OKind::kEndwhile}, {"do", OKind::kDo},         {"repeat", OKind::kRepeat},
    {"endrepeat", OKind::kEndrepeat}, {"break", OKind::kBreak}, {"continue", OKind::kContinue}};

const ParameterStore& empty_store() {
  static const ParameterStore store;
  return store;
}

class LineLexer {
 public:
  LineLexer(std::string_view text, int line_no, DiagnosticSink& sink, const ParameterStore& params)
      : c_{text.data(), text.data(), text.data() + text.size(), line_no, sink}, expr_(c_, params) {}

  bool run(LexedLine& out, bool skipping) {
    out.count = 0;
    out.block_delete = out.percent = out.program_number = false;
    out.assignment_count = 0;
    out.oword.kind = OKind::kNone;
    out.message = MessageKind::kNone;
    c_.skip_spaces();
    if (!c_.at_end() && *c_.p == '/') {
      out.block_delete = true;
      return true;
    }
    if (skipping) return skip_line(out);
    if (!skip_blank(out)) return false;
    if (!c_.at_end() && *c_.p == '%') {
      const char* at = c_.p++;
      if (!skip_blank(out)) return false;
      if (!c_.at_end())
        return c_.fail(at, "'%' program delimiter must be alone on its line; expected end of line after '%'");
      out.percent = true;
      return true;
    }
    while (true) {
      if (!skip_blank(out)) return false;
      if (c_.at_end()) return true;
      const char* at = c_.p;
      const char ch = lex_upper(*c_.p);
      if ((ch >= 'A' && ch <= 'Z') || ch == '@' || ch == '^') {  // @ ^: LinuxCNC's polar radius and angle
        ++c_.p;
        if (ch == 'O') return o_word(at, out);
        double v = 0.0;
        if (!word_value(v, ch, at)) return false;
        if (out.count == LexedLine::kMaxWords) return c_.fail(at, "too many words on one line; expected at most 64");
        out.words[out.count++] = Word{ch, c_.col(at), v};
        continue;
      }
      if (ch == '#') {
        if (!assignment(at, out)) return false;
        continue;
      }
      if (ch == '[') return c_.fail(at, "expression without a word letter; expected a word such as X[1+2]");
      return c_.fail(at, "unexpected " + describe_char(*at) +
                             "; expected a word (letter and number), a parameter assignment, a comment or end of line");
    }
  }

 private:
  // A line not being run: only its O-word (label and keyword) matters; nothing is reported.
  bool skip_line(LexedLine& out) {
    DiagnosticSink scratch;
    LineLexer inner(std::string_view(c_.begin, static_cast<std::size_t>(c_.end - c_.begin)), c_.line, scratch,
                    empty_store());
    inner.c_.p = c_.p;
    inner.no_values_ = true;
    if (!inner.skip_blank(out)) return true;
    // An N word may come first.
    if (!inner.c_.at_end() && lex_upper(*inner.c_.p) == 'N') {
      ++inner.c_.p;
      while (!inner.c_.at_end() && (lex_digit(*inner.c_.p) || *inner.c_.p == ' ' || *inner.c_.p == '\t')) ++inner.c_.p;
      if (!inner.skip_blank(out)) return true;
    }
    if (inner.c_.at_end() || lex_upper(*inner.c_.p) != 'O') return true;
    const char* at = inner.c_.p++;
    if (!inner.o_word(at, out)) out.oword.kind = OKind::kNone;
    out.message = MessageKind::kNone;
    return true;
  }

  // Spaces and comments. False (reported) on an unclosed comment; a nested one is accepted
  // with a warning.
  bool skip_blank(LexedLine& out) {
    while (!c_.at_end()) {
      const char ch = *c_.p;
      if (ch == ' ' || ch == '\t' || ch == '\r' || ch == '\f' || ch == '\v') {
        ++c_.p;
      } else if (ch == '(') {
        const char* open = c_.p++;
        const char* text = c_.p;
        int depth = 1;
        const char* nested = nullptr;
        while (!c_.at_end()) {
          if (*c_.p == '(') {
            if (nested == nullptr) nested = c_.p;
            ++depth;
          } else if (*c_.p == ')') {
            if (--depth == 0) break;
          }
          ++c_.p;
        }
        if (c_.at_end()) return c_.fail(open, "comment not closed; expected ')' before end of line");
        if (nested != nullptr && !no_values_ && !c_.sink.repeat("nested-comment")) {
          c_.sink.warning(c_.line, c_.col(nested), "nested-comment",
                          "nested '(' inside the comment opened at column " + std::to_string(c_.col(open)) +
                              ": read as one comment up to its matching ')' (LinuxCNC refuses nested comments)");
        }
        comment(std::string_view(text, static_cast<std::size_t>(c_.p - text)), c_.col(open), out);
        ++c_.p;
      } else if (ch == ';') {
        c_.p = c_.end;
      } else {
        break;
      }
    }
    return true;
  }

  // (MSG,...), (DEBUG,...), (PRINT,...): kept with their raw text (the last one on a line).
  void comment(std::string_view text, int column, LexedLine& out) {
    std::size_t i = 0;
    while (i < text.size() && (text[i] == ' ' || text[i] == '\t')) ++i;
    struct Kind {
      const char* prefix;
      MessageKind kind;
    };
    static constexpr Kind kKinds[] = {
        {"msg,", MessageKind::kMsg},          {"debug,", MessageKind::kDebug},
        {"print,", MessageKind::kPrint},      {"probeopen ", MessageKind::kProbeOpen},
        {"probeclose", MessageKind::kProbeClose}};
    for (const Kind& k : kKinds) {
      const std::string_view p(k.prefix);
      if (text.size() - i < p.size()) continue;
      bool same = true;
      for (std::size_t j = 0; j < p.size(); ++j) same = same && lower(text[i + j]) == p[j];
      if (!same) continue;
      out.message = k.kind;
      out.message_text.assign(text.substr(i + p.size()));
      out.message_column = column;
      return;
    }
  }

  bool word_value(double& v, char letter, const char* at) {
    c_.skip_spaces();
    const auto no_value = [&](const char* where, const std::string& found) {
      const std::string L(1, letter);
      return c_.fail(where, L + " word without a value; expected a number after " + L + found);
    };
    if (c_.at_end()) return no_value(at, "");
    const char* s = c_.p;
    const char c0 = *s;
    const char c1 = s + 1 < c_.end ? s[1] : '\0';
    // The common case, a plain number ("X12.5", "Y-.25"): straight to the number reader.
    if (lex_digit(c0) || (c0 == '.' && lex_digit(c1)) || ((c0 == '-' || c0 == '+') && (lex_digit(c1) || c1 == '.'))) {
      if (!expr_.number(v)) return false;
    } else {
      if (lex_alpha(c0) && !is_function_name(s, c_.end)) return no_value(s, ", found " + describe_char(c0));
      if (c0 == '-' || c0 == '+') {
        const char* q = s + 1;
        while (q < c_.end && (*q == ' ' || *q == '\t')) ++q;
        if (q == c_.end || (!lex_digit(*q) && *q != '.' && *q != '#' && *q != '[' && !lex_alpha(*q))) return no_value(s, "");
      }
      if (c0 == '.') return no_value(s, "");
      if (!expr_.real_value(v)) return false;
    }
    if (!(std::fabs(v) <= kMaxMagnitude)) {
      const std::string L(1, letter);
      return c_.fail(at, L + " value out of range; expected a magnitude below 1e9");
    }
    return true;
  }

  // '#ref = value'
  bool assignment(const char* hash, LexedLine& out) {
    ++c_.p;
    int number = 0;
    std::string name;
    if (!expr_.parameter_ref(number, name, hash)) return false;
    c_.skip_spaces();
    if (c_.at_end() || *c_.p != '=')
      return c_.fail(c_.p < c_.end ? c_.p : hash,
                     "parameter without '='; expected an assignment such as #1=2 or #<name>=[expression]");
    ++c_.p;
    double v = 0.0;
    if (!expr_.real_value(v)) return false;
    if (static_cast<std::size_t>(out.assignment_count) == out.assignments.size()) out.assignments.emplace_back();
    Assignment& a = out.assignments[static_cast<std::size_t>(out.assignment_count++)];
    a.number = number;
    a.name = std::move(name);
    a.value = v;
    a.column = c_.col(hash);
    return true;
  }

  bool o_word(const char* at, LexedLine& out) {
    if (out.count != 0) {
      bool only_n = true;
      for (int i = 0; i < out.count; ++i) only_n = only_n && out.words[i].letter == 'N';
      if (!only_n) return c_.fail(at, "O word after other words; expected the O word first on its line");
    }
    c_.skip_spaces();
    OWord& o = out.oword;
    o.column = c_.col(at);
    o.has_value = false;
    o.value = 0.0;
    o.args.clear();
    if (!c_.at_end() && *c_.p == '<') {
      const char* open = c_.p++;
      const char* s = c_.p;
      while (!c_.at_end() && *c_.p != '>') ++c_.p;
      if (c_.at_end()) return c_.fail(open, "O-word name not closed; expected '>' after the name");
      o.label = ParameterStore::normalize(std::string_view(s, static_cast<std::size_t>(c_.p - s)));
      ++c_.p;
      if (o.label.empty()) return c_.fail(open, "empty O-word name; expected o<name>");
    } else if (!c_.at_end() && (*c_.p == '#' || *c_.p == '[')) {
      // A computed label (o#<sub> call): a number, as LinuxCNC evaluates it.
      if (no_values_) {
        o.label = "#?";  // not evaluated while skipping: matches nothing
        while (!c_.at_end() && *c_.p != ' ' && *c_.p != '\t') ++c_.p;
      } else {
        const char* lab = c_.p;
        double v = 0.0;
        if (!expr_.real_value(v)) return false;
        if (v != std::floor(v) || v < 0.0 || v > 99999999.0)
          return c_.fail(lab, "computed O-word label is not a whole number >= 0; expected e.g. o#1 with #1 = 100");
        o.label = std::to_string(static_cast<long>(v));
      }
    } else {
      double v = 0.0;
      const std::size_t n = parse_decimal(c_.p, c_.end, v);
      if (n == 0 || *c_.p == '-' || *c_.p == '+' || v != std::floor(v) || v > 99999999.0)
        return c_.fail(at, "O word without a label; expected a number or <name> after O, e.g. O100 sub");
      c_.p += n;
      o.label = std::to_string(static_cast<long>(v));
      out.program_value = v;
    }
    if (!skip_blank(out)) return false;
    if (c_.at_end()) {
      if (!lex_digit(o.label.empty() ? 'x' : o.label[0]))
        return c_.fail(at, "O-word without a keyword; expected sub, endsub, return, call, if, elseif, else, endif, "
                           "while, endwhile, do, repeat, endrepeat, break or continue");
      out.program_number = true;
      return true;
    }
    const char* kw = c_.p;
    while (!c_.at_end() && lex_alpha(*c_.p)) ++c_.p;
    const std::string_view word(kw, static_cast<std::size_t>(c_.p - kw));
    o.kind = OKind::kNone;
    for (const Keyword& k : kKeywords) {
      const std::string_view want(k.name);
      if (word.size() != want.size()) continue;
      bool same = true;
      for (std::size_t i = 0; i < word.size(); ++i) same = same && lower(word[i]) == want[i];
      if (same) o.kind = k.kind;
    }
    if (o.kind == OKind::kNone) {
      return c_.fail(kw, "unknown O-word keyword '" + std::string(word) +
                             "'; expected sub, endsub, return, call, if, elseif, else, endif, while, endwhile, do, "
                             "repeat, endrepeat, break or continue");
    }
    if (no_values_) return true;  // skipping: the keyword is all that is wanted
    // Arguments: call takes any number of [expr]; if, elseif, while, repeat, return and endsub one.
    while (true) {
      if (!skip_blank(out)) return false;
      if (c_.at_end()) break;
      if (*c_.p != '[') {
        return c_.fail(c_.p, "unexpected " + describe_char(*c_.p) + " after the O-word keyword; expected '[expression]' or "
                                                              "end of line");
      }
      const char* arg_at = c_.p;
      double v = 0.0;
      if (!expr_.real_value(v)) return false;
      if (o.kind == OKind::kCall) {
        if (o.args.size() >= ParameterStore::kLocalNumbered)
          return c_.fail(arg_at, "too many subroutine arguments; expected at most 30");
        o.args.push_back(v);
      } else if (!o.has_value && (o.kind == OKind::kIf || o.kind == OKind::kElseif || o.kind == OKind::kWhile ||
                                  o.kind == OKind::kRepeat || o.kind == OKind::kReturn || o.kind == OKind::kEndsub)) {
        o.has_value = true;
        o.value = v;
      } else {
        return c_.fail(arg_at, "unexpected value after '" + std::string(word) + "'; expected end of line");
      }
    }
    if ((o.kind == OKind::kIf || o.kind == OKind::kElseif || o.kind == OKind::kRepeat || o.kind == OKind::kWhile) &&
        !o.has_value) {
      return c_.fail(kw, "'" + std::string(word) + "' without a condition; expected " + std::string(word) +
                             " [expression]");
    }
    return true;
  }

  LineCursor c_;
  ExpressionReader expr_;
  bool no_values_ = false;  // skipping: recognize the O-word only
};

}  // namespace

bool lex_line(std::string_view text, int line_no, LexedLine& out, DiagnosticSink& sink, const ParameterStore* params,
              bool skipping) {
  LineLexer lexer(text, line_no, sink, params != nullptr ? *params : empty_store());
  return lexer.run(out, skipping);
}

}  // namespace pcnc
