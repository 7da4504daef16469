// service.hpp — `pcnc-host --serve`: the long-running operator service behind the control
// socket. It keeps pcnc-rt attached (and re-attaches to a new rt after the old one died),
// turns socket requests (rpc.hpp) into mailbox commands, runs programs in a worker thread
// with the JobRunner, keeps continuous jogs alive while their client does, pushes status to
// subscribers, and resumes a program a previous host left in HOST_LOST (job_journal.hpp).
// service.cpp only assembles the parts that do this (host/service/README.md lists them).
//
// Threads: the socket event loop (all request handling), an rt monitor (liveness every few
// ms, attach/re-attach), the job worker (preflight + ring feeding), and RtLink's heartbeat.
// Nothing a client does can block the worker or the rt: the loop never waits on the rt.
//
// May include: control_server.hpp (its limits), shared/config. Callers (host/main.cpp)
// need nothing else.
#pragma once

#include <atomic>
#include <memory>

#include "config/config.hpp"
#include "service/control_server.hpp"

namespace pcnc {

struct ServiceOptions {
  ServerLimits limits{};
  double tick_s = 0.005;             // loop tick: subscriptions, jog deadman, pending replies
  double monitor_period_s = 0.005;   // rt liveness check period
  double attach_retry_s = 0.1;       // how often to look for a (new) rt while none is attached
};

class Service {
 public:
  explicit Service(const MachineConfig& config, ServiceOptions options = {});
  ~Service();
  Service(const Service&) = delete;
  Service& operator=(const Service&) = delete;

  /// Creates the control socket (throws std::runtime_error with the reason), then serves
  /// until `stop` becomes true. A program still running is stopped along the path.
  void run(const std::atomic<bool>& stop);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace pcnc
