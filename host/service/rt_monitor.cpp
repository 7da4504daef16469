// rt_monitor.cpp — attaching to pcnc-rt, noticing its loss, re-attaching (see rt_monitor.hpp).
#include "service/rt_monitor.hpp"

#include <spdlog/spdlog.h>

#include <chrono>

namespace pcnc {

namespace {
std::chrono::steady_clock::duration seconds(double s) {
  return std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(s));
}
}  // namespace

RtMonitor::RtMonitor(const MachineConfig& config, double period_s, double attach_retry_s, RtMonitorEvents events)
    : config_(config), period_s_(period_s), attach_retry_s_(attach_retry_s), events_(std::move(events)) {}

RtMonitor::~RtMonitor() {
  stop();
  release();
}

void RtMonitor::start() {
  stop_ = false;
  thread_ = std::thread([this] { loop(); });
}

void RtMonitor::stop() {
  stop_ = true;
  if (thread_.joinable()) thread_.join();
}

void RtMonitor::release() {
  std::lock_guard<std::mutex> lock(mutex_);
  link_.reset();
}

std::shared_ptr<RtLink> RtMonitor::current() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return link_;
}

std::shared_ptr<RtLink> RtMonitor::alive(std::string* why) const {
  auto l = current();
  if (l && l->rt_alive()) return l;
  std::lock_guard<std::mutex> lock(mutex_);
  if (why) *why = "pcnc-rt is not available (" + state_.state + "): " + state_.message;
  return nullptr;
}

RtLinkState RtMonitor::state() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return state_;
}

void RtMonitor::loop() {
  auto next_attach = std::chrono::steady_clock::now();
  std::string last_problem;
  while (!stop_.load()) {
    // The monitor's thread must not end the host: a turn that throws is logged and the next
    // one tries again (an exception escaping a thread would call std::terminate).
    try {
      turn(next_attach, last_problem);
    } catch (const std::exception& e) {
      spdlog::error("rt monitor: {}", e.what());
    } catch (...) {
      spdlog::error("rt monitor: unknown exception");
    }
    std::this_thread::sleep_for(std::chrono::duration<double>(period_s_));
  }
}

void RtMonitor::turn(std::chrono::steady_clock::time_point& next_attach, std::string& last_problem) {
  {
    std::shared_ptr<RtLink> l = current();
    if (l) {
      if (!l->rt_alive()) {
        std::string why = l->rt_loss_reason();
        if (why.empty()) why = "pcnc-rt stopped responding";
        const double age_ms = l->rt_heartbeat_age_s() * 1000.0;
        {
          std::lock_guard<std::mutex> lock(mutex_);
          link_.reset();
          state_.state = "lost";
          state_.message = why;
        }
        spdlog::error("pcnc-rt lost: {} (last heartbeat {:.1f} ms ago); motion commands are refused until a new "
                      "pcnc-rt starts",
                      why, age_ms);
        if (events_.lost) events_.lost(why, age_ms);
        next_attach = std::chrono::steady_clock::now() + seconds(attach_retry_s_);
      }
    } else if (std::chrono::steady_clock::now() >= next_attach) {
      next_attach = std::chrono::steady_clock::now() + seconds(attach_retry_s_);
      try_attach(last_problem);
    }
  }
}

void RtMonitor::try_attach(std::string& last_problem) {
  try {
    std::shared_ptr<RtLink> nl = RtLink::attach(config_, 0.0);
    if (!nl->rt_alive()) {
      const std::string why = "found a segment left by a pcnc-rt that is gone (" + nl->rt_loss_reason() + "); waiting for a new pcnc-rt";
      if (why != last_problem) spdlog::info("{}", why);
      last_problem = why;
      std::lock_guard<std::mutex> lock(mutex_);
      state_.message = why;
      return;
    }
    const Status st = nl->status();
    const int pid = nl->rt_pid();
    {
      std::lock_guard<std::mutex> lock(mutex_);
      link_ = nl;
      state_ = RtLinkState{"attached", "", pid};
    }
    last_problem.clear();
    spdlog::info("attached to pcnc-rt pid {} (machine {}, {} clock)", pid, to_string(st.state), st.clock_virtual ? "virtual" : "real");
    if (st.state == MachineState::kHostLost) {
      spdlog::warn("the machine is HOST_LOST: a previous pcnc-host was lost while a program ran; 'resume' continues it, "
                   "'stop' abandons it");
    }
    if (events_.attached) events_.attached(pid, st);
  } catch (const std::exception& e) {
    const std::string why = e.what();
    const bool transient = RtLink::transient_failure(why);
    if (why != last_problem) {
      if (transient) {
        spdlog::info("waiting for pcnc-rt: {}", why);
      } else {
        spdlog::error("refusing pcnc-rt's segment: {}", why);
      }
    }
    last_problem = why;
    std::lock_guard<std::mutex> lock(mutex_);
    if (!transient) {
      state_.state = "refused";
    } else if (state_.state == "refused" || state_.state == "attached") {
      state_.state = "waiting";
    }
    state_.message = why;
  }
}

}  // namespace pcnc
