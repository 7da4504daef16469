// parameters.cpp — the program's parameters (see parameters.hpp).
#include "gcode/parameters.hpp"

namespace pcnc {

ParameterStore::ParameterStore() : numbered_(static_cast<std::size_t>(kMaxReadable) + 1, 0.0) {
  numbered_[kDebugOutput] = 1.0;
}

std::string ParameterStore::normalize(std::string_view name) {
  std::string s;
  s.reserve(name.size());
  for (char c : name) {
    if (c == ' ' || c == '\t') continue;
    s.push_back((c >= 'A' && c <= 'Z') ? static_cast<char>(c + 32) : c);
  }
  return s;
}

bool ParameterStore::read(int number, double& value, std::string& why) const {
  if (number < 1 || number > kMaxReadable) {
    why = "parameter #" + std::to_string(number) + " does not exist; expected #1 to #" + std::to_string(kMaxReadable);
    return false;
  }
  const bool computed = number > kMaxNumbered || (number >= 5021 && number <= 5029);
  if (system_ != nullptr && computed && system_->numbered(number, value)) return true;
  value = numbered_[static_cast<std::size_t>(number)];
  return true;
}

bool ParameterStore::read(std::string_view name, double& value, std::string& why) const {
  if (!name.empty() && name[0] == '_') {
    if (name == "_value") {
      value = value_;
      return true;
    }
    if (name == "_value_returned") {
      value = value_returned_ ? 1.0 : 0.0;
      return true;
    }
    if (system_ != nullptr && system_->named(name, value)) return true;
    const auto it = globals_.find(std::string(name));
    if (it != globals_.end()) {
      value = it->second;
      return true;
    }
  } else {
    const auto& l = locals();
    const auto it = l.find(std::string(name));
    if (it != l.end()) {
      value = it->second;
      return true;
    }
  }
  why = "named parameter #<" + std::string(name) + "> is not defined; expected it to be set before it is read";
  return false;
}

bool ParameterStore::exists(std::string_view name) const {
  double v = 0.0;
  std::string why;
  return read(name, v, why);
}

bool ParameterStore::write(int number, double value, std::string& why) {
  if ((number < 1 || number > kMaxNumbered) && number != kDebugOutput) {
    why = number > kMaxNumbered && number <= kMaxReadable
              ? "parameter #" + std::to_string(number) + " is read-only; expected a parameter from #1 to #" +
                    std::to_string(kMaxNumbered) + " (or #5599, the (DEBUG,...) switch)"
              : "parameter #" + std::to_string(number) + " does not exist; expected #1 to #" +
                    std::to_string(kMaxNumbered);
    return false;
  }
  numbered_[static_cast<std::size_t>(number)] = value;
  return true;
}

std::size_t ParameterStore::name_count() const {
  std::size_t n = globals_.size() + main_locals_.size();
  for (const Frame& f : frames_) n += f.locals.size();
  return n;
}

bool ParameterStore::write(std::string_view name, double value, std::string& why) {
  const bool global = !name.empty() && name[0] == '_';
  double dummy = 0.0;
  if (global && (name == "_value" || name == "_value_returned" || (system_ != nullptr && system_->named(name, dummy)))) {
    why = "#<" + std::string(name) + "> is a read-only system parameter; expected another name";
    return false;
  }
  auto& table = global ? globals_ : locals();
  auto it = table.find(std::string(name));
  if (it != table.end()) {
    it->second = value;
    return true;
  }
  if (name_count() >= kMaxNames) {
    why = "too many named parameters; expected at most " + std::to_string(kMaxNames);
    return false;
  }
  table.emplace(std::string(name), value);
  return true;
}

bool ParameterStore::push_call(const double* args, int count) {
  if (static_cast<int>(frames_.size()) >= kMaxCallDepth) return false;
  Frame f;
  for (int i = 0; i < kLocalNumbered; ++i) {
    f.saved[static_cast<std::size_t>(i)] = numbered_[static_cast<std::size_t>(i + 1)];
    numbered_[static_cast<std::size_t>(i + 1)] = i < count ? args[i] : 0.0;
  }
  frames_.push_back(std::move(f));
  return true;
}

void ParameterStore::pop_call() {
  if (frames_.empty()) return;
  const Frame& f = frames_.back();
  for (int i = 0; i < kLocalNumbered; ++i) numbered_[static_cast<std::size_t>(i + 1)] = f.saved[static_cast<std::size_t>(i)];
  frames_.pop_back();
}

}  // namespace pcnc
