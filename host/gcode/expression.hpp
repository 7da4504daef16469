// expression.hpp — the value of a word, as the lexer reads it: a number, a parameter (#1,
// #<name>, #[expr], ##1), a function (SIN[30], ATAN[1]/[2], EXISTS[#<x>]), or a bracketed
// expression, evaluated at once against the parameters as they stand before the line's own
// assignments (RS274NGC: every value on a line is read before any '#n=' on it takes effect).
//
// The grammar and arithmetic are LinuxCNC's: six precedence levels (power above times-like
// (* / MOD) above plus-like (+ -) above relational (EQ NE GT GE LT LE, EQ within 1e-6) above
// logical (AND OR XOR)), evaluated left to right within a level; a leading sign binds to its
// operand (-2**2 = 4); angles in degrees; MOD's result is never negative; logical and
// relational results are 1 or 0. Errors name the column and say what was expected.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "gcode/diagnostics.hpp"
#include "gcode/parameters.hpp"

namespace pcnc {

/// A position in one line of text, with the error reporting both lexer and expression use.
struct LineCursor {
  const char* begin;
  const char* p;
  const char* end;
  int line;
  DiagnosticSink& sink;

  int col(const char* q) const { return static_cast<int>(q - begin) + 1; }
  bool at_end() const { return p >= end; }
  bool fail(const char* at, std::string message) {
    sink.error(line, col(at), std::move(message));
    return false;
  }
  void skip_spaces() {
    while (p < end && (*p == ' ' || *p == '\t' || *p == '\r' || *p == '\f' || *p == '\v')) ++p;
  }
};

class ExpressionReader {
 public:
  ExpressionReader(LineCursor& cur, const ParameterStore& params) : c_(cur), params_(params) {}

  /// A real value at the cursor: a number, '#' parameter, function, signed value or '[...]'.
  bool real_value(double& v, int depth = 0);
  /// After a '#': the parameter reference (number, <name>, [expr] or #...). Sets either
  /// `number` (> 0) or `name` (normalized); nothing is read from the store.
  bool parameter_ref(int& number, std::string& name, const char* hash, int depth = 0);
  /// The value of a parameter reference (after its '#').
  bool parameter_value(double& v, const char* hash, int depth = 0);
  /// A plain number at the cursor, possibly with spaces inside ("1 .5"), as RS274 allows.
  bool number(double& v);

 private:
  bool bracket_rest(double& v, int depth);  // after '[': expression then ']'
  bool function_call(double& v, int depth, bool& is_function);
  bool read_operator(int& op, const char*& at);
  bool apply(double& left, int op, double right, const char* at);

  LineCursor& c_;
  const ParameterStore& params_;
};

/// Parses a plain decimal number (optional sign, digits, optional point, digits) exactly as
/// std::from_chars would, faster on the short numbers G-code is made of. Returns the number of
/// characters used (0: not a number).
std::size_t parse_decimal(const char* first, const char* last, double& out);

/// LinuxCNC's (DEBUG,...) text: #n and #<name> replaced by their values ("%lf", or the
/// format a preceding %d, %f or %.Nf selects), "######" for an unknown name.
std::string substitute_parameters(std::string_view text, const ParameterStore& params);

}  // namespace pcnc
