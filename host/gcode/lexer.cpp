// lexer.cpp — hand-written line lexer: no regex, no allocation on the hot path.
#include "gcode/lexer.hpp"

#include <charconv>
#include <cmath>
#include <cstdint>
#include <string>

namespace pcnc {
namespace {

constexpr double kPow10[] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,  1e8,  1e9,  1e10, 1e11,
                             1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};
constexpr double kMaxMagnitude = 1e9;  // larger word values are typos or corruption
constexpr int kMaxExprDepth = 64;
constexpr double kPi = 3.14159265358979323846;

inline bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }
inline bool is_digit(char c) { return c >= '0' && c <= '9'; }
inline bool is_alpha(char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z'); }
inline char upper(char c) { return (c >= 'a' && c <= 'z') ? static_cast<char>(c - 32) : c; }

std::string describe(char c) {
  if (c >= 33 && c <= 126) return std::string("'") + c + "'";
  static const char* hex = "0123456789abcdef";
  const auto u = static_cast<unsigned char>(c);
  return std::string("byte 0x") + hex[u >> 4] + hex[u & 15];
}

enum class Func { kNone, kAbs, kAcos, kAsin, kAtan, kCos, kExp, kFix, kFup, kLn, kRound, kSin, kSqrt, kTan, kExists };

Func lookup_function(std::string_view name) {
  struct Entry {
    const char* name;
    Func f;
  };
  static constexpr Entry kTable[] = {{"ABS", Func::kAbs},     {"ACOS", Func::kAcos},    {"ASIN", Func::kAsin},
                                     {"ATAN", Func::kAtan},   {"COS", Func::kCos},      {"EXP", Func::kExp},
                                     {"FIX", Func::kFix},     {"FUP", Func::kFup},      {"LN", Func::kLn},
                                     {"ROUND", Func::kRound}, {"SIN", Func::kSin},      {"SQRT", Func::kSqrt},
                                     {"TAN", Func::kTan},     {"EXISTS", Func::kExists}};
  for (const Entry& e : kTable) {
    if (name.size() == std::char_traits<char>::length(e.name)) {
      bool same = true;
      for (std::size_t i = 0; i < name.size(); ++i) same = same && upper(name[i]) == e.name[i];
      if (same) return e.f;
    }
  }
  return Func::kNone;
}

class LineLexer {
 public:
  LineLexer(std::string_view text, int line_no, DiagnosticSink& sink)
      : b_(text.data()), p_(text.data()), e_(text.data() + text.size()), line_(line_no), sink_(sink) {}

  bool run(LexedLine& out) {
    out.count = 0;
    out.block_delete = out.percent = out.program_number = false;
    skip_spaces();
    if (p_ < e_ && *p_ == '/') {
      out.block_delete = true;
      return true;
    }
    if (!skip_blank()) return false;
    if (p_ < e_ && *p_ == '%') {
      const char* at = p_++;
      if (!skip_blank()) return false;
      if (p_ != e_) return fail(at, "'%' program delimiter must be alone on its line; expected end of line after '%'");
      out.percent = true;
      return true;
    }
    while (true) {
      if (!skip_blank()) return false;
      if (p_ == e_) return true;
      const char* at = p_;
      const char c = upper(*p_);
      if (c >= 'A' && c <= 'Z') {
        ++p_;
        if (c == 'O') return o_word(at, out);
        double v = 0.0;
        if (!read_value(v, c, at)) return false;
        if (out.count == LexedLine::kMaxWords) return fail(at, "too many words on one line; expected at most 64");
        out.words[out.count++] = Word{c, col(at), v};
        continue;
      }
      if (c == '#') return fail(at, "parameters ('#') are not supported; expected a word (letter and number)");
      if (c == '[') return fail(at, "expression without a word letter; expected a word such as X[1+2]");
      return fail(at,
                  "unexpected " + describe(*at) + "; expected a word (letter and number), a comment or end of line");
    }
  }

 private:
  int col(const char* q) const { return static_cast<int>(q - b_) + 1; }
  bool fail(const char* at, std::string message) {
    sink_.error(line_, col(at), std::move(message));
    return false;
  }
  void skip_spaces() {
    while (p_ < e_ && is_space(*p_)) ++p_;
  }
  // Spaces and comments. False (reported) on an unclosed or nested parenthesis comment.
  bool skip_blank() {
    while (p_ < e_) {
      const char c = *p_;
      if (is_space(c)) {
        ++p_;
      } else if (c == '(') {
        const char* open = p_;
        ++p_;
        while (p_ < e_ && *p_ != ')') {
          if (*p_ == '(')
            return fail(
                p_, "nested comment; expected ')' to close the comment opened at column " + std::to_string(col(open)));
          ++p_;
        }
        if (p_ == e_) return fail(open, "comment not closed; expected ')' before end of line");
        ++p_;
      } else if (c == ';') {
        p_ = e_;
      } else {
        break;
      }
    }
    return true;
  }

  bool o_word(const char* at, LexedLine& out) {
    if (out.count != 0) return fail(at, "O word after other words; expected a program number alone on its line");
    skip_spaces();
    if (p_ < e_ && *p_ == '<')
      return fail(
          at,
          "named O-words (subroutines, control flow) are not supported; expected a program number alone on its line");
    double v = 0.0;
    if (!read_number(v, 'O', at)) return false;
    if (!skip_blank()) return false;
    if (p_ != e_) {
      return fail(at,
                  "O-word control flow (sub, call, if, while, ...) is not supported; expected a program number alone "
                  "on its line");
    }
    out.program_number = true;
    return true;
  }

  bool read_value(double& v, char letter, const char* at) {
    skip_spaces();
    if (p_ == e_) return fail(at, std::string(1, letter) + " word without a value; expected a number after " + letter);
    const char c = *p_;
    if (c == '[') {
      ++p_;
      if (!bracket_rest(v, 0)) return false;
    } else if (is_alpha(c)) {
      const char* name_at = p_;
      if (!function_call(v, 0)) {
        if (sink_.error_count() == errors_before_) {
          return fail(name_at, std::string(1, letter) + " word without a value; expected a number after " + letter +
                                   ", found " + describe(*name_at));
        }
        return false;
      }
    } else if (c == '#') {
      return fail(p_, "parameters ('#') are not supported; expected a number after " + std::string(1, letter));
    } else {
      if (!read_number(v, letter, at)) return false;
    }
    if (!std::isfinite(v) || std::fabs(v) > kMaxMagnitude) {
      return fail(at, std::string(1, letter) + " value out of range; expected a magnitude below 1e9");
    }
    return true;
  }

  // A number, possibly with spaces inside ("1 .5"), as RS274 allows.
  bool read_number(double& v, char letter, const char* at) {
    const char* start = p_;
    std::size_t n = parse_decimal(p_, e_, v);
    const char* q = p_ + n;
    const char* r = q;
    while (r < e_ && is_space(*r)) ++r;
    if (n > 0 && !(r < e_ && r != q && (is_digit(*r) || *r == '.'))) {
      if (q < e_ && *q == '.') return fail(q, "malformed number (two decimal points); expected one number");
      p_ = q;
      return true;
    }
    // Slow path: gather the number's characters without spaces.
    char buf[80];
    std::size_t len = 0;
    const char* s = start;
    if (s < e_ && (*s == '+' || *s == '-')) {
      buf[len++] = *s++;
      while (s < e_ && is_space(*s)) ++s;
    }
    const char* last_used = s;
    while (s < e_ && (is_digit(*s) || *s == '.' || is_space(*s))) {
      if (!is_space(*s)) {
        if (len + 1 >= sizeof buf) return fail(start, "number too long; expected at most 78 characters");
        buf[len++] = *s;
        last_used = s + 1;
      }
      ++s;
    }
    n = parse_decimal(buf, buf + len, v);
    if (n == 0) return fail(start, std::string(1, letter) + " word without a value; expected a number after " + letter);
    if (n != len) return fail(start, "malformed number (two decimal points); expected one number");
    (void)at;
    p_ = last_used;
    return true;
  }

  // ---- constant expressions (LinuxCNC syntax, no parameters) ----
  // After '[': expression then ']'.
  bool bracket_rest(double& v, int depth) {
    if (depth > kMaxExprDepth) return fail(p_, "expression nested too deeply; expected at most 32 levels of brackets");
    if (!expr(v, depth + 1)) return false;
    skip_spaces();
    if (p_ == e_ || *p_ != ']') return fail(p_ < e_ ? p_ : e_, "expression not closed; expected ']'");
    ++p_;
    return true;
  }
  bool expr(double& v, int depth) {  // + and -
    if (!term(v, depth)) return false;
    while (true) {
      skip_spaces();
      if (p_ < e_ && (*p_ == '+' || *p_ == '-')) {
        const char op = *p_++;
        double r = 0.0;
        if (!term(r, depth)) return false;
        v = op == '+' ? v + r : v - r;
        continue;
      }
      if (p_ < e_ && is_alpha(*p_)) {
        const char* at = p_;
        std::string_view name = read_name();
        if (is_name(name, "MOD")) {  // MOD binds like '*', but a MOD after a sum is rare: apply here
          double r = 0.0;
          if (!term(r, depth)) return false;
          if (r == 0.0) return fail(at, "MOD by zero in expression; expected a nonzero divisor");
          v = std::fmod(v, r);
          if (v < 0) v += std::fabs(r);
          continue;
        }
        return fail(at, "operator '" + std::string(name) + "' is not supported; expected + - * / MOD ** or ']'");
      }
      return true;
    }
  }
  bool term(double& v, int depth) {  // * and /
    if (!power(v, depth)) return false;
    while (true) {
      skip_spaces();
      if (p_ < e_ && *p_ == '*' && !(p_ + 1 < e_ && p_[1] == '*')) {
        ++p_;
        double r = 0.0;
        if (!power(r, depth)) return false;
        v *= r;
      } else if (p_ < e_ && *p_ == '/') {
        const char* at = p_++;
        double r = 0.0;
        if (!power(r, depth)) return false;
        if (r == 0.0) return fail(at, "division by zero in expression; expected a nonzero divisor");
        v /= r;
      } else {
        return true;
      }
    }
  }
  bool power(double& v, int depth) {
    if (!unary(v, depth)) return false;
    skip_spaces();
    while (p_ + 1 < e_ && p_[0] == '*' && p_[1] == '*') {
      const char* at = p_;
      p_ += 2;
      double r = 0.0;
      if (!unary(r, depth)) return false;
      v = std::pow(v, r);
      if (!std::isfinite(v)) return fail(at, "'**' gives no finite number; expected a smaller power");
      skip_spaces();
    }
    return true;
  }
  bool unary(double& v, int depth) {
    if (depth > kMaxExprDepth) return fail(p_, "expression nested too deeply; expected at most 32 levels of brackets");
    skip_spaces();
    if (p_ == e_) return fail(e_, "expression ends early; expected a number, '[' or a function");
    const char c = *p_;
    if (c == '-' || c == '+') {
      ++p_;
      if (!unary(v, depth + 1)) return false;
      if (c == '-') v = -v;
      return true;
    }
    if (c == '[') {
      ++p_;
      return bracket_rest(v, depth + 1);
    }
    if (c == '#') return fail(p_, "parameters ('#') are not supported; expected a number");
    if (is_alpha(c)) {
      const char* at = p_;
      errors_before_ = sink_.error_count();
      if (!function_call(v, depth + 1)) {
        if (sink_.error_count() == errors_before_)
          return fail(at, "unknown function; expected a number or a function such as SQRT[...]");
        return false;
      }
      return true;
    }
    const char* at = p_;
    const std::size_t n = parse_decimal(p_, e_, v);
    if (n == 0) return fail(at, "unexpected " + describe(c) + " in expression; expected a number, '[' or a function");
    p_ += n;
    return true;
  }
  std::string_view read_name() {
    const char* s = p_;
    while (p_ < e_ && is_alpha(*p_)) ++p_;
    return std::string_view(s, static_cast<std::size_t>(p_ - s));
  }
  static bool is_name(std::string_view name, const char* want) {
    if (name.size() != std::char_traits<char>::length(want)) return false;
    for (std::size_t i = 0; i < name.size(); ++i) {
      if (upper(name[i]) != want[i]) return false;
    }
    return true;
  }
  // NAME[expr] (or ATAN[a]/[b]). Returns false without reporting when the name is not a function.
  bool function_call(double& v, int depth) {
    errors_before_ = sink_.error_count();
    const char* at = p_;
    const char* save = p_;
    const Func f = lookup_function(read_name());
    if (f == Func::kNone) {
      p_ = save;
      return false;
    }
    if (f == Func::kExists) return fail(at, "EXISTS[] needs parameters, which are not supported; expected a number");
    skip_spaces();
    if (p_ == e_ || *p_ != '[') return fail(p_ < e_ ? p_ : e_, "function without argument; expected '['");
    ++p_;
    double a = 0.0;
    if (!bracket_rest(a, depth + 1)) return false;
    constexpr double d2r = kPi / 180.0;
    switch (f) {
      case Func::kAbs: v = std::fabs(a); break;
      case Func::kAcos:
        if (a < -1.0 || a > 1.0) return fail(at, "ACOS argument outside [-1, 1]; expected a value from -1 to 1");
        v = std::acos(a) / d2r;
        break;
      case Func::kAsin:
        if (a < -1.0 || a > 1.0) return fail(at, "ASIN argument outside [-1, 1]; expected a value from -1 to 1");
        v = std::asin(a) / d2r;
        break;
      case Func::kAtan: {
        skip_spaces();
        if (p_ == e_ || *p_ != '/') return fail(p_ < e_ ? p_ : e_, "ATAN needs two arguments; expected ATAN[y]/[x]");
        ++p_;
        skip_spaces();
        if (p_ == e_ || *p_ != '[') return fail(p_ < e_ ? p_ : e_, "ATAN needs two arguments; expected ATAN[y]/[x]");
        ++p_;
        double b = 0.0;
        if (!bracket_rest(b, depth + 1)) return false;
        v = std::atan2(a, b) / d2r;
        break;
      }
      case Func::kCos: v = std::cos(a * d2r); break;
      case Func::kExp: v = std::exp(a); break;
      case Func::kFix: v = std::floor(a); break;
      case Func::kFup: v = std::ceil(a); break;
      case Func::kLn:
        if (a <= 0.0) return fail(at, "LN of a number <= 0; expected a positive argument");
        v = std::log(a);
        break;
      case Func::kRound: v = std::round(a); break;
      case Func::kSin: v = std::sin(a * d2r); break;
      case Func::kSqrt:
        if (a < 0.0) return fail(at, "SQRT of a negative number; expected an argument >= 0");
        v = std::sqrt(a);
        break;
      case Func::kTan: v = std::tan(a * d2r); break;
      case Func::kNone:
      case Func::kExists: break;
    }
    if (!std::isfinite(v)) return fail(at, "function result is not a finite number; expected a finite value");
    return true;
  }

  const char* b_;
  const char* p_;
  const char* e_;
  int line_;
  DiagnosticSink& sink_;
  std::uint64_t errors_before_ = 0;
};

}  // namespace

std::size_t parse_decimal(const char* first, const char* last, double& out) {
  const char* p = first;
  bool neg = false;
  if (p < last && (*p == '+' || *p == '-')) {
    neg = *p == '-';
    ++p;
  }
  // All digits go into one integer; up to 15 of them (leading zeros included) it is exact, and
  // one correctly rounded division by an exact power of ten gives the same double as strtod.
  std::uint64_t m = 0;
  const char* digits = p;
  while (p < last && is_digit(*p)) m = m * 10 + static_cast<unsigned>(*p++ - '0');
  std::ptrdiff_t count = p - digits;
  std::ptrdiff_t frac = 0;
  if (p < last && *p == '.') {
    ++p;
    const char* f = p;
    while (p < last && is_digit(*p)) m = m * 10 + static_cast<unsigned>(*p++ - '0');
    frac = p - f;
    count += frac;
  }
  if (count == 0) return 0;
  if (count <= 15) {
    const double v = frac > 0 ? static_cast<double>(m) / kPow10[frac] : static_cast<double>(m);
    out = neg ? -v : v;
    return static_cast<std::size_t>(p - first);
  }
  // Long numbers (m may have overflowed): the standard library's correctly rounded conversion.
  const char* s = first;
  if (*s == '+') ++s;
  double v = 0.0;
  const auto r = std::from_chars(s, p, v);
  if (r.ec != std::errc() || r.ptr != p) {
    out = neg ? -HUGE_VAL : HUGE_VAL;  // out of range: the caller's range check reports it
  } else {
    out = v;
  }
  return static_cast<std::size_t>(p - first);
}

bool lex_line(std::string_view text, int line_no, LexedLine& out, DiagnosticSink& sink) {
  LineLexer lexer(text, line_no, sink);
  return lexer.run(out);
}

}  // namespace pcnc
