// expression.cpp — word values: numbers, parameters, functions and bracketed expressions
// (see expression.hpp).
#include "gcode/expression.hpp"

#include <charconv>
#include <cmath>
#include <cstdio>

namespace pcnc {
namespace {

constexpr double kPow10[] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,  1e8,  1e9,  1e10, 1e11,
                             1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};
constexpr int kMaxDepth = 32;
constexpr double kDegree = 3.14159265358979323846 / 180.0;
constexpr double kToleranceEqual = 1e-6;  // EQ/NE/LE/GE compare within this (LinuxCNC's)

inline bool is_digit(char c) { return c >= '0' && c <= '9'; }
inline bool is_alpha(char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z'); }
inline char upper(char c) { return (c >= 'a' && c <= 'z') ? static_cast<char>(c - 32) : c; }

bool same_name(std::string_view name, const char* want) {
  if (name.size() != std::char_traits<char>::length(want)) return false;
  for (std::size_t i = 0; i < name.size(); ++i) {
    if (upper(name[i]) != want[i]) return false;
  }
  return true;
}

std::string describe(char c) {
  if (c >= 33 && c <= 126) return std::string("'") + c + "'";
  static const char* hex = "0123456789abcdef";
  const auto u = static_cast<unsigned char>(c);
  return std::string("byte 0x") + hex[u >> 4] + hex[u & 15];
}

// Binary operators and their precedence (LinuxCNC's six levels; ']' closes).
enum Op : int { kClose, kAnd, kOr, kXor, kEq, kNe, kGt, kGe, kLt, kLe, kPlus, kMinus, kTimes, kDivide, kMod, kPower };
int precedence(int op) {
  switch (op) {
    case kClose: return 1;
    case kAnd:
    case kOr:
    case kXor: return 2;
    case kEq:
    case kNe:
    case kGt:
    case kGe:
    case kLt:
    case kLe: return 3;
    case kPlus:
    case kMinus: return 4;
    case kTimes:
    case kDivide:
    case kMod: return 5;
    default: return 6;
  }
}

enum class Func { kNone, kAbs, kAcos, kAsin, kAtan, kCos, kExp, kFix, kFup, kLn, kRound, kSin, kSqrt, kTan, kExists };

Func lookup_function(std::string_view name) {
  struct Entry {
    const char* name;
    Func f;
  };
  static constexpr Entry kTable[] = {{"ABS", Func::kAbs},     {"ACOS", Func::kAcos}, {"ASIN", Func::kAsin},
                                     {"ATAN", Func::kAtan},   {"COS", Func::kCos},   {"EXP", Func::kExp},
                                     {"FIX", Func::kFix},     {"FUP", Func::kFup},   {"LN", Func::kLn},
                                     {"ROUND", Func::kRound}, {"SIN", Func::kSin},   {"SQRT", Func::kSqrt},
                                     {"TAN", Func::kTan},     {"EXISTS", Func::kExists}};
  for (const Entry& e : kTable) {
    if (same_name(name, e.name)) return e.f;
  }
  return Func::kNone;
}

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

// A number, possibly with spaces inside ("1 .5"), as RS274 allows.
bool ExpressionReader::number(double& v) {
  const char* start = c_.p;
  const char* e = c_.end;
  std::size_t n = parse_decimal(start, e, v);
  const char* q = start + n;
  const char* r = q;
  while (r < e && (*r == ' ' || *r == '\t')) ++r;
  if (n > 0 && !(r < e && r != q && (is_digit(*r) || *r == '.'))) {
    if (q < e && *q == '.') return c_.fail(q, "malformed number (two decimal points); expected one number");
    c_.p = q;
    return true;
  }
  // Slow path: gather the number's characters without spaces.
  char buf[80];
  std::size_t len = 0;
  const char* s = start;
  if (s < e && (*s == '+' || *s == '-')) {
    buf[len++] = *s++;
    while (s < e && (*s == ' ' || *s == '\t')) ++s;
  }
  const char* last_used = s;
  while (s < e && (is_digit(*s) || *s == '.' || *s == ' ' || *s == '\t')) {
    if (*s != ' ' && *s != '\t') {
      if (len + 1 >= sizeof buf) return c_.fail(start, "number too long; expected at most 78 characters");
      buf[len++] = *s;
      last_used = s + 1;
    }
    ++s;
  }
  n = parse_decimal(buf, buf + len, v);
  if (n == 0) {
    return c_.fail(start, start < e ? "unexpected " + describe(*start) +
                                          "; expected a number, a parameter '#', '[' or a function"
                                    : std::string("value missing at the end of the line; expected a number"));
  }
  if (n != len) return c_.fail(start, "malformed number (two decimal points); expected one number");
  c_.p = last_used;
  return true;
}

bool ExpressionReader::real_value(double& v, int depth) {
  if (depth > kMaxDepth) return c_.fail(c_.p, "expression nested too deeply; expected at most 32 levels");
  c_.skip_spaces();
  if (c_.at_end()) return c_.fail(c_.end, "value missing at the end of the line; expected a number, '#', '[' or a function");
  const char* at = c_.p;
  const char ch = *c_.p;
  if (ch == '[') {
    ++c_.p;
    if (!bracket_rest(v, depth + 1)) return false;
  } else if (ch == '#') {
    ++c_.p;
    if (!parameter_value(v, at, depth + 1)) return false;
  } else if ((ch == '-' || ch == '+')) {
    // A sign before a digit belongs to the number; before anything else it applies to the value.
    const char* q = c_.p + 1;
    while (q < c_.end && (*q == ' ' || *q == '\t')) ++q;
    if (q < c_.end && (is_digit(*q) || *q == '.')) {
      if (!number(v)) return false;
    } else {
      c_.p = q;
      if (!real_value(v, depth + 1)) return false;
      if (ch == '-') v = -v;
    }
  } else if (is_alpha(ch)) {
    bool is_function = false;
    if (!function_call(v, depth + 1, is_function)) return false;
    if (!is_function) return c_.fail(at, "unknown function; expected a number or a function such as SQRT[...]");
  } else {
    if (!number(v)) return false;
  }
  if (std::isnan(v)) return c_.fail(at, "the value is not a number; expected a finite result");
  if (std::isinf(v)) return c_.fail(at, "the value is infinite; expected a finite result");
  return true;
}

bool ExpressionReader::read_operator(int& op, const char*& at) {
  c_.skip_spaces();
  at = c_.p;
  if (c_.at_end()) return c_.fail(c_.end, "expression not closed; expected ']' or an operator");
  const char ch = *c_.p;
  switch (ch) {
    case ']': ++c_.p; op = kClose; return true;
    case '+': ++c_.p; op = kPlus; return true;
    case '-': ++c_.p; op = kMinus; return true;
    case '/': ++c_.p; op = kDivide; return true;
    case '*':
      ++c_.p;
      if (!c_.at_end() && *c_.p == '*') {
        ++c_.p;
        op = kPower;
      } else {
        op = kTimes;
      }
      return true;
    default: break;
  }
  if (is_alpha(ch)) {
    const char* s = c_.p;
    while (c_.p < c_.end && is_alpha(*c_.p)) ++c_.p;
    const std::string_view name(s, static_cast<std::size_t>(c_.p - s));
    struct Entry {
      const char* name;
      int op;
    };
    static constexpr Entry kOps[] = {{"MOD", kMod}, {"AND", kAnd}, {"OR", kOr}, {"XOR", kXor}, {"EQ", kEq},
                                     {"NE", kNe},   {"GT", kGt},   {"GE", kGe}, {"LT", kLt},   {"LE", kLe}};
    for (const Entry& e : kOps) {
      if (same_name(name, e.name)) {
        op = e.op;
        return true;
      }
    }
    return c_.fail(s, "unknown operator '" + std::string(name) +
                          "'; expected + - * / MOD ** AND OR XOR EQ NE GT GE LT LE or ']'");
  }
  return c_.fail(at, "unexpected " + describe(ch) + " in expression; expected an operator or ']'");
}

bool ExpressionReader::apply(double& left, int op, double right, const char* at) {
  switch (op) {
    case kPlus: left += right; break;
    case kMinus: left -= right; break;
    case kTimes: left *= right; break;
    case kDivide:
      if (right == 0.0) return c_.fail(at, "division by zero in expression; expected a nonzero divisor");
      left /= right;
      break;
    case kMod:
      if (right == 0.0) return c_.fail(at, "MOD by zero in expression; expected a nonzero divisor");
      left = std::fmod(left, right);
      if (left < 0.0) left += std::fabs(right);
      break;
    case kPower:
      if (left < 0.0 && std::floor(right) != right)
        return c_.fail(at, "a negative number raised to a non-integer power; expected an integer exponent");
      left = std::pow(left, right);
      break;
    case kAnd: left = (left != 0.0 && right != 0.0) ? 1.0 : 0.0; break;
    case kOr: left = (left != 0.0 || right != 0.0) ? 1.0 : 0.0; break;
    case kXor: left = ((left != 0.0) != (right != 0.0)) ? 1.0 : 0.0; break;
    case kEq: left = std::fabs(left - right) < kToleranceEqual ? 1.0 : 0.0; break;
    case kNe: left = std::fabs(left - right) >= kToleranceEqual ? 1.0 : 0.0; break;
    case kGt: left = left > right ? 1.0 : 0.0; break;
    case kLt: left = left < right ? 1.0 : 0.0; break;
    case kGe: left = (std::fabs(left - right) < kToleranceEqual || left >= right) ? 1.0 : 0.0; break;
    case kLe: left = (std::fabs(left - right) < kToleranceEqual || left <= right) ? 1.0 : 0.0; break;
    default: break;
  }
  if (!std::isfinite(left)) return c_.fail(at, "the expression gives no finite number; expected smaller values");
  return true;
}

// After '[': values and operators up to the closing ']', evaluated by precedence, left to
// right within a level (a stack of at most one pending operation per level).
bool ExpressionReader::bracket_rest(double& v, int depth) {
  if (depth > kMaxDepth) return c_.fail(c_.p, "expression nested too deeply; expected at most 32 levels");
  double values[8];
  int ops[8];
  const char* op_at[8];
  int n = 0;  // pending (value, operator) pairs
  double cur = 0.0;
  if (!real_value(cur, depth)) return false;
  while (true) {
    int op = kClose;
    const char* at = nullptr;
    if (!read_operator(op, at)) return false;
    // Reduce while the pending operator binds at least as tightly as this one.
    while (n > 0 && precedence(ops[n - 1]) >= precedence(op)) {
      double left = values[n - 1];
      if (!apply(left, ops[n - 1], cur, op_at[n - 1])) return false;
      cur = left;
      --n;
    }
    if (op == kClose) {
      v = cur;
      return true;
    }
    values[n] = cur;
    ops[n] = op;
    op_at[n] = at;
    ++n;
    if (!real_value(cur, depth)) return false;
  }
}

bool ExpressionReader::parameter_ref(int& number, std::string& name, const char* hash, int depth) {
  number = 0;
  name.clear();
  c_.skip_spaces();
  if (c_.at_end()) return c_.fail(hash, "'#' without a parameter; expected #123, #<name> or #[expression]");
  if (*c_.p == '<') {
    const char* open = c_.p++;
    const char* s = c_.p;
    while (c_.p < c_.end && *c_.p != '>') ++c_.p;
    if (c_.at_end()) return c_.fail(open, "named parameter not closed; expected '>' after the name");
    name = ParameterStore::normalize(std::string_view(s, static_cast<std::size_t>(c_.p - s)));
    ++c_.p;
    if (name.empty()) return c_.fail(open, "empty parameter name; expected #<name>");
    for (char ch : name) {
      if (ch == '<' || ch == '#' || ch == '[' || ch == ']' || ch == '(' || ch == ')')
        return c_.fail(open, "bad character " + describe(ch) + " in a parameter name; expected letters, digits and _");
    }
    return true;
  }
  double idx = 0.0;
  if (*c_.p == '[' || *c_.p == '#' || ((*c_.p >= 'a' && *c_.p <= 'z') || (*c_.p >= 'A' && *c_.p <= 'Z'))) {
    if (!real_value(idx, depth + 1)) return false;
  } else {
    const char* s = c_.p;
    std::size_t k = parse_decimal(c_.p, c_.end, idx);
    if (k == 0 || *s == '-' || *s == '+')
      return c_.fail(hash, "'#' without a parameter; expected #123, #<name> or #[expression]");
    c_.p += k;
  }
  const double r = std::round(idx);
  if (std::fabs(idx - r) > 1e-6 || r < 1.0 || r > ParameterStore::kMaxReadable) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%g", idx);
    return c_.fail(hash, std::string("parameter number ") + buf + " out of range; expected a whole number from 1 to " +
                             std::to_string(ParameterStore::kMaxReadable));
  }
  number = static_cast<int>(r);
  return true;
}

bool ExpressionReader::parameter_value(double& v, const char* hash, int depth) {
  int number = 0;
  std::string name;
  if (!parameter_ref(number, name, hash, depth)) return false;
  std::string why;
  const bool ok = number > 0 ? params_.read(number, v, why) : params_.read(name, v, why);
  if (!ok) return c_.fail(hash, why);
  return true;
}

// NAME[expr] (or ATAN[a]/[b], EXISTS[#<name>]).
bool ExpressionReader::function_call(double& v, int depth, bool& is_function) {
  const char* at = c_.p;
  const char* s = c_.p;
  while (c_.p < c_.end && is_alpha(*c_.p)) ++c_.p;
  const Func f = lookup_function(std::string_view(s, static_cast<std::size_t>(c_.p - s)));
  if (f == Func::kNone) {
    c_.p = s;
    is_function = false;
    return true;
  }
  is_function = true;
  c_.skip_spaces();
  if (c_.at_end() || *c_.p != '[') return c_.fail(c_.p, "function without argument; expected '['");
  ++c_.p;
  if (f == Func::kExists) {
    c_.skip_spaces();
    if (c_.at_end() || *c_.p != '#') return c_.fail(c_.p, "EXISTS needs a named parameter; expected EXISTS[#<name>]");
    const char* hash = c_.p++;
    c_.skip_spaces();
    const char nc = c_.at_end() ? '\0' : *c_.p;
    if (nc != '<' && nc != '#' && nc != '[' && !(nc >= '0' && nc <= '9'))
      return c_.fail(hash, "EXISTS needs a parameter; expected EXISTS[#<name>] or EXISTS[#123]");
    bool exists = false;
    if (nc >= '0' && nc <= '9') {  // a number: whether such a parameter can exist (LinuxCNC)
      double n = 0.0;
      c_.p += parse_decimal(c_.p, c_.end, n);
      exists = n == std::floor(n) && n >= 1.0 && n <= ParameterStore::kMaxReadable;
    } else {
      int number = 0;
      std::string name;
      if (!parameter_ref(number, name, hash, depth)) return false;
      exists = number > 0 || params_.exists(name);
    }
    c_.skip_spaces();
    if (c_.at_end() || *c_.p != ']') return c_.fail(c_.p < c_.end ? c_.p : hash, "EXISTS[] not closed; expected ']'");
    ++c_.p;
    v = exists ? 1.0 : 0.0;
    return true;
  }
  double a = 0.0;
  if (!bracket_rest(a, depth + 1)) return false;
  switch (f) {
    case Func::kAbs: v = std::fabs(a); break;
    case Func::kAcos:
      if (a < -1.0 || a > 1.0) return c_.fail(at, "ACOS argument outside [-1, 1]; expected a value from -1 to 1");
      v = std::acos(a) / kDegree;
      break;
    case Func::kAsin:
      if (a < -1.0 || a > 1.0) return c_.fail(at, "ASIN argument outside [-1, 1]; expected a value from -1 to 1");
      v = std::asin(a) / kDegree;
      break;
    case Func::kAtan: {
      c_.skip_spaces();
      if (c_.at_end() || *c_.p != '/') return c_.fail(c_.p, "ATAN needs two arguments; expected ATAN[y]/[x]");
      ++c_.p;
      c_.skip_spaces();
      if (c_.at_end() || *c_.p != '[') return c_.fail(c_.p, "ATAN needs two arguments; expected ATAN[y]/[x]");
      ++c_.p;
      double b = 0.0;
      if (!bracket_rest(b, depth + 1)) return false;
      v = std::atan2(a, b) / kDegree;
      break;
    }
    case Func::kCos: v = std::cos(a * kDegree); break;
    case Func::kExp: v = std::exp(a); break;
    case Func::kFix: v = std::floor(a); break;
    case Func::kFup: v = std::ceil(a); break;
    case Func::kLn:
      if (a <= 0.0) return c_.fail(at, "LN of a number <= 0; expected a positive argument");
      v = std::log(a);
      break;
    case Func::kRound: v = std::round(a); break;
    case Func::kSin: v = std::sin(a * kDegree); break;
    case Func::kSqrt:
      if (a < 0.0) return c_.fail(at, "SQRT of a negative number; expected an argument >= 0");
      v = std::sqrt(a);
      break;
    case Func::kTan: v = std::tan(a * kDegree); break;
    case Func::kNone:
    case Func::kExists: break;
  }
  if (!std::isfinite(v)) return c_.fail(at, "function result is not a finite number; expected a finite value");
  return true;
}

std::string substitute_parameters(std::string_view text, const ParameterStore& params) {
  std::string out;
  char format[8] = "%lf";
  std::size_t i = 0;
  while (i < text.size()) {
    const char ch = text[i];
    if (ch == '%') {
      ++i;
      if (i < text.size() && text[i] == 'd') {
        std::snprintf(format, sizeof format, "%%.0f");
        ++i;
      } else if (i < text.size() && text[i] == 'f') {
        std::snprintf(format, sizeof format, "%%.4f");
        ++i;
      } else if (i < text.size() && text[i] == '.') {
        ++i;
        if (i + 1 < text.size() && is_digit(text[i]) && text[i + 1] == 'f') {
          std::snprintf(format, sizeof format, "%%.%cf", text[i]);
          i += 2;
        } else {
          out.push_back('.');
        }
      } else {
        out.push_back('%');
      }
      continue;
    }
    if (ch != '#') {
      out.push_back(ch);
      ++i;
      continue;
    }
    ++i;
    double v = 0.0;
    bool found = false;
    std::string why;
    if (i < text.size() && is_digit(text[i])) {
      int n = 0;
      while (i < text.size() && is_digit(text[i])) {
        if (n < 100000) n = n * 10 + (text[i] - '0');
        ++i;
      }
      found = params.read(n, v, why);
    } else if (i < text.size() && text[i] == '<') {
      const std::size_t close = text.find('>', i);
      if (close == std::string_view::npos) {
        out += "######";
        break;
      }
      found = params.read(ParameterStore::normalize(text.substr(i + 1, close - i - 1)), v, why);
      i = close + 1;
    } else {
      out.push_back('#');
      continue;
    }
    if (found) {
      if (std::fabs(v) < 1e-12) v = 0.0;
      char buf[64];
      const int k = std::snprintf(buf, sizeof buf, format, v);
      out += (k > 0 && k < static_cast<int>(sizeof buf)) ? buf : "######";
    } else {
      out += "######";
    }
  }
  return out;
}

}  // namespace pcnc
