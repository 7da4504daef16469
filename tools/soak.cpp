// soak.cpp — `pcnc soak`: the fault-injection soak (see soak.hpp, docs/reliability.md).
#include "soak.hpp"

#include <CLI/CLI.hpp>
#include <spdlog/spdlog.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <numbers>
#include <random>
#include <regex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "config/config.hpp"
#include "config/output_path.hpp"
#include "ctl.hpp"
#include "gcode/program.hpp"
#include "geometry/nurbs.hpp"
#include "geometry/plane.hpp"
#include "ipc/block_nurbs.hpp"
#include "ipc/segment.hpp"
#include "launcher.hpp"

#include "soak_parts.hpp"

namespace pcnc::soak {
namespace {

void sleep_s(double s) { std::this_thread::sleep_for(std::chrono::duration<double>(s)); }

// ---- processes ----------------------------------------------------------------------------

pid_t spawn(const std::string& exe, const std::vector<std::string>& args, const std::string& log) {
  const pid_t pid = fork();
  if (pid < 0) return -1;
  if (pid == 0) {
    prctl(PR_SET_PDEATHSIG, SIGTERM);  // a soak that is killed takes its processes with it
    const int fd = open(log.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0600);
    if (fd >= 0) {
      dup2(fd, 1);
      dup2(fd, 2);
    }
    const int devnull = open("/dev/null", O_RDONLY);
    if (devnull >= 0) dup2(devnull, 0);
    std::vector<char*> argv;
    argv.push_back(const_cast<char*>(exe.c_str()));
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    execv(exe.c_str(), argv.data());
    _exit(127);
  }
  return pid;
}

// Signals `pid` and reaps it; SIGKILL after `timeout_s` if it has not ended.
void end_process(pid_t& pid, int sig, double timeout_s) {
  if (pid <= 0) return;
  kill(pid, sig);
  const auto t0 = Clock::now();
  int st = 0;
  while (waitpid(pid, &st, WNOHANG) == 0) {
    if (since(t0) > timeout_s) {
      kill(pid, SIGKILL);
      waitpid(pid, &st, 0);
      break;
    }
    sleep_s(0.005);
  }
  pid = -1;
}

// ---- the socket ---------------------------------------------------------------------------

json call(const std::string& sock, const std::string& method, const json& params = json::object(), double timeout_s = 10.0) {
  try {
    CtlClient c(sock);
    return c.call(method, params, timeout_s);
  } catch (const std::exception& e) {
    return json{{"error", {{"code", -1}, {"message", e.what()}}}};
  }
}
std::string error_text(const json& r) {
  return r.contains("error") ? r["error"].value("message", std::string("error")) : std::string();
}
json status_of(const std::string& sock) {
  json r = call(sock, "status", json::object(), 5.0);
  return r.contains("result") ? r["result"] : json();
}
Vec3 vec_of(const json& j) { return {j["x"].get<double>(), j["y"].get<double>(), j["z"].get<double>()}; }

bool read_segment(const std::string& shm, Status& out) {
  try {
    HostSegment seg(shm);
    seg.shm().status.load(out);
    return true;
  } catch (const std::exception&) {
    return false;
  }
}


}  // namespace

bool Soak::setup() {
  cfg_ = load_config(o_.config_path);
  if (o_.work_dir.empty()) {
    std::string tmpl = (std::getenv("TMPDIR") ? std::string(std::getenv("TMPDIR")) : std::string("/tmp")) + "/pcnc-soak-XXXXXX";
    if (mkdtemp(tmpl.data()) == nullptr) return false;
    dir_ = tmpl;
  } else {
    dir_ = o_.work_dir;
    std::filesystem::create_directories(dir_);
    chmod(dir_.c_str(), 0700);
  }
  // A private copy of the config: own segment and socket, so a soak never meets a service.
  std::ifstream in(o_.config_path);
  std::stringstream text;
  text << in.rdbuf();
  shm_ = "/pcnc-soak-" + std::to_string(getpid());
  sock_ = dir_ + "/pcnc.sock";
  std::string t = text.str();
  t = std::regex_replace(t, std::regex(R"((^|\n)shm_name *=[^\n]*)"), "$1shm_name = \"" + shm_ + "\"");
  // socket and journal in the soak's folder (the shipped configs leave these lines commented:
  // the service then uses its runtime and state directories, shared with a real service)
  t = std::regex_replace(t, std::regex(R"((^|\n)#? *socket_path *=[^\n]*)"), "$1socket_path = \"" + sock_ + "\"");
  t = std::regex_replace(t, std::regex(R"((^|\n)#? *state_dir *=[^\n]*)"), "$1state_dir = \"" + dir_ + "/state\"");
  cfg_file_ = dir_ + "/soak.toml";
  std::ofstream(cfg_file_) << t;
  cfg_ = load_config(cfg_file_);
  const std::string exe_dir = executable_dir();
  rt_exe_ = exe_dir + "/../rt/pcnc-rt";
  host_exe_ = exe_dir + "/../host/pcnc-host";
  if (access((exe_dir + "/pcnc-rt").c_str(), X_OK) == 0) rt_exe_ = exe_dir + "/pcnc-rt";
  if (access((exe_dir + "/pcnc-host").c_str(), X_OK) == 0) host_exe_ = exe_dir + "/pcnc-host";
  return true;
}

bool Soak::wait(const std::function<bool(const json&)>& pred, double timeout_s, json* last) {
  const auto t0 = Clock::now();
  json s;
  do {
    s = status_of(sock_);
    if (s.is_object() && pred(s)) {
      if (last) *last = s;
      return true;
    }
    sleep_s(0.01);
  } while (since(t0) < timeout_s);
  if (last) *last = s;
  return false;
}

bool Soak::start_rt() {
  const std::string trace = dir_ + "/trace-" + std::to_string(trace_index_) + ".csv";
  traces_.push_back(trace);
  rt_ = spawn(rt_exe_, {"--config", cfg_file_, "--clock", "real", "--trace", trace}, dir_ + "/rt.log");
  if (rt_ <= 0) return false;
  Status st{};
  for (int i = 0; i < 2000; ++i) {
    if (read_segment(shm_, st) && st.state != MachineState::kStarting) return true;
    sleep_s(0.005);
  }
  return false;
}

bool Soak::start_host() {
  host_ = spawn(host_exe_, {"--config", cfg_file_, "--serve"}, dir_ + "/host.log");
  if (host_ <= 0) return false;
  return wait([](const json& s) { return s["rt"].is_object() && s["rt"]["state"] == "attached"; }, 15.0);
}

// kill -9 of one of the two processes, reaped at once: the fault's record with the machine
// time at the kill, the rt's last status before it (read from the segment) and the wall
// time of the kill (recovery times count from it).
Fault Soak::kill_process(const char* kind, pid_t& pid, Status& before, Clock::time_point& killed_at) {
  Fault f;
  f.kind = kind;
  f.trace = trace_index_;
  read_segment(shm_, before);
  f.t_kill = before.time_s;
  killed_at = Clock::now();
  kill(pid, SIGKILL);
  int w = 0;
  waitpid(pid, &w, 0);
  pid = -1;
  return f;
}

void Soak::fault_host_kill() {
  Status st{};
  Clock::time_point t0;
  Fault f = kill_process("kill -9 host", host_, st, t0);
  bool lost = false;
  while (since(t0) < 5.0) {
    if (read_segment(shm_, st) && st.state == MachineState::kHostLost) {
      lost = true;
      break;
    }
    if (st.state == MachineState::kIdle && !st.program_active) {  // the program had ended
      ended_under_killed_host_ = st.program_done != 0;
      break;
    }
    sleep_s(0.001);
  }
  if (lost) f.to_lost_ms = 1000.0 * since(t0);
  if (!start_host()) {
    f.note = "a new pcnc-host did not come up";
    failures_.push_back(f.note);
    faults_.push_back(f);
    return;
  }
  if (!lost) {
    f.survived = true;
    f.note = "the program had ended before HOST_LOST";
  } else {
    const json r = call(sock_, "resume", json::object(), 60.0);
    if (r.contains("result")) {
      f.to_resumed_ms = 1000.0 * since(t0);
      f.survived = true;
      if (read_segment(shm_, st)) f.t_back = st.time_s;
    } else {
      f.note = "resume refused: " + error_text(r);
      failures_.push_back("after a host kill: " + f.note);
      call(sock_, "stop");
    }
  }
  char buf[200];
  std::snprintf(buf, sizeof buf, "kill -9 host: HOST_LOST after %.0f ms, resumed after %.0f ms%s%s", f.to_lost_ms,
                f.to_resumed_ms, f.note.empty() ? "" : ": ", f.note.c_str());
  log(buf);
  faults_.push_back(f);
}

void Soak::fault_pause(bool jog) {
  const json p = call(sock_, "pause");
  if (!p.contains("result")) return;  // nothing was moving any more: not a fault injected
  Fault f;
  f.kind = jog ? "jog while paused" : "pause/resume";
  f.trace = trace_index_;
  json s;
  if (!wait([](const json& x) { return x["state"] == "PAUSED" && x["path_speed"].get<double>() == 0.0; }, 10.0, &s)) {
    if (job_over(s)) return;  // the hold met the program's end
    f.note = "no rest after pause (state " + s.value("state", std::string("?")) + ")";
  } else if (jog) {
    const int jogs = 1 + static_cast<int>(uniform(0.0, 2.0));
    for (int k = 0; k < jogs && f.note.empty(); ++k) {
      const int axis = static_cast<int>(uniform(0.0, 3.0)) % 3;
      const double dist = (uniform(0.0, 1.0) < 0.5 ? -1.0 : 1.0) * uniform(0.5, 2.0);
      const json j = call(sock_, "jog", {{"axis", std::string(1, "XYZ"[axis])}, {"distance", dist}, {"feed", 600}});
      if (!j.contains("result")) {
        f.note = "jog refused: " + error_text(j);
        break;
      }
      sleep_s(0.05);
      if (!wait([](const json& x) { return x["state"] == "PAUSED"; }, 20.0, &s)) f.note = "the jog did not end PAUSED";
    }
  } else {
    sleep_s(uniform(0.2, 1.0));
  }
  const json r = call(sock_, "resume");
  if (!r.contains("result") && f.note.empty()) f.note = "resume refused: " + error_text(r);
  f.survived = f.note.empty();
  if (!f.survived) failures_.push_back(f.kind + ": " + f.note);
  log(f.kind + (f.survived ? ": resumed" : ": " + f.note));
  faults_.push_back(f);
}

void Soak::fault_override() {
  const int percent = static_cast<int>(uniform(40.0, 151.0));
  const json r = call(sock_, "override", {{"percent", percent}});
  Fault f;
  f.kind = "feed override";
  f.trace = trace_index_;
  f.survived = r.contains("result");
  if (!f.survived) {
    f.note = error_text(r);
    failures_.push_back("override: " + f.note);
  }
  log("feed override " + std::to_string(percent) + " %");
  faults_.push_back(f);
}

void Soak::fault_rt_kill() {
  Status before{};
  Clock::time_point t0;
  Fault f = kill_process("kill -9 rt", rt_, before, t0);
  json s;
  if (wait([](const json& x) { return x["rt"].is_object() && x["rt"]["state"] != "attached"; }, 5.0, &s)) {
    f.to_lost_ms = 1000.0 * since(t0);
  }
  ++trace_index_;
  if (!start_rt() || !wait([](const json& x) { return x["rt"]["state"] == "attached"; }, 15.0, &s)) {
    f.note = "the service did not re-attach to a new pcnc-rt";
    failures_.push_back(f.note);
  } else {
    f.to_resumed_ms = 1000.0 * since(t0);
    f.survived = true;
    wait([&](const json& x) { return job_over(x); }, 10.0, &s);
    if (s.is_object() && s["actual"].is_object()) f.position_jump_mm = norm(vec_of(s["actual"]) - before.actual);
    f.note = "the program ended (" + (s["last_job"].is_object() ? s["last_job"].value("end", std::string("?")) : std::string("?")) +
             "); the new rt stands " + std::to_string(f.position_jump_mm) + " mm from the last measured position";
  }
  log("kill -9 rt: " + f.note);
  faults_.push_back(f);
  attempt_aborted_ = true;
}

// The rt entered HOST_LOST although the host runs: it missed the host's heartbeat
// (process.host_timeout_s, 100 ms by default) on a loaded machine. Not injected, but a fault
// all the same: the running host resumes, as a new one would.
void Soak::fault_spontaneous_host_lost() {
  Fault f;
  f.kind = "HOST_LOST unasked";
  f.trace = trace_index_;
  Status st{};
  if (read_segment(shm_, st)) f.t_kill = st.time_s;
  const auto t0 = Clock::now();
  const json r = call(sock_, "resume", json::object(), 60.0);
  if (r.contains("result")) {
    f.survived = true;
    f.to_resumed_ms = 1000.0 * since(t0);
    if (read_segment(shm_, st)) f.t_back = st.time_s;
    f.note = "heartbeat missed under load; resumed by the same host";
  } else {
    f.note = "resume refused: " + error_text(r);
    failures_.push_back("after an unasked HOST_LOST: " + f.note);
    call(sock_, "stop");
  }
  log("HOST_LOST without a kill (host heartbeat missed): " + f.note);
  faults_.push_back(f);
}

int Soak::run() {
  if (!setup()) {
    std::fprintf(stderr, "pcnc soak: cannot create a work directory\n");
    return 2;
  }
  std::printf("pcnc soak: %s, %.2f min, seed %llu%s, work dir %s\n", o_.file.c_str(), o_.minutes,
              static_cast<unsigned long long>(o_.seed), o_.kill_rt ? ", with rt kills" : "", dir_.c_str());
  if (!start_rt() || !start_host()) {
    std::fprintf(stderr, "pcnc soak: the processes did not start (logs in %s)\n", dir_.c_str());
    end_process(host_, SIGTERM, 5.0);
    end_process(rt_, SIGTERM, 5.0);
    return 3;
  }
  const double budget_s = o_.minutes * 60.0;
  std::exponential_distribution<double> gap(1.0 / o_.mean_gap_s);
  while (attempts_.empty() || since(t0_) < budget_s) {
    json s;
    if (!wait([](const json& x) { return x["state"] == "IDLE"; }, 15.0, &s)) {
      failures_.push_back("the machine did not come to IDLE between runs");
      break;
    }
    Attempt a;
    a.trace = trace_index_;
    a.t_begin = s["time_s"].get<double>();
    JobOptions jo;
    jo.fit = o_.fit;
    jo.start_position = vec_of(s["commanded"]);
    double acc = 0.0;
    const CheckResult check = check_program(o_.file, cfg_, jo, [&](const Block& b) {
      PathBlock pb;
      pb.b = b;
      pb.s0 = acc;
      pb.len = (b.kind == BlockKind::kRapid || b.kind == BlockKind::kLine || b.kind == BlockKind::kArc ||
                b.kind == BlockKind::kNurbs)
                   ? b.length
                   : 0.0;
      acc += pb.len;
      a.path.push_back(pb);
    });
    if (!check.ok) {
      std::fprintf(stderr, "pcnc soak: %s does not pass preflight (pcnc check it)\n", o_.file.c_str());
      end_process(host_, SIGTERM, 5.0);
      end_process(rt_, SIGTERM, 5.0);
      return 2;
    }
    a.total = acc;
    const json r = call(sock_, "run", {{"file", std::filesystem::absolute(o_.file).string()}, {"fit", o_.fit}}, 120.0);
    if (!r.contains("result")) {
      failures_.push_back("run refused: " + error_text(r));
      break;
    }
    log("run " + std::to_string(attempts_.size() + 1) + " started (" + std::to_string(a.path.size()) + " blocks, " +
        std::to_string(a.total) + " mm)");
    attempt_aborted_ = false;
    ended_under_killed_host_ = false;
    const auto started = Clock::now();
    while (true) {
      const double next = std::max(0.3, gap(rng_));
      const auto t_next = Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(next));
      bool over = false;
      while (Clock::now() < t_next) {
        s = status_of(sock_);
        if (job_over(s)) {
          over = true;
          break;
        }
        if (s.is_object() && s["state"] == "PAUSED" && s["path_speed"].get<double>() == 0.0) call(sock_, "resume");  // M00/M01
        sleep_s(0.05);
      }
      if (over) break;
      if (since(started) > 1800.0) {
        failures_.push_back("a run did not end within 30 minutes");
        break;
      }
      if (s.is_object() && s["state"] == "HOST_LOST") {
        fault_spontaneous_host_lost();
        continue;
      }
      if (s.is_object() && (s["state"] == "FAULT" || s["state"] == "ESTOP")) {
        failures_.push_back("the machine went to " + s["state"].get<std::string>());
        break;
      }
      if (!s.is_object() || s["state"] != "RUNNING") continue;
      const double pick = uniform(0.0, 1.0);
      // rt kills (long form) in every second run, at most one per run, so that the runs in
      // between complete with every other fault.
      if (o_.kill_rt && attempts_.size() % 2 == 1 && pick < 0.15) {
        fault_rt_kill();
      } else if (pick < 0.35) {
        fault_host_kill();
      } else if (pick < 0.6) {
        fault_pause(false);
      } else if (pick < 0.8) {
        fault_override();
      } else {
        fault_pause(true);
      }
      if (attempt_aborted_) break;
    }
    s = status_of(sock_);
    a.aborted = attempt_aborted_;
    if (!a.aborted && s.is_object()) {
      a.t_end = s["time_s"].get<double>();
      if (s["last_job"].is_object()) {
        a.end = s["last_job"].value("end", std::string("?"));
        a.program_time_s = s["last_job"].value("program_time_s", 0.0);
      } else if (ended_under_killed_host_) {
        a.end = "completed";  // the rt reached the End block; the host that ran it was killed after
        log("run " + std::to_string(attempts_.size() + 1) +
            ": the host was killed after the program's end; the rt's status says it completed");
      }
      if (a.end != "completed") failures_.push_back("run " + std::to_string(attempts_.size() + 1) + " ended " + a.end);
    } else {
      a.end = "pcnc-rt killed";
    }
    log("run " + std::to_string(attempts_.size() + 1) + " ended: " + a.end);
    attempts_.push_back(std::move(a));
  }
  call(sock_, "override", {{"percent", 100}});
  end_process(host_, SIGTERM, 5.0);
  end_process(rt_, SIGTERM, 10.0);  // the rt flushes its trace
  remove_segment(shm_);
  const int rc = analyse();
  if (!o_.keep && rc == 0) {
    std::error_code ec;
    std::filesystem::remove_all(dir_, ec);
  } else {
    std::printf("files kept in %s\n", dir_.c_str());
  }
  return rc;
}


}  // namespace pcnc::soak

namespace pcnc {

using soak::Options;
using soak::Soak;
using Clock = soak::Clock;


void add_soak_subcommand(CLI::App& app, int& exit_code) {
  auto opts = std::make_shared<Options>();
  opts->config_path = default_config_path();
  auto* cmd = app.add_subcommand("soak",
                                 "fault-injection soak: run FILE on both processes at real clock while killing and "
                                 "restarting them, pausing, jogging and changing the override; check the trace");
  cmd->add_option("FILE", opts->file, "G-code program (run with --fit by default)")->required()->check(CLI::ExistingFile);
  cmd->add_option("--config", opts->config_path, "machine configuration (TOML)")->capture_default_str();
  cmd->add_option("--minutes", opts->minutes, "keep running the program (and injecting faults) this long; the last run "
                                              "is finished")->capture_default_str();
  cmd->add_option("--mean-gap", opts->mean_gap_s, "mean seconds between faults (exponential)")->capture_default_str();
  cmd->add_option("--seed", opts->seed, "random seed (default: from the clock; always printed)");
  cmd->add_flag("--kill-rt", opts->kill_rt, "also kill -9 pcnc-rt and restart it (the long form)");
  cmd->add_flag("!--no-fit", opts->fit, "run the program as it is (default: --fit)");
  cmd->add_option("--tolerance", opts->path_tol_mm, "how far a setpoint may lie from the program's path, mm")->capture_default_str();
  cmd->add_option("--work-dir", opts->work_dir, "keep config, logs and traces here (default: a fresh temporary directory, "
                                                "removed when every invariant held)");
  cmd->add_flag("--keep", opts->keep, "keep the work directory");
  cmd->add_option("--summary", opts->summary, "also write the figures as JSON");
  cmd->callback([opts, cmd, &exit_code] {
    if (cmd->count("--seed") == 0) opts->seed = static_cast<std::uint64_t>(Clock::now().time_since_epoch().count()) % 1000000007ULL;
    if (!(opts->mean_gap_s > 0.0) || !(opts->minutes >= 0.0)) {
      std::fprintf(stderr, "pcnc soak: --mean-gap must be > 0 and --minutes >= 0\n");
      exit_code = 2;
      return;
    }
    try {
      check_output_paths({{opts->summary, "--summary"}});
    } catch (const std::exception& e) {
      std::fprintf(stderr, "pcnc soak: %s\n", e.what());
      exit_code = 2;
      return;
    }
    signal(SIGPIPE, SIG_IGN);
    spdlog::set_level(spdlog::level::err);  // the program's preflight warnings are check's business
    try {
      Soak soak(*opts);
      exit_code = soak.run();
    } catch (const std::exception& e) {
      std::fprintf(stderr, "pcnc soak: %s\n", e.what());
      exit_code = 2;
    }
  });
}

}  // namespace pcnc

