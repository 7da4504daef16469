// rt_link.cpp — opening the segment, the heartbeat thread, mailbox and status access.
#include "service/rt_link.hpp"

#include <unistd.h>

#include <chrono>
#include <fstream>
#include <string>

namespace pcnc {

RtLink::RtLink(const MachineConfig& config) : config_(config), segment_(config.process.shm_name) {
  // One host at a time: a second one would mask the first one's loss with its heartbeat.
  if (const int holder = claim_host(shm().header, getpid()); holder != 0) {
    throw SegmentError("pcnc-rt (pid " + std::to_string(shm().header.rt_pid.load()) + ") is already served by pcnc-host pid " +
                       std::to_string(holder) + "; stop that one first");
  }
  shm().header.host_heartbeat_ns.store(monotonic_ns());
  heartbeat_ = std::thread([this] { beat(); });
}

RtLink::~RtLink() {
  {
    std::lock_guard<std::mutex> lock(beat_mutex_);
    stop_ = true;
  }
  beat_wake_.notify_all();  // the heartbeat thread wakes now, not at the end of its period (20 ms)
  if (heartbeat_.joinable()) heartbeat_.join();
  release_host(shm().header, getpid());
}

std::unique_ptr<RtLink> RtLink::attach(const MachineConfig& config, double wait_s) {
  const std::uint64_t deadline = monotonic_ns() + static_cast<std::uint64_t>(wait_s * 1e9);
  for (;;) {
    try {
      auto link = std::make_unique<RtLink>(config);
      // Attached; now wait for the rt's first published status (its first cycle).
      while (link->status().state == MachineState::kStarting) {
        if (monotonic_ns() >= deadline) throw SegmentError("pcnc-rt created its segment but never published a status");
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
      }
      return link;
    } catch (const SegmentError& e) {
      if (!transient_failure(e.what()) || monotonic_ns() >= deadline) throw;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));  // start-up only, not a data path
  }
}

bool RtLink::transient_failure(const std::string& why) {
  // A segment pcnc-rt is creating this very moment: not sized yet ("is empty"), or sized and
  // still zero (magic 0x0) before the rt writes its header.
  return why.find("does not exist") != std::string::npos || why.find("never published") != std::string::npos ||
         why.find("not initialised") != std::string::npos || why.find("is empty") != std::string::npos ||
         why.find("magic is 0x0,") != std::string::npos;
}

void RtLink::beat() {
  // The heartbeat period is a fifth of the rt's timeout, so one late beat never trips it.
  const auto period = std::chrono::duration<double>(config_.process.host_timeout_s / 5.0);
  std::unique_lock<std::mutex> lock(beat_mutex_);
  while (!stop_.load()) {
    shm().header.host_heartbeat_ns.store(monotonic_ns(), std::memory_order_release);
    beat_wake_.wait_for(lock, period, [this] { return stop_.load(); });
  }
}

namespace {
// A process that exists and is not a zombie (a killed rt not yet reaped by its parent still
// answers kill(pid, 0); /proc tells the difference at once).
bool pid_running(int pid) {
  if (pid <= 0 || !process_alive(pid)) return false;
  std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
  std::string text;
  if (!std::getline(stat, text)) return true;  // no /proc: trust kill(pid, 0)
  const auto paren = text.rfind(')');
  return paren == std::string::npos || paren + 2 >= text.size() || (text[paren + 2] != 'Z' && text[paren + 2] != 'X');
}
}  // namespace

std::uint64_t RtLink::send(Command cmd) {
  std::lock_guard<std::mutex> lock(send_mutex_);
  // Ids keep rising across hosts: a host started after another one (a restart of the
  // service) would otherwise number from 1 again, below the rt's last_command_id, and take
  // the rt's status as the answer to commands it has not taken yet (a program "ended" at once).
  const std::uint64_t seen = status().last_command_id;
  if (next_id_.load() <= seen) next_id_.store(seen + 1);
  cmd.id = next_id_.fetch_add(1);
  if (!shm().commands.try_push(cmd)) return 0;
  shm().block_published.notify();
  return cmd.id;
}

Status RtLink::status() const {
  Status s;
  shm().status.load(s);
  return s;
}

double RtLink::rt_heartbeat_age_s() const {
  const std::uint64_t beat = shm().header.rt_heartbeat_ns.load(std::memory_order_acquire);
  const std::uint64_t now = monotonic_ns();
  return now > beat ? static_cast<double>(now - beat) / 1e9 : 0.0;
}

bool RtLink::rt_alive() const {
  const int pid = shm().header.rt_pid.load();
  return pid_running(pid) && rt_heartbeat_age_s() < config_.process.rt_timeout_s;
}

std::string RtLink::rt_loss_reason() const {
  const int pid = shm().header.rt_pid.load();
  if (pid == 0) return "pcnc-rt exited (it released its segment)";
  if (!pid_running(pid)) return "pcnc-rt (pid " + std::to_string(pid) + ") is gone";
  const double age = rt_heartbeat_age_s();
  if (age >= config_.process.rt_timeout_s) {
    return "pcnc-rt (pid " + std::to_string(pid) + ") stopped beating: last cycle " + std::to_string(static_cast<int>(age * 1000)) +
           " ms ago (limit " + std::to_string(static_cast<int>(config_.process.rt_timeout_s * 1000)) + " ms)";
  }
  return "";
}

}  // namespace pcnc
