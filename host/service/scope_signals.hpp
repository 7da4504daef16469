// scope_signals.hpp — what a capture (`capture`, docs/protocol.md) may record and trigger on,
// pure: the signals by the trace's column names (ipc/trace_format.hpp: line, state, cmd_x ..
// ferr_z, speed), their value in a sample, the trigger condition ("ferr_x>0.005",
// "abs(ferr_y)>=2e-3", "line>=20", "state==RUNNING") and the capture's checked parameters,
// with the messages that refuse a bad one.
//
// May include: rpc.hpp, shared/ipc.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "ipc/trace_format.hpp"
#include "service/rpc.hpp"

namespace pcnc {

/// The signals, in the trace's column order (t excluded: every row has it).
const std::vector<std::string>& scope_signal_names();
/// The signal's index in scope_signal_names(), or -1.
int scope_signal_index(std::string_view name);
/// The value of signal `index` in a sample (state: its enum number).
double scope_signal_value(const TraceSample& s, int index);

enum class TriggerOp { kGreater, kLess, kGreaterEqual, kLessEqual, kEqual, kNotEqual };

struct Trigger {
  std::string text;   // as given
  int signal = 0;     // index in scope_signal_names()
  bool absolute = false;  // abs(signal)
  TriggerOp op = TriggerOp::kGreater;
  double level = 0.0;
  bool holds(const TraceSample& s) const;
};

/// Parses "SIGNAL OP NUMBER" (blanks allowed), SIGNAL optionally as abs(SIGNAL), OP one of
/// > < >= <= == !=; for state the level may be a state name. The error says what is wrong.
std::optional<Trigger> parse_trigger(std::string_view text, std::string& error);

struct CaptureParams {
  std::vector<int> signals;       // indices into scope_signal_names(), as asked, no repeats
  double seconds = 0.0;           // record length
  std::optional<Trigger> trigger; // none: the record starts at once
  double pre_trigger = 0.1;       // share of the record before the trigger sample, [0, 1)
  double trigger_timeout_s = 60.0;  // waiting for the trigger longer than this: refused
};

constexpr double kMaxCaptureSeconds = 10.0;
constexpr double kMaxTriggerTimeoutS = 3600.0;
constexpr std::size_t kMaxCaptureSignals = 12;
/// A capture holds at most this many values (cycles x signals), like halscope's sample
/// memory shared by its channels; it keeps the reply under the socket's 1 MiB reply bound.
constexpr std::size_t kMaxCaptureValues = 48000;

/// Checks `capture`'s parameters: signals (array of names), seconds, trigger (string),
/// pre_trigger_percent, trigger_timeout_s. `cycle_hz` sizes the record.
rpc::Checked<CaptureParams> check_capture_params(const rpc::json& params, double cycle_hz);

}  // namespace pcnc
