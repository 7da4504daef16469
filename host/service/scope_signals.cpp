// scope_signals.cpp — the scope's signals, its trigger condition and capture's parameter check
// (see scope_signals.hpp).
#include "service/scope_signals.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>

namespace pcnc {

using rpc::json;

const std::vector<std::string>& scope_signal_names() {
  static const std::vector<std::string> names = {"line",  "state", "cmd_x",  "cmd_y",  "cmd_z",  "act_x", "act_y",
                                                 "act_z", "ferr_x", "ferr_y", "ferr_z", "speed"};
  return names;
}

int scope_signal_index(std::string_view name) {
  const auto& n = scope_signal_names();
  const auto it = std::find(n.begin(), n.end(), name);
  return it == n.end() ? -1 : static_cast<int>(it - n.begin());
}

double scope_signal_value(const TraceSample& s, int index) {
  switch (index) {
    case 0: return static_cast<double>(s.line);
    case 1: return static_cast<double>(static_cast<int>(s.state));
    case 2: case 3: case 4: return s.commanded[static_cast<std::size_t>(index - 2)];
    case 5: case 6: case 7: return s.actual[static_cast<std::size_t>(index - 5)];
    case 8: case 9: case 10: return s.following_error[static_cast<std::size_t>(index - 8)];
    case 11: return s.speed;
    default: return 0.0;
  }
}

bool Trigger::holds(const TraceSample& s) const {
  double v = scope_signal_value(s, signal);
  if (absolute) v = std::fabs(v);
  switch (op) {
    case TriggerOp::kGreater: return v > level;
    case TriggerOp::kLess: return v < level;
    case TriggerOp::kGreaterEqual: return v >= level;
    case TriggerOp::kLessEqual: return v <= level;
    case TriggerOp::kEqual: return v == level;
    case TriggerOp::kNotEqual: return v != level;
  }
  return false;
}

namespace {

std::string signal_list() {
  std::string list;
  for (const auto& n : scope_signal_names()) list += (list.empty() ? "" : ", ") + n;
  return list;
}

std::string trim_signal(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return std::string(s);
}

}  // namespace

std::optional<Trigger> parse_trigger(std::string_view text, std::string& error) {
  const std::string whole(text);
  auto bad = [&](const std::string& why) {
    error = "bad trigger '" + whole + "': " + why +
            " (expected SIGNAL OP NUMBER, e.g. \"ferr_x>0.005\" or \"abs(ferr_y)>=2e-3\"; OP one of > < >= <= == !=)";
    return std::nullopt;
  };
  const std::size_t op_at = whole.find_first_of("<>=!");
  if (op_at == std::string::npos) return bad("no comparison");
  std::size_t op_len = 1;
  Trigger t;
  t.text = whole;
  const char c0 = whole[op_at], c1 = op_at + 1 < whole.size() ? whole[op_at + 1] : '\0';
  if (c0 == '>' && c1 == '=') { t.op = TriggerOp::kGreaterEqual; op_len = 2; }
  else if (c0 == '<' && c1 == '=') { t.op = TriggerOp::kLessEqual; op_len = 2; }
  else if (c0 == '=' && c1 == '=') { t.op = TriggerOp::kEqual; op_len = 2; }
  else if (c0 == '!' && c1 == '=') { t.op = TriggerOp::kNotEqual; op_len = 2; }
  else if (c0 == '>') t.op = TriggerOp::kGreater;
  else if (c0 == '<') t.op = TriggerOp::kLess;
  else return bad(std::string("'") + c0 + "' is not a comparison");

  std::string lhs = trim_signal(std::string_view(whole).substr(0, op_at));
  const std::string rhs = trim_signal(std::string_view(whole).substr(op_at + op_len));
  if (lhs.empty()) return bad("no signal before the comparison");
  if (lhs.size() > 5 && lhs.rfind("abs(", 0) == 0 && lhs.back() == ')') {
    t.absolute = true;
    lhs = trim_signal(std::string_view(lhs).substr(4, lhs.size() - 5));
  }
  t.signal = scope_signal_index(lhs);
  if (t.signal < 0) return bad("unknown signal '" + lhs + "' (signals: " + signal_list() + ")");
  if (rhs.empty()) return bad("no level after the comparison");
  if (t.signal == scope_signal_index("state")) {
    if (t.absolute) return bad("abs() of state");
    MachineState st{};
    if (parse_state_name(rhs, st)) {
      t.level = static_cast<double>(static_cast<int>(st));
      return t;
    }
  }
  const char* b = rhs.data();
  const char* e = rhs.data() + rhs.size();
  if (*b == '+') ++b;
  const auto r = std::from_chars(b, e, t.level);
  if (r.ec != std::errc() || r.ptr != e || !std::isfinite(t.level)) return bad("'" + rhs + "' is not a number");
  return t;
}

rpc::Checked<CaptureParams> check_capture_params(const json& params, double cycle_hz) {
  rpc::Checked<CaptureParams> out;
  CaptureParams p;
  auto fail = [&](std::string message) {
    out.error = rpc::Error{rpc::kInvalidParams, std::move(message), nullptr};
    return out;
  };
  for (auto it = params.begin(); it != params.end(); ++it) {
    const std::string& k = it.key();
    if (k != "signals" && k != "seconds" && k != "trigger" && k != "pre_trigger_percent" && k != "trigger_timeout_s") {
      return fail("unknown parameter '" + k + "' of capture (expected signals, seconds, trigger, pre_trigger_percent, "
                  "trigger_timeout_s)");
    }
  }
  const auto sig = params.find("signals");
  if (sig == params.end()) return fail("missing parameter 'signals' of capture (an array of names: " + signal_list() + ")");
  if (!sig->is_array() || sig->empty()) return fail("parameter 'signals' of capture must be a non-empty array of names");
  for (const json& s : *sig) {
    if (!s.is_string()) return fail("parameter 'signals' of capture must hold names (strings), got " + s.dump());
    const std::string name = s.get<std::string>();
    const int i = scope_signal_index(name);
    if (i < 0) {
      return fail("unknown signal '" + name + "' in 'signals' of capture (signals: " + signal_list() +
                  "; t is in every row)");
    }
    if (std::find(p.signals.begin(), p.signals.end(), i) != p.signals.end()) return fail("signal '" + name + "' is named twice");
    p.signals.push_back(i);
  }
  auto number = [&](const char* key, double& v) -> bool {
    const auto it = params.find(key);
    if (it == params.end()) return true;
    if (!it->is_number()) return false;
    v = it->get<double>();
    return std::isfinite(v);
  };
  p.seconds = 0.0;
  if (params.find("seconds") == params.end()) return fail("missing parameter 'seconds' of capture");
  if (!number("seconds", p.seconds)) return fail("parameter 'seconds' of capture must be a number");
  const double cycles = std::floor(p.seconds * cycle_hz + 0.5);
  if (!(p.seconds > 0.0) || cycles < 1.0) return fail("parameter 'seconds' of capture must be > 0 (at least one cycle)");
  char buf[256];
  if (p.seconds > kMaxCaptureSeconds) {
    std::snprintf(buf, sizeof buf, "parameter 'seconds' of capture is out of range: %g s; a capture records at most %g s",
                  p.seconds, kMaxCaptureSeconds);
    return fail(buf);
  }
  if (cycles * static_cast<double>(p.signals.size()) > static_cast<double>(kMaxCaptureValues)) {
    std::snprintf(buf, sizeof buf,
                  "a capture holds at most %zu values (seconds x %g Hz x signals): %g s of %zu signals is %.0f; record "
                  "fewer seconds or signals (at most %.3g s of %zu)",
                  kMaxCaptureValues, cycle_hz, p.seconds, p.signals.size(), cycles * static_cast<double>(p.signals.size()),
                  static_cast<double>(kMaxCaptureValues / p.signals.size()) / cycle_hz, p.signals.size());
    return fail(buf);
  }
  if (p.signals.size() > kMaxCaptureSignals) return fail("too many signals");  // unreachable: 12 names, no repeats
  if (const auto tr = params.find("trigger"); tr != params.end() && !tr->is_null()) {
    if (!tr->is_string()) return fail("parameter 'trigger' of capture must be a string such as \"ferr_x>0.005\"");
    std::string why;
    p.trigger = parse_trigger(tr->get<std::string>(), why);
    if (!p.trigger) return fail(why);
  }
  double pre = p.pre_trigger * 100.0;
  if (!number("pre_trigger_percent", pre) || pre < 0.0 || pre >= 100.0) {
    return fail("parameter 'pre_trigger_percent' of capture must be a number in [0, 100) %");
  }
  if (params.contains("pre_trigger_percent") && !p.trigger) {
    return fail("parameter 'pre_trigger_percent' of capture needs a 'trigger' (without one the record starts at once)");
  }
  p.pre_trigger = pre / 100.0;
  if (!number("trigger_timeout_s", p.trigger_timeout_s) || p.trigger_timeout_s <= 0.0 ||
      p.trigger_timeout_s > kMaxTriggerTimeoutS) {
    std::snprintf(buf, sizeof buf, "parameter 'trigger_timeout_s' of capture must be a number in (0, %g] s", kMaxTriggerTimeoutS);
    return fail(buf);
  }
  out.value = std::move(p);
  return out;
}

}  // namespace pcnc
