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
#include "ctl.hpp"
#include "gcode/program.hpp"
#include "geometry/nurbs.hpp"
#include "geometry/plane.hpp"
#include "ipc/block_nurbs.hpp"
#include "ipc/segment.hpp"
#include "launcher.hpp"

namespace pcnc {
namespace {

using json = nlohmann::json;
using Clock = std::chrono::steady_clock;

double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }
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

// ---- the path of a program ------------------------------------------------------------------

struct PathBlock {
  Block b;
  double s0 = 0.0;  // arc length of the program before this block
  double len = 0.0;
};

// Where p lies on block b: arc length s from the block's start and the distance d from the
// nearest point of the block's path. `hint` picks the turn of a multi-turn flat arc.
void locate(const Block& b, const Vec3& p, double hint, double& s, double& d) {
  switch (b.kind) {
    case BlockKind::kRapid:
    case BlockKind::kLine: {
      const Vec3 v = b.end - b.start;
      const double len = norm(v);
      const double t = len > 0.0 ? std::clamp(dot(p - b.start, v) / (len * len), 0.0, 1.0) : 0.0;
      s = t * len;
      d = norm(b.start + t * v - p);
      return;
    }
    case BlockKind::kArc: {
      const ArcGeometry& g = b.arc;
      const auto pa = plane_axes(g.normal_axis);
      const int a0 = pa[0], a1 = pa[1], an = g.normal_axis;
      const double two_pi = 2.0 * std::numbers::pi;
      const double sw = std::abs(g.sweep);
      const double th = std::atan2(p[a1] - g.center[a1], p[a0] - g.center[a0]);
      double tr0 = std::remainder((th - g.start_angle) * (g.sweep < 0.0 ? -1.0 : 1.0), two_pi);
      if (tr0 < 0.0) tr0 += two_pi;
      const double r1 = std::hypot(b.end[a0] - g.center[a0], b.end[a1] - g.center[a1]);
      d = 1e300;
      for (int k = -1; k <= static_cast<int>(sw / two_pi) + 1; ++k) {
        const double u = std::clamp((tr0 + two_pi * k) / sw, 0.0, 1.0);
        const double theta = g.start_angle + g.sweep * u;
        const double r = g.radius + (r1 - g.radius) * u;
        Vec3 e = b.start;
        e[a0] = g.center[a0] + r * std::cos(theta);
        e[a1] = g.center[a1] + r * std::sin(theta);
        e[an] = b.start[an] + g.helix * u;
        const double dk = norm(e - p);
        const double sk = u * b.length;
        if (dk < d - 1e-9 || (std::abs(dk - d) <= 1e-9 && std::abs(sk - hint) < std::abs(s - hint))) {
          d = dk;
          s = sk;
        }
      }
      return;
    }
    case BlockKind::kNurbs: {
      const NurbsView v = view_of(b.nurbs);
      const double u = nurbs_project(v, p, &d, 8);
      s = nurbs_arc_length(v, v.u_min(), u);
      return;
    }
    default:
      s = 0.0;
      d = norm(p - b.end);
      return;
  }
}

// ---- the trace --------------------------------------------------------------------------------

struct Row {
  double t = 0.0;
  std::uint32_t line = 0;
  std::string state;
  Vec3 cmd{}, ferr{};
};

std::vector<Row> read_trace(const std::string& path) {
  std::vector<Row> rows;
  std::ifstream in(path);
  std::string line;
  if (!std::getline(in, line)) return rows;
  while (std::getline(in, line)) {
    std::stringstream ss(line);
    std::string f[13];
    int n = 0;
    while (n < 13 && std::getline(ss, f[n], ',')) ++n;
    if (n < 13) continue;  // a line cut by a killed rt
    try {
      Row r;
      r.t = std::stod(f[0]);
      r.line = static_cast<std::uint32_t>(std::stoul(f[1]));
      r.state = f[2];
      for (int i = 0; i < 3; ++i) {
        r.cmd[i] = std::stod(f[3 + i]);
        r.ferr[i] = std::stod(f[9 + i]);
      }
      rows.push_back(r);
    } catch (const std::exception&) {
    }
  }
  return rows;
}

double max_abs(const Vec3& v) { return std::max({std::abs(v[0]), std::abs(v[1]), std::abs(v[2])}); }

// ---- the soak -----------------------------------------------------------------------------------

struct Options {
  std::string file, config_path, work_dir, summary;
  double minutes = 1.0;
  double mean_gap_s = 4.0;
  std::uint64_t seed = 0;
  bool seed_given = false;
  bool kill_rt = false;
  bool fit = true;
  bool keep = false;
  double path_tol_mm = 0.002;
};

struct Attempt {
  int trace = 0;
  double t_begin = 0.0, t_end = 1e300;
  std::vector<PathBlock> path;
  double total = 0.0;
  std::string end = "?";
  bool aborted = false;  // ended by an rt kill
  double program_time_s = 0.0;
};

struct Fault {
  std::string kind;
  bool survived = false;
  std::string note;
  int trace = 0;
  double t_kill = 0.0, t_back = 0.0;  // machine time (trace's t) at the kill and at recovery
  double to_lost_ms = -1.0, to_resumed_ms = -1.0;
  double max_ferr_mm = 0.0;
  double position_jump_mm = -1.0;  // rt kill: restarted rt's position vs the last measured
};

class Soak {
 public:
  explicit Soak(Options o) : o_(std::move(o)), rng_(o_.seed) {}
  int run();

 private:
  bool setup();
  bool start_rt();
  bool start_host();
  bool wait(const std::function<bool(const json&)>& pred, double timeout_s, json* last = nullptr);
  bool job_over(const json& s) const {
    return s.is_object() && s["state"] == "IDLE" && s["job"].is_object() && !s["job"].value("active", false);
  }
  double uniform(double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng_); }
  void log(const std::string& text) { std::printf("[%7.1f s] %s\n", since(t0_), text.c_str()); std::fflush(stdout); }

  // faults; each returns false when the attempt ends with it (an rt kill)
  void fault_host_kill();
  void fault_pause(bool jog);
  void fault_override();
  void fault_rt_kill();
  void fault_spontaneous_host_lost();

  int analyse();

  Options o_;
  std::mt19937_64 rng_;
  MachineConfig cfg_;
  std::string dir_, cfg_file_, sock_, shm_, rt_exe_, host_exe_;
  pid_t rt_ = -1, host_ = -1;
  int trace_index_ = 0;
  std::vector<std::string> traces_;
  std::vector<Attempt> attempts_;
  std::vector<Fault> faults_;
  std::vector<std::string> failures_;
  Clock::time_point t0_ = Clock::now();
  bool attempt_aborted_ = false;
};

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

void Soak::fault_host_kill() {
  Fault f;
  f.kind = "kill -9 host";
  f.trace = trace_index_;
  Status st{};
  read_segment(shm_, st);
  f.t_kill = st.time_s;
  const auto t0 = Clock::now();
  kill(host_, SIGKILL);
  int w = 0;
  waitpid(host_, &w, 0);
  host_ = -1;
  bool lost = false;
  while (since(t0) < 5.0) {
    if (read_segment(shm_, st) && st.state == MachineState::kHostLost) {
      lost = true;
      break;
    }
    if (st.state == MachineState::kIdle && !st.program_active) break;  // the program had ended
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
  Fault f;
  f.kind = "kill -9 rt";
  f.trace = trace_index_;
  Status before{};
  read_segment(shm_, before);
  f.t_kill = before.time_s;
  const auto t0 = Clock::now();
  kill(rt_, SIGKILL);
  int w = 0;
  waitpid(rt_, &w, 0);
  rt_ = -1;
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

int Soak::analyse() {
  const double dt = cfg_.cycle_period_s();
  const double tol = o_.path_tol_mm;
  double vmax_path = 0.0;
  for (int i = 0; i < 3; ++i) vmax_path += cfg_.axes[i].max_velocity_mm_s * cfg_.axes[i].max_velocity_mm_s;
  const double step_bound = std::sqrt(vmax_path) * dt * 1.01;
  std::size_t rows_checked = 0, off_path_rows = 0, excursion_rows = 0;
  double worst_v = 0.0, worst_a = 0.0, worst_off = 0.0, repeated_mm = 0.0, skipped_mm = 0.0;
  int limit_failures = 0;
  double lost_path_mm = 0.0, lost_time_s = 0.0;

  std::vector<std::vector<Row>> traces;
  for (const auto& path : traces_) traces.push_back(read_trace(path));

  // Limits over every trace (consecutive cycles only).
  for (std::size_t ti = 0; ti < traces.size(); ++ti) {
    const auto& rows = traces[ti];
    for (std::size_t k = 0; k < rows.size(); ++k) {
      for (int i = 0; i < 3; ++i) {
        const AxisConfig& ax = cfg_.axes[i];
        const double x = rows[k].cmd[i];
        if (x < ax.travel_min_mm - 1e-7 || x > ax.travel_max_mm + 1e-7) {
          if (limit_failures++ < 5) failures_.push_back("trace " + std::to_string(ti) + " t=" + std::to_string(rows[k].t) + ": setpoint outside the travel");
        }
        if (k >= 1 && std::abs(rows[k].t - rows[k - 1].t - dt) < 0.25 * dt) {
          const double v = std::abs(x - rows[k - 1].cmd[i]) / dt;
          worst_v = std::max(worst_v, v / ax.max_velocity_mm_s);
          if (v > ax.max_velocity_mm_s * (1.0 + 1e-6) + 1e-6 / dt) {
            if (limit_failures++ < 5) failures_.push_back("trace " + std::to_string(ti) + " t=" + std::to_string(rows[k].t) + ": a setpoint step beyond the velocity limit (a jump) on " + std::string(1, "XYZ"[i]));
          }
          if (k >= 2 && std::abs(rows[k - 1].t - rows[k - 2].t - dt) < 0.25 * dt) {
            const double acc = std::abs(x - 2.0 * rows[k - 1].cmd[i] + rows[k - 2].cmd[i]) / (dt * dt);
            const double slack = 4e-7 / (dt * dt);  // the trace's 0.1 um rounding
            worst_a = std::max(worst_a, std::max(0.0, acc - slack) / ax.max_accel_mm_s2);
            if (acc > ax.max_accel_mm_s2 * (1.0 + 1e-3) + slack) {
              if (limit_failures++ < 5) failures_.push_back("trace " + std::to_string(ti) + " t=" + std::to_string(rows[k].t) + ": acceleration beyond the limit on " + std::string(1, "XYZ"[i]));
            }
          }
        }
      }
    }
  }

  // The path of every run, walked along its blocks.
  for (std::size_t ai = 0; ai < attempts_.size(); ++ai) {
    const Attempt& a = attempts_[ai];
    const auto& rows = traces[static_cast<std::size_t>(a.trace)];
    const auto& path = a.path;
    if (path.empty()) continue;
    std::size_t j = 0;
    double s_cur = 0.0, s_max = 0.0, prev_g = 0.0;
    bool excursion = false, seen = false;
    std::size_t since_on = 0;
    const std::string name = "run " + std::to_string(ai + 1);
    for (const Row& r : rows) {
      if (r.t < a.t_begin - 1e-9 || r.t > a.t_end + 1e-9) continue;
      ++rows_checked;
      ++since_on;
      if (r.state == "JOGGING") {
        excursion = true;
        ++excursion_rows;
        continue;
      }
      if (r.state == "FAULT" || r.state == "ESTOP") {
        failures_.push_back(name + ": the machine went to " + r.state + " at t=" + std::to_string(r.t));
        break;
      }
      std::size_t found = path.size();
      double fs = 0.0, best_d = 1e300;
      std::size_t back = path.size();
      double back_s = 0.0;
      for (std::size_t k = j; k < path.size() && k < j + 64; ++k) {
        double s = 0.0, d = 0.0;
        locate(path[k].b, r.cmd, k == j ? s_cur : 0.0, s, d);
        best_d = std::min(best_d, d);
        if (d > tol) continue;
        if (k == j && s < s_cur - tol) {
          back = k;
          back_s = s;
          continue;
        }
        found = k;
        fs = s;
        break;
      }
      if (found == path.size() && back < path.size()) {
        found = back;
        fs = back_s;
      }
      for (std::size_t k = j; found == path.size() && k-- > 0 && k + 4 > j;) {
        double s = 0.0, d = 0.0;
        locate(path[k].b, r.cmd, 0.0, s, d);
        if (d <= tol) {
          found = k;
          fs = s;
        }
      }
      if (found == path.size()) {
        if (excursion) {
          ++excursion_rows;  // the return leg to the pause point
        } else {
          ++off_path_rows;
          worst_off = std::max(worst_off, best_d);
          if (off_path_rows <= 3) failures_.push_back(name + ": setpoint off the program's path by " + std::to_string(best_d) + " mm at t=" + std::to_string(r.t));
        }
        continue;
      }
      const double g = path[found].s0 + fs;
      if (excursion) {
        // Jogged away: nothing counts until the machine is back on the pause point (the
        // return leg may run along or across the path elsewhere). A run that never gets back
        // fails the coverage check below.
        if (std::abs(g - s_max) > tol) {
          ++excursion_rows;
          continue;
        }
        excursion = false;
      }
      if (seen && g > s_max + step_bound * static_cast<double>(since_on) + tol) {
        skipped_mm += g - s_max;
        failures_.push_back(name + ": path skipped from s=" + std::to_string(s_max) + " to " + std::to_string(g) + " mm");
      }
      if (g < s_max - tol) {
        repeated_mm = std::max(repeated_mm, s_max - g);
        failures_.push_back(name + ": path repeated from s=" + std::to_string(g) + " back from " + std::to_string(s_max) + " mm");
        s_max = g;  // report each regression once
      }
      s_max = std::max(s_max, g);
      prev_g = g;
      since_on = 0;
      seen = true;
      j = found;
      s_cur = fs;
    }
    (void)prev_g;
    if (!a.aborted && a.end == "completed" && s_max < a.total - tol) {
      failures_.push_back(name + ": the trace covers " + std::to_string(s_max) + " of " + std::to_string(a.total) + " mm");
    }
    if (a.aborted) {
      lost_path_mm += s_max;
    }
    std::printf("%s: %s, %zu blocks, path %.3f mm, covered %.3f mm\n", name.c_str(), a.end.c_str(), path.size(), a.total, s_max);
  }

  // Following error at each recovery: the trace from the kill to 1 s after the resume.
  for (Fault& f : faults_) {
    if ((f.kind != "kill -9 host" && f.kind != "HOST_LOST unasked") || f.t_back <= 0.0) continue;
    for (const Row& r : traces[static_cast<std::size_t>(f.trace)]) {
      if (r.t >= f.t_kill - 0.01 && r.t <= f.t_back + 1.0) f.max_ferr_mm = std::max(f.max_ferr_mm, max_abs(r.ferr));
    }
    lost_time_s += f.to_resumed_ms / 1000.0;
  }

  // Figures.
  std::map<std::string, std::pair<int, int>> by_kind;
  for (const Fault& f : faults_) {
    by_kind[f.kind].first++;
    by_kind[f.kind].second += f.survived ? 1 : 0;
  }
  int injected = 0, survived = 0;
  std::printf("\n==== soak figures (seed %llu) ====\n", static_cast<unsigned long long>(o_.seed));
  for (const auto& [k, v] : by_kind) {
    std::printf("  %-18s injected %4d  survived %4d\n", k.c_str(), v.first, v.second);
    injected += v.first;
    survived += v.second;
  }
  std::printf("  %-18s injected %4d  survived %4d\n", "all faults", injected, survived);
  auto stats = [&](const char* label, const std::function<double(const Fault&)>& get, const std::string& kind) {
    std::vector<double> v;
    for (const Fault& f : faults_) {
      if (f.kind == kind && get(f) >= 0.0) v.push_back(get(f));
    }
    if (v.empty()) return;
    double sum = 0.0;
    for (double x : v) sum += x;
    std::printf("  %-36s min %8.1f  mean %8.1f  max %8.1f  (n=%zu)\n", label, *std::min_element(v.begin(), v.end()),
                sum / static_cast<double>(v.size()), *std::max_element(v.begin(), v.end()), v.size());
  };
  stats("host kill -> HOST_LOST, ms", [](const Fault& f) { return f.to_lost_ms; }, "kill -9 host");
  stats("host kill -> resumed, ms", [](const Fault& f) { return f.to_resumed_ms; }, "kill -9 host");
  stats("max |ferr| per host recovery, um", [](const Fault& f) { return f.t_back > 0.0 ? 1000.0 * f.max_ferr_mm : -1.0; }, "kill -9 host");
  stats("rt kill -> seen lost by host, ms", [](const Fault& f) { return f.to_lost_ms; }, "kill -9 rt");
  stats("rt kill -> re-attached, ms", [](const Fault& f) { return f.to_resumed_ms; }, "kill -9 rt");
  stats("restarted rt off last position, mm", [](const Fault& f) { return f.position_jump_mm; }, "kill -9 rt");
  std::printf("  runs %zu (completed %zu, ended by an rt kill %zu)\n", attempts_.size(),
              static_cast<std::size_t>(std::count_if(attempts_.begin(), attempts_.end(), [](const Attempt& a) { return a.end == "completed"; })),
              static_cast<std::size_t>(std::count_if(attempts_.begin(), attempts_.end(), [](const Attempt& a) { return a.aborted; })));
  std::printf("  lost work: %.1f s standing still in host recoveries, %.3f mm of path repeated, %.3f mm of path "
              "cut by runs an rt kill ended\n", lost_time_s, repeated_mm, lost_path_mm);
  std::printf("  trace rows checked %zu, off the path %zu (worst %.6f mm), jog excursions %zu, skipped %.3f mm\n",
              rows_checked, off_path_rows, off_path_rows ? worst_off : 0.0, excursion_rows, skipped_mm);
  std::printf("  worst setpoint velocity %.3f x the axis limit, acceleration %.3f x the axis limit\n", worst_v, worst_a);
  if (!o_.summary.empty()) {
    json j = {{"seed", o_.seed}, {"file", o_.file}, {"minutes", o_.minutes}, {"faults_injected", injected},
              {"faults_survived", survived}, {"repeated_mm", repeated_mm}, {"skipped_mm", skipped_mm},
              {"off_path_rows", off_path_rows}, {"worst_velocity_ratio", worst_v}, {"worst_accel_ratio", worst_a},
              {"lost_time_s", lost_time_s}, {"failures", failures_}};
    json fl = json::array();
    for (const Fault& f : faults_) {
      fl.push_back({{"kind", f.kind}, {"survived", f.survived}, {"note", f.note}, {"to_lost_ms", f.to_lost_ms},
                    {"to_resumed_ms", f.to_resumed_ms}, {"max_ferr_mm", f.max_ferr_mm}, {"position_jump_mm", f.position_jump_mm}});
    }
    j["faults"] = fl;
    std::ofstream(o_.summary) << j.dump(1) << "\n";
  }
  if (!failures_.empty()) {
    std::printf("\nINVARIANTS FAILED (%zu):\n", failures_.size());
    for (const auto& f : failures_) std::printf("  %s\n", f.c_str());
    return 1;
  }
  std::printf("  all invariants held\n");
  return 0;
}

}  // namespace

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
