// service_procs.cpp — real pcnc-rt + pcnc-host --serve pairs for the socket tests.
#include "service_procs.hpp"

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <fstream>
#include <sstream>
#include <thread>

#include "ipc/segment.hpp"
#include "service/rpc.hpp"
#include "test_paths.hpp"

namespace pcnc::test {

std::string rt_exe() { return bin_dir() + "/rt/pcnc-rt"; }
std::string host_exe() { return bin_dir() + "/host/pcnc-host"; }
std::string pcnc_exe() { return bin_dir() + "/tools/pcnc"; }

MachineConfig mill_config() { return load_config(default_config()); }

double pos(const json& status, const char* which, int axis) {
  return status[which][std::string(1, "xyz"[axis])].get<double>();
}
int error_code(const json& reply) { return reply.contains("error") ? reply["error"]["code"].get<int>() : 0; }
std::string error_message(const json& reply) {
  return reply.contains("error") ? reply["error"]["message"].get<std::string>() : "";
}
bool idle(const json& status) { return status["state"] == "IDLE" && !status["job"]["active"].get<bool>(); }
bool idle_after_job(const json& status) { return idle(status) && status["last_job"].is_object(); }

ProcessResult ServicePair::ctl(const std::vector<std::string>& args, double timeout_s) const {
  std::vector<std::string> argv = {pcnc_exe(), "ctl", "--config", config_};
  argv.insert(argv.end(), args.begin(), args.end());
  return run_process(argv, timeout_s);
}

ServicePair::ServicePair(const std::string& tag, const std::vector<std::pair<std::string, std::string>>& replacements)
    : tag_(tag), dir_(make_temp_dir(tag)) {
  config_ = write_test_config(dir_, tag, replacements);
  socket_ = dir_ + "/pcnc.sock";
}

namespace {
void stop_process(BackgroundProcess& p) {
  if (p.pid <= 0) return;
  kill(p.pid, SIGTERM);
  if (p.wait(10.0) < 0) {
    kill(p.pid, SIGKILL);
    p.wait(5.0);
  }
  p.pid = -1;
}
}  // namespace

ServicePair::~ServicePair() {
  stop_process(host_);
  stop_process(rt_);
  remove_segment(test_shm_name(tag_));
}

void ServicePair::start_rt(const std::string& clock, const std::vector<std::string>& extra) {
  std::vector<std::string> argv = {rt_exe(), "--config", config_, "--clock", clock};
  argv.insert(argv.end(), extra.begin(), extra.end());
  rt_ = start_process(argv, dir_ + "/rt" + std::to_string(++rt_starts_));
}

bool ServicePair::start_host(double timeout_s) {
  host_ = start_process({host_exe(), "--config", config_, "--serve"}, dir_ + "/host" + std::to_string(++host_starts_));
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  while (std::chrono::steady_clock::now() < deadline) {
    try {
      CtlClient c(socket_);
      return true;
    } catch (const std::exception&) {
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return false;
}

bool ServicePair::start(const std::string& clock, const std::vector<std::string>& rt_extra) {
  start_rt(clock, rt_extra);
  if (!start_host()) return false;
  const json s = wait_status([](const json& s) { return s["rt"]["state"] == "attached" && s["state"] == "IDLE"; }, 20.0);
  return s["rt"]["state"] == "attached" && s["state"] == "IDLE";
}

json ServicePair::call(const std::string& method, const json& params, double timeout_s) {
  CtlClient c(socket_);
  return c.call(method, params, timeout_s);
}

json ServicePair::status() {
  const json r = call("status");
  if (!r.contains("result")) throw std::runtime_error("status failed: " + r.dump());
  return r["result"];
}

json ServicePair::wait_status(const std::function<bool(const json&)>& pred, double timeout_s) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  // While pcnc-rt's heartbeat is stale (a loaded machine, or the rt gone) the status has no
  // machine fields (state NO_RT). A predicate that reads one, `x["blocks_done"]` on a const json,
  // would look up a key that is not there: an assertion in a debug build (the ASan suite once
  // aborted on it), undefined behaviour without one. Such fields are null here instead, so the
  // predicate's get<>() throws (taken as "not yet") or its comparison is false.
  static const json machine_fields = rpc::status_to_json(Status{});
  json s;
  for (;;) {
    try {
      s = status();
      for (const auto& field : machine_fields.items())
        if (!s.contains(field.key())) s[field.key()] = nullptr;
      if (pred(s)) return s;
    } catch (const std::exception&) {
    }
    if (std::chrono::steady_clock::now() >= deadline) return s;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
}

void ServicePair::kill_rt(int sig) {
  kill(rt_.pid, sig);
  rt_.wait(10.0);
  rt_.pid = -1;
}

void ServicePair::kill_host(int sig) {
  kill(host_.pid, sig);
  host_.wait(10.0);
  host_.pid = -1;
}

std::string write_program(const std::string& dir, const std::string& name, const std::string& text) {
  const std::string path = dir + "/" + name;
  std::ofstream(path) << text;
  return path;
}

bool read_rt_status(const std::string& tag, Status& out) {
  try {
    HostSegment seg(test_shm_name(tag));
    return seg.shm().status.load(out, 1 << 16);
  } catch (const SegmentError&) {
    return false;
  }
}

KillAndResume kill_host_and_resume(ServicePair& p) {
  KillAndResume k;
  p.kill_host(SIGKILL);
  k.lost = wait_rt_state(p.tag(), MachineState::kHostLost);
  if (k.lost.state != MachineState::kHostLost) return k.error = std::string("the rt is ") + to_string(k.lost.state), k;
  if (!p.start_host()) return k.error = "the new host did not start: " + p.host_log(), k;
  const json s = p.wait_status([](const json& x) { return x["rt"]["state"] == "attached"; }, 10);
  if (s["state"] != "HOST_LOST") return k.error = "the new host sees " + s.dump(), k;
  k.reply = p.call("resume", json::object(), 60);
  if (!k.reply.contains("result") || !k.reply["result"].value("resumed", false))
    return k.error = "resume: " + k.reply.dump() + " " + p.host_log(), k;
  for (int i = 0; i < 3; ++i) {
    if (k.reply["result"]["from"][std::string(1, "xyz"[i])].get<double>() != k.lost.commanded[static_cast<std::size_t>(i)])
      return k.error = "resumed from another point than the held one: " + k.reply.dump(), k;
  }
  k.final = p.wait_status(
      [](const json& x) { return x["state"] == "IDLE" && !x["job"]["active"].get<bool>() && x["last_job"].is_object(); }, 180);
  if (!k.final["last_job"].is_object() || k.final["last_job"]["end"] != "completed")
    return k.error = "the resumed job did not complete: " + k.final.dump(), k;
  return k;
}

Status wait_rt_state(const std::string& tag, MachineState state, double timeout_s) {
  Status st{};
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  while (!(read_rt_status(tag, st) && st.state == state) && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return st;
}

std::string loop_program(const std::string& dir, const std::string& name, int iterations) {
  return write_program(dir, name,
                       "G21 G90 G17\nG0 X0 Y0 Z-0.5\nG1 Z-1 F600\n#1=0\no100 while [#1 LT " + std::to_string(iterations) +
                           "]\nG1 X[[#1 MOD 20]*0.1] Y[[#1 MOD 7]*0.1]\n#1=[#1+1]\no100 endwhile\nG0 Z-0.5\nM2\n");
}

std::string zigzag_program(const std::string& dir, int rows, double width, double feed) {
  std::ostringstream p;
  p << "G21 G90 G17 G54\nG00 Z-1\nG00 X" << -width / 2 << " Y-8\n";
  const double step = rows > 1 ? 16.0 / (rows - 1) : 0.0;
  for (int i = 0; i < rows; ++i) {
    p << "G01 X" << (i % 2 == 0 ? width / 2 : -width / 2) << " F" << feed << "\n";
    if (i + 1 < rows) p << "G01 Y" << -8.0 + step * (i + 1) << "\n";
  }
  p << "G01 X0 Y0\nM30\n";
  return write_program(dir, "zigzag.ngc", p.str());
}

}  // namespace pcnc::test
