// dispatch.hpp — request dispatch: one request line in, its reply out, through a table of
// methods. Each row names a method and says whether it takes parameters and whether it
// needs a live pcnc-rt; its handler checks the parameters into their typed value (rpc.hpp)
// and acts. The dispatcher checks, in this order: the line parses as a request of a known
// method (rpc::parse_request), a method without parameters got none, the rt is attached and
// alive when the method needs it (the handler then gets the link and the rt's status taken
// once for the whole request); then it calls the handler and turns what it returns, or any
// exception it throws, into the reply.
//
// This is the one place every request passes through: limits on requests (rates, which
// methods are always answered) belong here, limits on connections in control_server.hpp.
//
// Loop thread only. May include: outcome.hpp, rpc.hpp, rt_monitor.hpp, control_server.hpp.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "service/control_server.hpp"
#include "service/outcome.hpp"
#include "service/rt_monitor.hpp"

namespace pcnc {

/// One request, as a handler sees it.
struct Call {
  ClientId client = 0;
  const rpc::json& id;
  const rpc::json& params;
  std::shared_ptr<RtLink> link;  // methods that need the rt: the live link (else null)
  Status status{};               // methods that need the rt: its status when the request came
};

struct Method {
  std::string name;
  bool takes_params = false;  // false: params must be absent, null or {} (rpc::check_no_params)
  bool needs_rt = false;      // true: refused with kRtUnavailable while no live pcnc-rt is attached
  std::function<Outcome(Call&)> handler;
};

/// A handler that first checks the parameters with `check` (one of rpc::check_*_params) and
/// then calls `body(call, typed_params)`; a check that fails is the reply.
template <typename Check, typename Body>
std::function<Outcome(Call&)> with_params(Check check, Body body) {
  return [check = std::move(check), body = std::move(body)](Call& call) -> Outcome {
    auto p = check(call.params);
    if (!p.ok()) return Outcome::fail(p.error);
    return body(call, *p.value);
  };
}

class Dispatcher {
 public:
  /// `methods` must name exactly the protocol's methods (rpc::method_names()); throws
  /// std::logic_error otherwise.
  Dispatcher(std::vector<Method> methods, const RtMonitor& rt);

  /// Handles one request line (without its '\n'); returns the reply line, or "" when the
  /// reply comes later (the handler has arranged for it).
  std::string handle(ClientId client, std::string_view line);

  /// The line is a request that is answered even when the connection table is full: stop,
  /// estop or status (a line that does not parse is not).
  static bool always_answered(std::string_view line);

 private:
  Outcome dispatch(ClientId client, const rpc::Request& req);
  std::vector<Method> methods_;
  const RtMonitor& rt_;
};

}  // namespace pcnc
