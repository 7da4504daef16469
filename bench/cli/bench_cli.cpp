// bench_cli.cpp — the benches' command line on CLI11, compiled once (bench_cli.hpp).
#include "bench_cli.hpp"

#include <CLI/CLI.hpp>
#include <deque>

namespace pcnc {

struct BenchCli::Impl {
  CLI::App app;
  std::deque<Option> options;  // stable addresses
  explicit Impl(const std::string& description) : app(description) {}
};

BenchCli::Option* BenchCli::Option::required() {
  impl_->required();
  return this;
}

BenchCli::Option* BenchCli::Option::show_default() {
  impl_->capture_default_str();
  return this;
}

BenchCli::Option* BenchCli::Option::positive() {
  impl_->check(CLI::PositiveNumber);
  return this;
}

BenchCli::Option* BenchCli::Option::one_of(const std::vector<std::string>& choices) {
  impl_->check(CLI::IsMember(choices));
  return this;
}

BenchCli::BenchCli(const std::string& description) : impl_(std::make_unique<Impl>(description)) {}
BenchCli::~BenchCli() = default;

template <class T>
BenchCli::Option* BenchCli::add_option(const std::string& name, T& value, const std::string& help) {
  impl_->options.push_back(Option(impl_->app.add_option(name, value, help)));
  return &impl_->options.back();
}

void BenchCli::add_flag(const std::string& name, bool& value, const std::string& help) { impl_->app.add_flag(name, value, help); }

int BenchCli::parse(int argc, char** argv) {
  try {
    impl_->app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return impl_->app.exit(e);
  }
  return -1;
}

template BenchCli::Option* BenchCli::add_option<double>(const std::string&, double&, const std::string&);
template BenchCli::Option* BenchCli::add_option<int>(const std::string&, int&, const std::string&);
template BenchCli::Option* BenchCli::add_option<long>(const std::string&, long&, const std::string&);
template BenchCli::Option* BenchCli::add_option<long long>(const std::string&, long long&, const std::string&);
template BenchCli::Option* BenchCli::add_option<unsigned>(const std::string&, unsigned&, const std::string&);
template BenchCli::Option* BenchCli::add_option<unsigned long>(const std::string&, unsigned long&, const std::string&);
template BenchCli::Option* BenchCli::add_option<unsigned long long>(const std::string&, unsigned long long&, const std::string&);
template BenchCli::Option* BenchCli::add_option<std::string>(const std::string&, std::string&, const std::string&);

}  // namespace pcnc
