// dispatch.cpp — from a request line to its reply through the method table (see dispatch.hpp).
#include "service/dispatch.hpp"

#include <algorithm>
#include <stdexcept>

namespace pcnc {

Dispatcher::Dispatcher(std::vector<Method> methods, const RtMonitor& rt) : methods_(std::move(methods)), rt_(rt) {
  const auto& names = rpc::method_names();
  for (const auto& name : names) {
    const auto n = std::count_if(methods_.begin(), methods_.end(), [&](const Method& m) { return m.name == name; });
    if (n != 1) throw std::logic_error("the method table has " + std::to_string(n) + " rows for '" + name + "'");
  }
  if (methods_.size() != names.size()) throw std::logic_error("the method table has methods the protocol does not list");
}

std::string Dispatcher::handle(ClientId client, std::string_view line) {
  // No client input may end the host: whatever throws while a request is parsed, checked,
  // handled or its reply formatted becomes an internal-error reply to that request alone.
  rpc::json id = nullptr;
  try {
    rpc::ParsedRequest parsed = rpc::parse_request(line);
    id = parsed.request.id;
    if (parsed.error) return rpc::format_error(id, *parsed.error);
    return format_outcome(id, dispatch(client, parsed.request));
  } catch (const std::exception& e) {
    return rpc::format_error(id, rpc::Error{rpc::kInternalError, std::string("internal error: ") + e.what(), nullptr});
  } catch (...) {
    return rpc::format_error(id, rpc::Error{rpc::kInternalError, "internal error", nullptr});
  }
}

bool Dispatcher::always_answered(std::string_view line) {
  try {
    const rpc::ParsedRequest parsed = rpc::parse_request(line);
    if (parsed.error) return false;
    const std::string& m = parsed.request.method;
    return m == "stop" || m == "estop" || m == "status";
  } catch (...) {
    return false;
  }
}

Outcome Dispatcher::dispatch(ClientId client, const rpc::Request& req) {
  auto m = std::find_if(methods_.begin(), methods_.end(), [&](const Method& row) { return row.name == req.method; });
  if (m == methods_.end()) {
    return Outcome::fail(rpc::Error{rpc::kMethodNotFound, "unknown method '" + req.method + "'", nullptr});
  }
  if (!m->takes_params) {
    if (auto e = rpc::check_no_params(m->name, req.params)) return Outcome::fail(*e);
  }
  Call call{client, req.id, req.params, nullptr, Status{}};
  if (m->needs_rt) {
    std::string why;
    call.link = rt_.alive(&why);
    if (!call.link) return Outcome::fail(rpc::Error{rpc::kRtUnavailable, why, nullptr});
    call.status = call.link->status();
  }
  return m->handler(call);
}

}  // namespace pcnc
