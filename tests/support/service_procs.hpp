// service_procs.hpp — tests of `pcnc-host --serve`: start pcnc-rt and the service as real
// processes on a per-test config (own shm name and socket), talk to the socket with
// CtlClient, wait for conditions on the status, kill either process, clean up.
#pragma once

#include <nlohmann/json.hpp>

#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "config/config.hpp"
#include "ctl.hpp"
#include "ipc/status.hpp"
#include "subprocess.hpp"

namespace pcnc::test {

using json = nlohmann::json;

class ServicePair {
 public:
  /// Writes the test config (write_test_config with `replacements`) in a fresh temp dir.
  explicit ServicePair(const std::string& tag, const std::vector<std::pair<std::string, std::string>>& replacements = {});
  ~ServicePair();  // SIGTERM both (SIGKILL if they hang), remove the segment

  /// Starts pcnc-rt ("real" or "virtual"), optionally with more arguments (e.g. --trace).
  void start_rt(const std::string& clock, const std::vector<std::string>& extra = {});
  /// Starts pcnc-host --serve and waits until its socket answers.
  bool start_host(double timeout_s = 10.0);
  /// Both, and waits until the service reports the rt attached and the machine IDLE.
  bool start(const std::string& clock, const std::vector<std::string>& rt_extra = {});

  /// One request on a fresh connection: the whole reply ({"id","result"} or {"id","error"}).
  json call(const std::string& method, const json& params = json::object(), double timeout_s = 30.0);
  /// The "result" of status (throws if status itself failed).
  json status();
  /// Polls status until `pred` holds; returns the last status (check `pred` again).
  json wait_status(const std::function<bool(const json&)>& pred, double timeout_s);

  void kill_rt(int sig);    // signal + reap
  void kill_host(int sig);  // signal + reap

  const std::string& dir() const { return dir_; }
  const std::string& config() const { return config_; }
  /// `pcnc ctl --config <this pair's config> ARGS...`, run to its end (at most `timeout_s`).
  ProcessResult ctl(const std::vector<std::string>& args, double timeout_s = 120) const;
  const std::string& socket() const { return socket_; }
  const std::string& tag() const { return tag_; }
  std::string host_log() const { return host_.err() + host_.out(); }
  std::string rt_log() const { return rt_.err() + rt_.out(); }
  int rt_pid() const { return rt_.pid; }
  int host_pid() const { return host_.pid; }

 private:
  std::string tag_, dir_, config_, socket_;
  BackgroundProcess rt_, host_;
  int rt_starts_ = 0, host_starts_ = 0;
};

std::string rt_exe();
std::string host_exe();
std::string pcnc_exe();

/// The shipped desktop-mill config as pcnc-host loads it (its path tolerance included).
MachineConfig mill_config();

/// Readers of the socket's replies and status (docs/protocol.md).
/// status[which][x|y|z] for axis 0-2 (`which`: "machine", "work", ...).
double pos(const json& status, const char* which, int axis);
/// A reply's error code (0 when it is a result) and message ("" when it is a result).
int error_code(const json& reply);
std::string error_message(const json& reply);
/// Idle with no job running; idle_after_job: and the last job's record is there.
bool idle(const json& status);
bool idle_after_job(const json& status);

/// Writes `text` to dir/name; returns the path.
std::string write_program(const std::string& dir, const std::string& name, const std::string& text);
/// A zig-zag of `rows` X strokes of `width` mm at F`feed` mm/min around program zero, ending at
/// program X0 Y0 Z-1 (machine 12.5, 12.5, 24 with the default G54).
/// The rt's status read straight from the segment of test `tag` (also a stale one: a killed
/// rt leaves it behind); false when there is none.
bool read_rt_status(const std::string& tag, Status& out);
/// Polls the segment of test `tag` until the rt's state is `state` (or `timeout_s` passes);
/// returns the last status read (check its state).
Status wait_rt_state(const std::string& tag, MachineState state, double timeout_s = 5.0);

std::string zigzag_program(const std::string& dir, int rows, double width, double feed);
/// A program whose check takes a while: a loop of `iterations` short G1 moves just below program
/// zero (three lines run each), written to dir/name.
std::string loop_program(const std::string& dir, const std::string& name, int iterations);

/// A lost host and its resume (docs/reliability.md): kills the pair's host with SIGKILL while
/// its job runs, waits for the rt's HOST_LOST, starts a new host, asks it to resume and waits
/// for the job's end. `error` says which step failed (empty when all did what they should: the
/// resume replied with a result from the held position, the job ended); `lost` is the rt's
/// status when it held, `reply` the resume's reply, `final` the status after the job.
struct KillAndResume {
  std::string error;
  Status lost{};
  json reply;
  json final;
};
KillAndResume kill_host_and_resume(ServicePair& p);

}  // namespace pcnc::test
