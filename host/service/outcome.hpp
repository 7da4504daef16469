// outcome.hpp — what a request handler gives back: a result, an error, or "the reply comes
// later" (a run whose reply waits for the program to start, a jog whose reply waits for the
// rt to take it). The dispatcher (dispatch.hpp) turns an outcome into the reply line; the
// parts that answer later (job_control, jog_control) hand theirs to a reply callback.
//
// May include: rpc.hpp only (pure protocol values).
#pragma once

#include <optional>
#include <string>
#include <utility>

#include "service/rpc.hpp"

namespace pcnc {

struct Outcome {
  std::optional<rpc::json> result;
  std::optional<rpc::Error> error;
  static Outcome ok(rpc::json j) { return Outcome{std::move(j), std::nullopt}; }
  static Outcome fail(rpc::Error e) { return Outcome{std::nullopt, std::move(e)}; }
  static Outcome later() { return Outcome{}; }
  bool is_later() const { return !result && !error; }
};

/// Not allowed in the machine's current state; the message says why.
inline rpc::Error refused(std::string message) { return rpc::Error{rpc::kRefused, std::move(message), nullptr}; }

inline rpc::Error mailbox_full() {
  return rpc::Error{rpc::kMailboxFull, "pcnc-rt's command mailbox is full; try again", nullptr};
}

/// The reply line for an outcome ('\n'-terminated), or "" when the reply comes later.
inline std::string format_outcome(const rpc::json& id, const Outcome& o) {
  if (o.error) return rpc::format_error(id, *o.error);
  if (o.result) return rpc::format_result(id, *o.result);
  return {};
}

}  // namespace pcnc
