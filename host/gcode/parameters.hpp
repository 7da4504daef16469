// parameters.hpp — the program's parameters (RS274NGC '#' values), read by the lexer while it
// evaluates a line and written when the line's assignments take effect.
//
// Three kinds, as in LinuxCNC:
//   numbered  #1 .. #5399: always exist (0 until set). #1-#30 are the arguments of a
//             subroutine call and local to it; #31-#5000 are global; #5001-#5399 hold the
//             machine's state (probe result, stored positions, offsets: the interpreter keeps
//             them current). #5400-#5428 (tool, position) are computed on read, read-only.
//   named     #<name> is local to the subroutine level it is set in; #<_name> is global.
//             Reading a named parameter that was never set is an error (LinuxCNC: "named
//             parameter not defined"). Names are case-insensitive and spaces are removed.
//   system    #<_x>, #<_metric>, #<_value>, ... : read-only views of the modal state (the
//             interpreter answers them through SystemParameters), except _value and
//             _value_returned, which a subroutine's return sets.
// Memory is bounded by the program's distinct names, not its length.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

namespace pcnc {

/// The read-only, computed parameters: the interpreter implements it.
class SystemParameters {
 public:
  virtual ~SystemParameters() = default;
  /// #5400-#5428 and the like: true with the value when `number` is computed.
  virtual bool numbered(int number, double& value) const = 0;
  /// #<_x>, #<_metric>, ...: true with the value when `name` (normalized, without '#<>') is one.
  virtual bool named(std::string_view name, double& value) const = 0;
};

class ParameterStore {
 public:
  static constexpr int kMaxNumbered = 5399;    // #1 .. #5399 can be written (#5400+ are computed)
  static constexpr int kMaxReadable = 5602;    // the highest number a program may read
  static constexpr int kDebugOutput = 5599;    // writable too: 1 (at start) shows (DEBUG,...), 0 hides them (LinuxCNC)
  static constexpr int kLocalNumbered = 30;    // #1-#30: subroutine arguments, local
  static constexpr int kMaxCallDepth = 64;     // nested subroutine calls (recursion limit)
  static constexpr std::size_t kMaxNames = 100000;

  ParameterStore();

  void set_system(const SystemParameters* system) { system_ = system; }

  /// Reads #number. False (with `why`) for a number out of range.
  bool read(int number, double& value, std::string& why) const;
  /// Reads #<name> (normalized). False (with `why`) when it was never set.
  bool read(std::string_view name, double& value, std::string& why) const;
  /// EXISTS[#<name>]: true when the named parameter is set (or is a system parameter).
  bool exists(std::string_view name) const;

  /// Writes #number. False (with `why`) for a number out of range or read-only.
  bool write(int number, double value, std::string& why);
  /// Writes #<name>. False (with `why`) for a read-only system name or too many names.
  bool write(std::string_view name, double value, std::string& why);

  /// Direct access for the interpreter's state parameters (#5001-#5399), no checks.
  double& at(int number) { return numbered_[static_cast<std::size_t>(number)]; }
  double at(int number) const { return numbered_[static_cast<std::size_t>(number)]; }

  /// Enters a subroutine: saves #1-#30 and sets them from `args` (the rest 0); a new local
  /// name scope. False when the depth limit is reached.
  bool push_call(const double* args, int count);
  /// Leaves it: restores #1-#30 and drops its local names.
  void pop_call();
  int call_depth() const { return static_cast<int>(frames_.size()); }

  /// The subroutine's return value (#<_value>, #<_value_returned>).
  void set_return_value(bool returned, double value) {
    value_returned_ = returned;
    value_ = returned ? value : 0.0;
  }
  double value() const { return value_; }
  bool value_returned() const { return value_returned_; }

  /// A name as LinuxCNC compares it: lower case, spaces and tabs removed.
  static std::string normalize(std::string_view name);

 private:
  struct Frame {
    std::array<double, kLocalNumbered> saved{};
    std::unordered_map<std::string, double> locals;
  };
  std::unordered_map<std::string, double>& locals() { return frames_.empty() ? main_locals_ : frames_.back().locals; }
  const std::unordered_map<std::string, double>& locals() const {
    return frames_.empty() ? main_locals_ : frames_.back().locals;
  }
  std::size_t name_count() const;

  std::vector<double> numbered_;
  std::unordered_map<std::string, double> globals_;
  std::unordered_map<std::string, double> main_locals_;
  std::vector<Frame> frames_;
  const SystemParameters* system_ = nullptr;
  double value_ = 0.0;
  bool value_returned_ = false;
};

}  // namespace pcnc
