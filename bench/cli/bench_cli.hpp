// bench_cli.hpp — the benches' command line: options, flags and positionals with their help,
// parsed by CLI11 in one file compiled once (bench_cli.cpp).
//
// Debian's CLI11 (2.1) is header-only: each file that includes it spends about 12 s compiling
// it at -O2, and the nineteen benches are a program each. Behind this small interface CLI11 is
// compiled once for all of them, which keeps a bench's compile to its own code (tools/test.sh's
// builds run within CI's time). The benches need little of CLI11: typed options with a help
// line, flags, required positionals, a shown default, a positive number or one of a list.
#pragma once

#include <memory>
#include <string>
#include <vector>

namespace CLI {
class Option;
}  // namespace CLI

namespace pcnc {

class BenchCli {
 public:
  /// One option's settings (returned by add_option; owned by the BenchCli).
  class Option {
   public:
    Option* required();
    Option* show_default();  // the variable's value before parsing appears in --help
    Option* positive();      // a number > 0
    Option* one_of(const std::vector<std::string>& choices);

   private:
    friend class BenchCli;
    explicit Option(CLI::Option* impl) : impl_(impl) {}
    CLI::Option* impl_;
  };

  explicit BenchCli(const std::string& description);
  ~BenchCli();
  BenchCli(const BenchCli&) = delete;
  BenchCli& operator=(const BenchCli&) = delete;

  /// `name` "--x" (or "-x", or "-x,--long") is an option, "NAME" a positional. T: double, int,
  /// long, long long, unsigned, unsigned long, unsigned long long or std::string.
  template <class T>
  Option* add_option(const std::string& name, T& value, const std::string& help = "");
  void add_flag(const std::string& name, bool& value, const std::string& help = "");

  /// Parses the command line. Returns -1 when the bench goes on, else the exit status: 0 after
  /// --help, else CLI11's code for the error it printed.
  int parse(int argc, char** argv);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace pcnc
