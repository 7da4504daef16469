// soak_parts.hpp — the types the fault-injection soak's two files share: soak.cpp (the
// processes, the faults and their timing) and soak_check.cpp (the rt's traces checked against
// the program's blocks, and the figures). Only tools/soak*.cpp include it.
#pragma once

#include <nlohmann/json.hpp>

#include <sys/types.h>

#include <chrono>
#include <cstdint>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "config/config.hpp"
#include "ipc/block.hpp"
#include "ipc/status.hpp"

namespace pcnc::soak {

using json = nlohmann::json;
using Clock = std::chrono::steady_clock;

inline double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// One block of a run's program, with the program's arc length before it.
struct PathBlock {
  Block b;
  double s0 = 0.0;  // arc length of the program before this block
  double len = 0.0;
};

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
  Fault kill_process(const char* kind, pid_t& pid, Status& before, Clock::time_point& killed_at);
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
  // A host kill landed after the program's End: the rt saw it done (program_done) but the new
  // host has no record of the job, so the run's end comes from the rt's status.
  bool ended_under_killed_host_ = false;
};


}  // namespace pcnc::soak
