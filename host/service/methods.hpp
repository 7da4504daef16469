// methods.hpp — the protocol's methods (docs/protocol.md) as rows of the dispatch table: for
// each, its parameter check and its handler. Handlers that only send the rt a mailbox command
// (pause, resume from PAUSED, stop, estop, reset, override, jog_stop) and those that change
// the service's own state (set_offset, subscribe) are written here; run, resume after a lost
// host and jog hand over to the job control and the jog control. The status object, which
// gathers what every part knows, is built here too.
//
// May include: dispatch.hpp and the service's parts (rt_monitor, job_control, jog_control,
// subscriptions, work_store, capture_control), rpc.hpp, shared/.
#pragma once

#include <vector>

#include "config/config.hpp"
#include "service/capture_control.hpp"
#include "service/dispatch.hpp"
#include "service/job_control.hpp"
#include "service/jog_control.hpp"
#include "service/rt_monitor.hpp"
#include "service/subscriptions.hpp"
#include "service/work_store.hpp"

namespace pcnc {

/// The service's parts, as the handlers see them (loop thread).
struct ServiceParts {
  const MachineConfig& config;  // the service's copy (its gcode.g54..g59 are only the work state's defaults)
  WorkStore& work;              // the work-coordinate state: set_offset changes and saves it
  const RtMonitor& rt;
  JobControl& jobs;
  JogControl& jogs;
  Subscriptions& subs;
  CaptureControl* captures = nullptr;  // the scope (capture); null: capture is refused
};

/// One row per method of rpc::method_names(), in that order.
std::vector<Method> method_table(ServiceParts parts);

/// The `status` result (also pushed to subscribers): the rt's status (or state NO_RT), the
/// rt link, the job and the last job, the work-coordinate state, jog, and what `resume` would
/// continue.
rpc::json status_object(const ServiceParts& parts);

}  // namespace pcnc
