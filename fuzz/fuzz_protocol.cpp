// fuzz_protocol.cpp — libFuzzer entry for the control protocol (docs/protocol.md): the input,
// cut at '\n' into request lines (any bytes), goes through the service's real dispatch
// (service/dispatch.hpp) and its real method table (service/methods.hpp) with the real parts
// behind it (rt monitor, job control with its worker thread and journal, jog control,
// subscriptions), against a machine simulated in this process: a real shared-memory segment
// (RtSegment, unique name) with a real pcnc::Machine stepped on this thread, cycle by cycle
// (a virtual clock: 20 cycles after each line, and while a reply or a job waits), so every
// command reaches a real machine, programs run, jogs move and e-stops stop.
//
// What is checked (a failure traps, libFuzzer saves the input):
//   - every line gets exactly one reply: one JSON object on one '\n'-terminated line,
//     {"id","result"} or {"id","error":{"code","message"[,"data"]}} with a known code, never
//     the internal error (a client input that makes a handler throw is a bug even if caught);
//   - the reply carries the request's id when it could be read (the line is JSON, an object
//     with one "id" at its top level: a number, a string or null; otherwise the reply's id is
//     null); replies that come later (run, jog) come before the next line is handled, and no
//     reply comes that no request asked for;
//   - pushed notifications are {"method":"status"|"event","params":{...}} without an id;
//   - no exception escapes (libFuzzer reports one as a crash), no job or reply hangs (bounded
//     in wall time), and afterwards the service still answers `status` with a result.
// Between inputs the machine is rebuilt and the service's parts are new, so each input starts
// from the same IDLE machine at home.
//
// Programs: `run` needs an absolute path; four small programs live in memory files (memfd)
// at fixed descriptors, so the dictionary and the seeds can name them:
//   /proc/self/fd/900  a few short moves, ends with M30
//   /proc/self/fd/901  a preflight error
//   /proc/self/fd/902  empty
//   /proc/self/fd/903  moves with an M00 in the middle (pauses; resume continues)
// Nothing is left behind: the segment's name is removed as soon as the service has attached
// (both mappings stay), the memfds vanish with the process, and the journal's temporary
// folder (/tmp/pcnc-fuzz-protocol-PID-*) is removed at exit; one left by a crashed run is
// removed by the next run (its pid is gone).
#include <dirent.h>
#include <fcntl.h>
#include <spdlog/spdlog.h>
#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "config/config.hpp"
#include "ipc/segment.hpp"
#include "loop/machine.hpp"
#include "service/dispatch.hpp"
#include "service/job_control.hpp"
#include "service/job_journal.hpp"
#include "service/jog_control.hpp"
#include "service/methods.hpp"
#include "service/rt_monitor.hpp"
#include "service/subscriptions.hpp"

namespace {

using pcnc::rpc::json;
using Clock = std::chrono::steady_clock;

constexpr std::size_t kMaxLines = 64;       // lines handled per input
constexpr int kCyclesPerLine = 20;          // machine time between two lines: 10 ms at 2 kHz
constexpr unsigned kCyclesPerTick = 10;     // the service's loop tick: 5 ms
constexpr int kSettleCycles = 6000;         // at the end: a running program may go on this long
constexpr double kReplyTimeoutS = 5.0;      // a later reply must come within this (wall time)
constexpr double kSettleTimeoutS = 10.0;    // the job must end within this after the input

[[noreturn]] void fail(const char* what, std::string_view detail = {}) {
  std::fprintf(stderr, "\nfuzz_protocol: %s: %.*s\n", what, static_cast<int>(std::min<std::size_t>(detail.size(), 2000)),
               detail.data());
  std::fflush(stderr);
  __builtin_trap();
}

double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

// ---------------------------------------------------------------- programs and files

struct Program {
  int fd;
  const char* text;
};
constexpr Program kPrograms[] = {
    {900, "G21 G90 G54\nG0 X0.5 Y0.5\nG1 X1 F1200\nG2 X1.5 Y1 I0 J0.5\nG1 Z-0.2 F600\nG0 Z1\nM30\n"},
    {901, "G21 G90\nG1 X1 F600 Q3\nM30\n"},
    {902, ""},
    {903, "G21 G90 G54\nG1 X0.5 F1200\nM00\nG1 Y0.5\nM30\n"},
};

void make_program_files() {
  for (const Program& p : kPrograms) {
    const int fd = memfd_create("pcnc-fuzz-program", 0);
    if (fd < 0) fail("memfd_create failed");
    const std::string_view t(p.text);
    if (!t.empty() && write(fd, t.data(), t.size()) != static_cast<ssize_t>(t.size())) fail("memfd write failed");
    if (dup2(fd, p.fd) != p.fd) fail("dup2 failed");
    close(fd);
  }
}

// The journal's folder: /tmp/pcnc-fuzz-protocol-PID-XXXXXX. Folders of runs whose process is
// gone (a crash) are removed first.
std::string make_temp_dir() {
  const std::string prefix = "pcnc-fuzz-protocol-";
  if (DIR* d = opendir("/tmp")) {
    while (dirent* e = readdir(d)) {
      const std::string name = e->d_name;
      if (name.rfind(prefix, 0) != 0) continue;
      const int pid = std::atoi(name.c_str() + prefix.size());
      if (pid > 0 && pid != getpid() && !pcnc::process_alive(pid)) {
        std::error_code ec;
        std::filesystem::remove_all("/tmp/" + name, ec);
      }
    }
    closedir(d);
  }
  std::string templ = "/tmp/" + prefix + std::to_string(getpid()) + "-XXXXXX";
  if (!mkdtemp(templ.data())) fail("mkdtemp failed");
  return templ;
}

// ---------------------------------------------------------------- the machine side

// A real segment and a real Machine, stepped on the fuzzer's thread like pcnc-rt's loop
// under --clock virtual: the replay stage into the ring, mailbox, one cycle, slot-freed
// wake-up, status.
class InProcessRt {
 public:
  InProcessRt(const pcnc::MachineConfig& config, const std::string& name) : config_(config), segment_(name) { reset(); }

  pcnc::SharedSegment& shm() { return segment_.shm(); }
  const pcnc::Machine& machine() const { return *machine_; }

  /// A new machine at home, IDLE; mailbox and ring emptied (no job may be feeding).
  void reset() {
    auto& s = shm();
    pcnc::Command c;
    while (s.commands.try_pop(c)) {
    }
    s.motion.pop_all();
    s.stage.pop_all();
    machine_ = std::make_unique<pcnc::Machine>(config_);
    machine_->set_host_alive(true);
    cycle();
  }

  /// One cycle. `feeding`: a job is feeding the ring, so a program that wants blocks waits
  /// (a bounded while) for them first, as the rt does under the virtual clock.
  void step(bool feeding) {
    auto& s = shm();
    pcnc::take_staged(s);  // the host writes into the replay stage under the virtual clock
    if (feeding && !starved_ && s.commands.empty() && machine_->wants_more_blocks(s.motion)) {
      const bool got = s.block_published.wait_until(
          [&] { return !s.commands.empty() || !s.stage.empty() || !machine_->wants_more_blocks(s.motion); }, 0.02,
          50000);
      pcnc::take_staged(s);
      if (!got) starved_ = true;  // the job stopped feeding: run on (an underrun), do not wait again
    }
    if (!feeding) starved_ = false;
    cycle();
  }

  bool has_commands() { return !shm().commands.empty(); }

 private:
  void cycle() {
    auto& s = shm();
    s.header.rt_heartbeat_ns.store(pcnc::monotonic_ns(), std::memory_order_release);
    pcnc::Command cmd;
    while (s.commands.try_pop(cmd)) machine_->command(cmd);
    const std::uint64_t popped = s.motion.popped();
    machine_->cycle(s.motion);
    if (s.motion.popped() != popped) {
      starved_ = false;
      s.header.slot_freed_ns.store(pcnc::monotonic_ns(), std::memory_order_release);
      s.slot_freed.notify();
    }
    pcnc::Status st = machine_->status();
    st.clock_virtual = 1;
    st.ring_fill = static_cast<std::uint8_t>(s.motion.size());
    s.status.store(st);
  }

  const pcnc::MachineConfig& config_;
  pcnc::RtSegment segment_;
  std::unique_ptr<pcnc::Machine> machine_;
  bool starved_ = false;
};

pcnc::MachineConfig make_config(const std::string& dir) {
  pcnc::MachineConfig c;  // the built-in defaults: 25 mm travel per axis
  c.gcode.work_offsets[0] = {12.5, 12.5, 25.0};
  c.gcode.work_offsets[1] = {0.0, 0.0, 25.0};
  c.process.shm_name = "/pcnc-fuzz-protocol-" + std::to_string(getpid());
  c.process.socket_path = dir + "/pcnc.sock";  // never created: only the journal's name comes from it
  c.process.rt_timeout_s = 3600.0;  // the rt is stepped between lines: never "lost" while the fuzzer thinks
  return c;
}

// What lives as long as the process: the segment, the machine, the monitor's link.
struct Harness {
  Harness()
      : dir(make_temp_dir()),
        config(make_config(dir)),
        rt(config, config.process.shm_name),
        monitor(config, 0.001, 0.001, {}) {
    make_program_files();
    monitor.start();
    const auto t0 = Clock::now();
    while (!monitor.current()) {
      if (since(t0) > 10.0) fail("the service never attached to the in-process rt", monitor.state().message);
      rt.step(false);
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    monitor.stop();  // attached; the link stays (the in-process rt never dies)
    pcnc::remove_segment(config.process.shm_name);  // both mappings stay; nothing is left if we crash
  }
  ~Harness() {
    monitor.release();
    std::error_code ec;
    std::filesystem::remove_all(dir, ec);
  }
  std::string dir;
  pcnc::MachineConfig config;
  InProcessRt rt;
  pcnc::RtMonitor monitor;
};

// ---------------------------------------------------------------- the oracle

bool valid_id(const json& v) { return v.is_number() || v.is_string() || v.is_null(); }

// The id the reply must carry: the request's when the line is a JSON object with exactly one
// top-level "id" that is a number, a string or null; null when it is an object without one or
// with one of another type; unknown (nullopt: any valid id) otherwise.
std::optional<json> expected_id(std::string_view line) {
  int ids = 0;
  const json::parser_callback_t count_ids = [&](int depth, json::parse_event_t event, json& parsed) {
    if (event == json::parse_event_t::key && depth == 1 && parsed.is_string() && parsed.get_ref<const std::string&>() == "id") ++ids;
    return true;
  };
  const json j = json::parse(line.begin(), line.end(), count_ids, false);
  if (j.is_discarded() || !j.is_object() || ids > 1) return std::nullopt;
  const auto it = j.find("id");
  if (it == j.end() || !valid_id(*it)) return json(nullptr);
  return *it;
}

bool known_code(int code) {
  using namespace pcnc::rpc;
  switch (code) {
    case kParseError: case kInvalidRequest: case kMethodNotFound: case kInvalidParams: case kRefused:
    case kRtUnavailable: case kPreflightFailed: case kMailboxFull:
      return true;
    default:
      return false;
  }
}

// One line the service sent: parsed, its shape checked.
json parse_sent(std::string_view line) {
  if (line.empty() || line.back() != '\n' || line.find('\n') != line.size() - 1) fail("a sent line is not one '\\n'-terminated line", line);
  const json j = json::parse(line.begin(), line.end() - 1, nullptr, false);
  if (j.is_discarded() || !j.is_object()) fail("a sent line is not a JSON object", line);
  return j;
}

void check_reply_shape(const json& r, std::string_view line) {
  const bool result = r.contains("result"), error = r.contains("error");
  if (!r.contains("id") || !valid_id(r["id"]) || r.size() != 2 || result == error) fail("malformed reply", line);
  if (error) {
    const json& e = r["error"];
    if (!e.is_object() || !e.contains("code") || !e["code"].is_number_integer() || !e.contains("message") ||
        !e["message"].is_string() || e.size() > 3 || (e.size() == 3 && !e.contains("data"))) {
      fail("malformed error reply", line);
    }
    const int code = e["code"].get<int>();
    if (code == pcnc::rpc::kInternalError) fail("internal error: a handler threw on client input", line);
    if (!known_code(code)) fail("unknown error code", line);
  }
}

// ---------------------------------------------------------------- one input

// The service's parts for one input, wired as service.cpp wires them, with this thread as the
// loop thread: what the job worker reports is posted and run here.
struct Session {
  explicit Session(Harness& h)
      : harness(h),
        config(h.config),
        work("", pcnc::default_work_state(config)),  // in memory: set_offset is fuzzed, not the disk
        subs([this](pcnc::ClientId c, std::string_view line) { sent(c, line); }),
        jobs(pcnc::journal_path(config.process.socket_path),
             pcnc::JobNotices{[this](pcnc::ClientId c, json id, pcnc::Outcome o) {
                                post([this, c, id = std::move(id), o = std::move(o)] { reply(c, id, o); });
                              },
                              [this](json ev) { post([this, ev = std::move(ev)] { subs.broadcast_event(ev); }); },
                              [this](pcnc::WorkState before, pcnc::WorkState after, std::function<void()> applied) {
                                post([this, before, after, applied = std::move(applied)] {
                                  (void)work.replace(pcnc::merge_work_change(work.state(), before, after));
                                  if (applied) applied();  // the job's end waits for this (the service's order)
                                });
                              }}),
        jogs(config, h.monitor, [this](pcnc::ClientId c, const json& id, const pcnc::Outcome& o) { reply(c, id, o); },
             [this](const json& ev) { subs.broadcast_event(ev); }),
        parts{config, work, h.monitor, jobs, jogs, subs},
        dispatcher(pcnc::method_table(parts), h.monitor) {}

  ~Session() {
    jobs.interrupt();
    jobs.join();
  }

  void post(std::function<void()> fn) {
    std::lock_guard<std::mutex> lock(mutex);
    posted.push_back(std::move(fn));
  }
  void run_posted() {
    std::vector<std::function<void()>> fns;
    {
      std::lock_guard<std::mutex> lock(mutex);
      fns.swap(posted);
    }
    for (auto& fn : fns) fn();
  }

  void reply(pcnc::ClientId c, const json& id, const pcnc::Outcome& o) {
    const std::string line = pcnc::format_outcome(id, o);
    if (!line.empty()) sent(c, line);
  }

  // Everything the service sends to a client passes here.
  void sent(pcnc::ClientId c, std::string_view line) {
    const json j = parse_sent(line);
    if (!j.contains("id")) {  // a notification
      if (j.size() != 2 || !j.contains("method") || !j.contains("params") || !j["params"].is_object() ||
          (j["method"] != "status" && j["method"] != "event")) {
        fail("malformed notification", line);
      }
      return;
    }
    if (!waiting) fail("a reply no request asked for", line);
    if (c != client) fail("a reply to another client", line);
    check_reply_shape(j, line);
    if (want_id && j["id"] != *want_id) fail("the reply does not carry the request's id", std::string(line) + " for " + request);
    ++replies;
    last_reply = j;
  }

  // One machine cycle; every kCyclesPerTick cycles (5 ms of machine time, the service's
  // loop tick) also the loop's tick: posted work, jog control, subscriptions. The rt is
  // alive by construction, so its status is read without the liveness check.
  void tick() {
    harness.rt.step(jobs.active());
    if (++cycles % kCyclesPerTick != 0 && !waiting) return;
    run_posted();
    const std::optional<pcnc::Status> st = harness.monitor.current()->status();
    jogs.tick(st);
    subs.tick([this] { return pcnc::status_object(parts); });
  }

  void handle(pcnc::ClientId c, std::string_view line) {
    client = c;
    request.assign(line);
    want_id = expected_id(line);
    replies = 0;
    waiting = true;
    const std::string r = dispatcher.handle(c, line);
    if (!r.empty()) sent(c, r);
    const auto t0 = Clock::now();
    while (replies == 0) {  // a reply that comes later: run (once started or refused), jog (once taken)
      if (since(t0) > kReplyTimeoutS) fail("no reply within 5 s", line);
      tick();
      if (!harness.rt.has_commands() && jobs.active()) std::this_thread::sleep_for(std::chrono::microseconds(50));
    }
    run_posted();
    if (replies != 1) fail("more than one reply", line);
    waiting = false;
    for (int i = 0; i < kCyclesPerLine; ++i) tick();
  }

  // The end of the input: a program may run on for a while, then it is stopped; both clients
  // go away; the service must still answer status.
  void settle() {
    const auto t0 = Clock::now();
    for (int i = 0; i < kSettleCycles && jobs.active();) {
      if (since(t0) > kSettleTimeoutS) fail("a job did not end within 10 s");
      const auto s = harness.rt.machine().status().state;
      if (s == pcnc::MachineState::kPaused && harness.rt.machine().paused_at_rest() && !harness.rt.has_commands()) break;  // M00: stop it
      if (s == pcnc::MachineState::kIdle && !harness.rt.has_commands()) {
        // the program is over: the worker notices within its status poll (2 ms); machine time stands still meanwhile
        run_posted();
        std::this_thread::sleep_for(std::chrono::microseconds(100));
        continue;
      }
      tick();
      ++i;
    }
    jobs.interrupt();
    while (jobs.active()) {
      if (since(t0) > kSettleTimeoutS) fail("an interrupted job did not end within 10 s");
      tick();
      if (!harness.rt.has_commands()) std::this_thread::sleep_for(std::chrono::microseconds(20));
    }
    jobs.join();
    run_posted();
    for (pcnc::ClientId c : {1, 2}) {
      subs.remove(c);
      jogs.client_gone(c);
    }
    tick();
    handle(1, R"({"id":"final","method":"status"})");
    if (!last_reply.contains("result") || !last_reply["result"].contains("state")) fail("status is not answered after the input");
  }

  Harness& harness;
  pcnc::MachineConfig config;
  pcnc::WorkStore work;
  pcnc::Subscriptions subs;
  pcnc::JobControl jobs;
  pcnc::JogControl jogs;
  pcnc::ServiceParts parts;
  pcnc::Dispatcher dispatcher;
  std::mutex mutex;
  std::vector<std::function<void()>> posted;
  // the request being answered
  bool waiting = false;
  pcnc::ClientId client = 0;
  std::string request;
  std::optional<json> want_id;
  int replies = 0;
  json last_reply;
  unsigned cycles = 0;
};

Harness& harness() {
  static Harness h;
  return h;
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  spdlog::set_level(spdlog::level::off);
  harness();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  Harness& h = harness();
  h.rt.reset();
  {
    Session s(h);
    const std::string_view input(reinterpret_cast<const char*>(data), size);
    std::size_t start = 0, n = 0;
    while (start <= input.size() && n < kMaxLines) {
      std::size_t end = input.find('\n', start);
      if (end == std::string_view::npos) end = input.size();
      std::string_view line = input.substr(start, end - start);
      // As the control server does: a trailing '\r' goes, empty lines are skipped.
      if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
      // Two clients: even lines from one, odd from the other (jog ownership, subscriptions).
      if (!line.empty()) s.handle(1 + (n & 1), line);
      ++n;
      start = end + 1;
    }
    s.settle();
  }
  return 0;
}
