// test_proc_protocol_fuzz.cpp — the control protocol under a storm of mutated requests, live:
// pcnc-rt (real clock) and pcnc-host --serve run a real program of about 5 s while 4 client
// threads send requests made by a deterministic mutator (seeded per thread: byte flips,
// insertions, deletions, truncation, values of another type, huge numbers, unknown methods,
// repeated keys, deep nesting, with valid requests mixed in) and a fifth client asks for
// `status` every 50 ms. Requests that could legitimately change the program's outcome (run,
// pause, resume, stop, estop, reset, override, jog, jog_stop) are filtered out of the storm
// when the server would read them as such; everything else is sent.
//
// Asserted: the host stays up (same pid, the socket answers), the program completes
// (last_job.end "completed"), every request line gets exactly one reply, in order, carrying
// the request's id whenever the line is a JSON object with one readable id, every reply is
// a well-formed JSON reply and none is an internal error, and `status` is always answered
// during the storm. Underruns and the status latency are reported ("[ figures ]"), not
// asserted: a loaded CI machine is noisy.
#include <gtest/gtest.h>
#include <poll.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "service/rpc.hpp"
#include "service_procs.hpp"

namespace pcnc::test {
namespace {

using Clock = std::chrono::steady_clock;

constexpr int kStormThreads = 4;
constexpr double kStormSeconds = 4.0;   // the program runs about 5 s
constexpr int kMaxRequestsPerThread = 3000;
constexpr int kBatch = 8;               // lines sent before their replies are read

// ------------------------------------------------------------ a line client on a raw socket

class LineSocket {
 public:
  explicit LineSocket(const std::string& path) {
    sockaddr_un a{};
    a.sun_family = AF_UNIX;
    std::strncpy(a.sun_path, path.c_str(), sizeof a.sun_path - 1);
    fd_ = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
    if (fd_ >= 0 && connect(fd_, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0) {
      close(fd_);
      fd_ = -1;
    }
  }
  ~LineSocket() {
    if (fd_ >= 0) close(fd_);
  }
  bool ok() const { return fd_ >= 0; }
  bool send_all(const std::string& s) {
    std::size_t off = 0;
    while (off < s.size()) {
      const ssize_t n = ::send(fd_, s.data() + off, s.size() - off, MSG_NOSIGNAL);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) return false;
      off += static_cast<std::size_t>(n);
    }
    return true;
  }
  // One line (without '\n') within timeout_s; false on timeout or a closed connection.
  bool read_line(std::string& line, double timeout_s) {
    const auto deadline = Clock::now() + std::chrono::duration<double>(timeout_s);
    for (;;) {
      if (const auto nl = buf_.find('\n'); nl != std::string::npos) {
        line = buf_.substr(0, nl);
        buf_.erase(0, nl + 1);
        return true;
      }
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
      if (left <= 0) return false;
      pollfd p{fd_, POLLIN, 0};
      if (poll(&p, 1, static_cast<int>(left)) <= 0) continue;
      char tmp[65536];
      const ssize_t n = recv(fd_, tmp, sizeof tmp, 0);
      if (n <= 0) return false;
      buf_.append(tmp, static_cast<std::size_t>(n));
    }
  }
  // The next reply (a line with an "id"), skipping pushed notifications.
  bool read_reply(json& reply, std::string& raw, double timeout_s, int* notifications) {
    const auto deadline = Clock::now() + std::chrono::duration<double>(timeout_s);
    for (;;) {
      const double left = std::chrono::duration<double>(deadline - Clock::now()).count();
      if (left <= 0 || !read_line(raw, left)) return false;
      reply = json::parse(raw, nullptr, false);
      if (reply.is_object() && !reply.contains("id") && reply.contains("method")) {
        ++*notifications;
        continue;
      }
      return true;
    }
  }

 private:
  int fd_ = -1;
  std::string buf_;
};

// ------------------------------------------------------------ the mutator

// What the server will read from a line: the method(s) named at the top level, and the id the
// reply must carry (the same rule as fuzz/fuzz_protocol.cpp).
struct Reading {
  bool object = false;
  std::vector<std::string> methods;
  bool id_known = false;  // the reply's id is determined
  json id;
};

Reading read_as_server(const std::string& line) {
  Reading r;
  int ids = 0;
  bool method_value_next = false;
  // Every top-level "method" value, repeated ones included (the server refuses a repeated
  // key, but the filter must not depend on that).
  const json::parser_callback_t cb = [&](int depth, json::parse_event_t ev, json& parsed) {
    if (ev == json::parse_event_t::key && depth == 1 && parsed.is_string()) {
      const auto& k = parsed.get_ref<const std::string&>();
      ids += k == "id";
      method_value_next = k == "method";
    } else if (ev == json::parse_event_t::value && depth == 1 && method_value_next) {
      if (parsed.is_string()) r.methods.push_back(parsed.get<std::string>());
      method_value_next = false;
    }
    return true;
  };
  std::string_view v(line);
  if (!v.empty() && v.back() == '\r') v.remove_suffix(1);  // as the server reads it
  const json j = json::parse(v.begin(), v.end(), cb, false);
  if (j.is_discarded() || !j.is_object()) {
    r.methods.clear();
    return r;
  }
  r.object = true;
  if (ids <= 1) {
    r.id_known = true;
    auto it = j.find("id");
    r.id = (it != j.end() && (it->is_number() || it->is_string() || it->is_null())) ? *it : json(nullptr);
  }
  return r;
}

bool changes_the_program(const Reading& r) {
  static const char* unsafe[] = {"run", "pause", "resume", "stop", "estop", "reset", "override", "jog", "jog_stop"};
  for (const auto& m : r.methods) {
    for (const char* u : unsafe) {
      if (m == u) return true;
    }
  }
  return false;
}

class Mutator {
 public:
  explicit Mutator(std::uint64_t seed) : rng_(seed) {}

  std::string next(long long id) {
    std::string line = base(id);
    const int n = pick(0, 3);  // a quarter of the lines go as they are
    for (int i = 0; i < n; ++i) line = mutate(line);
    for (char& c : line) {
      if (c == '\n') c = ' ';  // one request per line: the reply count stays exact
    }
    if (line.empty() || line == "\r") line = "x";
    if (line.size() > 60000) line.resize(60000);  // under the 64 KiB line limit
    return line;
  }

 private:
  int pick(int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng_); }
  template <typename T>
  const T& one_of(const std::vector<T>& v) { return v[static_cast<std::size_t>(pick(0, static_cast<int>(v.size()) - 1))]; }

  std::string value() {
    static const std::vector<std::string> values = {
        "0", "-0", "-0.0", "1", "-1", "0.5", "120", "1e308", "1e309", "-1e400", "4.9e-324", "1e-400",
        "18446744073709551615", "18446744073709551616", "-9223372036854775809", "true", "false", "null",
        "\"\"", "\"G54\"", "\"G60\"", "\"X\"", "\"+\"", "\"\\u0000\"", "\"\\ud800\"", "\"\\u00e9\"", "[]", "{}",
        "[1,[2,[3]]]", "{\"a\":{\"b\":{}}}", "\"/nonexistent/x.ngc\""};
    return one_of(values);
  }

  std::string base(long long id) {
    const std::string sid = std::to_string(id);
    switch (pick(0, 15)) {
      case 0: case 1: case 2: return "{\"id\":" + sid + ",\"method\":\"status\"}";
      case 3: return "{\"id\":" + sid + ",\"method\":\"set_offset\",\"params\":{\"offset\":\"G5" + std::to_string(pick(5, 9)) +
                     "\",\"x\":" + value() + "}}";
      case 4: return "{\"id\":" + sid + ",\"method\":\"subscribe\",\"params\":{\"rate_hz\":" + std::to_string(pick(0, 60)) + "}}";
      case 5: return "{\"id\":" + sid + ",\"method\":\"jog_keepalive\"}";
      case 6: return "{\"jsonrpc\":\"2.0\",\"id\":\"s" + sid + "\",\"method\":\"status\",\"params\":{}}";
      case 7: return "{\"id\":" + sid + ",\"method\":\"" + one_of(std::vector<std::string>{"teleport", "Status", "", "status ", "\\u0073tatus"}) + "\"}";
      case 8: return "{\"id\":" + sid + ",\"method\":\"status\",\"params\":{\"x\":" + value() + "}}";
      case 9: return "{\"id\":" + sid + ",\"method\":\"subscribe\",\"params\":{\"rate_hz\":" + value() + "}}";
      case 10: return "{\"id\":" + sid + ",\"method\":\"" + one_of(std::vector<std::string>{"pause", "resume", "stop", "estop", "reset", "jog_stop"}) + "\"}";
      case 11: return "{\"id\":" + sid + ",\"method\":\"override\",\"params\":{\"percent\":" + value() + "}}";
      case 12: return "{\"id\":" + sid + ",\"method\":\"jog\",\"params\":{\"axis\":\"X\",\"distance\":" + value() + "}}";
      case 13: return "{\"id\":" + sid + ",\"method\":\"mdi\",\"params\":{\"text\":" + value() + "}}";
      case 14: return "{\"id\":" + sid + ",\"method\":\"touch_off\",\"params\":{\"axis\":\"Z\",\"value\":" + value() + "}}";
      default: return "{\"id\":" + sid + ",\"method\":\"run\",\"params\":{\"file\":" + value() + "}}";
    }
  }

  std::string mutate(std::string s) {
    if (s.empty()) return value();
    const auto at = [&] { return static_cast<std::size_t>(pick(0, static_cast<int>(s.size()) - 1)); };
    switch (pick(0, 9)) {
      case 0: s[at()] ^= static_cast<char>(1 << pick(0, 7)); return s;                   // bit flip
      case 1: s.insert(at(), 1, static_cast<char>(pick(0, 255))); return s;              // a random byte
      case 2: s.erase(at(), static_cast<std::size_t>(pick(1, 4))); return s;             // delete
      case 3: s.resize(at()); return s;                                                  // truncate
      case 4: {  // a value of another type (or a huge number) in place of the first number or string
        const auto c = s.find(':');
        if (c == std::string::npos) return s + value();
        auto e = s.find_first_of(",}", c + 1);
        if (e == std::string::npos) e = s.size();
        return s.substr(0, c + 1) + value() + s.substr(e);
      }
      case 5: {  // an unknown method
        const auto m = s.find("\"method\":\"");
        if (m == std::string::npos) return s;
        return s.substr(0, m + 10) + one_of(std::vector<std::string>{"warp", "statu", "STATUS", "run_", "\\\"", "jog_keepalive"}) +
               s.substr(s.find('"', m + 10) == std::string::npos ? s.size() : s.find('"', m + 10));
      }
      case 6: {  // a repeated key
        const auto b = s.rfind('}');
        if (b == std::string::npos) return s;
        return s.substr(0, b) + one_of(std::vector<std::string>{",\"id\":7", ",\"method\":\"status\"", ",\"params\":{}", ",\"x\":1"}) +
               s.substr(b);
      }
      case 7: {  // nesting
        const int depth = pick(1, 3) == 1 ? pick(500, 5000) : pick(1, 64);
        std::string open, close;
        for (int i = 0; i < depth; ++i) {
          open += pick(0, 1) ? "[" : "{\"a\":";
          close.insert(0, open.back() == '[' ? "]" : "}");
        }
        const auto c = s.find(':');
        if (c == std::string::npos) return open + close;
        auto e = s.find_first_of(",}", c + 1);
        if (e == std::string::npos) e = s.size();
        return s.substr(0, c + 1) + open + s.substr(c + 1, e - c - 1) + close + s.substr(e);
      }
      case 8: return s + s;  // two objects on one line
      default: {             // a chunk duplicated
        const auto a = at();
        return s.insert(a, s.substr(a, static_cast<std::size_t>(pick(1, 16))));
      }
    }
  }

  std::mt19937_64 rng_;
};

// ------------------------------------------------------------ the test

struct StormFigures {
  long long sent = 0, filtered = 0, replies = 0, checked_ids = 0, errors = 0, notifications = 0;
  std::vector<std::string> failures;
};

bool well_formed_reply(const json& r) {
  if (!r.is_object() || !r.contains("id") || r.size() != 2) return false;
  if (r.contains("result")) return true;
  if (!r.contains("error") || !r["error"].is_object()) return false;
  const json& e = r["error"];
  return e.contains("code") && e["code"].is_number_integer() && e.contains("message") && e["message"].is_string();
}

void storm(const std::string& socket, int thread, bool filter, int max_requests, const std::atomic<bool>& stop, StormFigures& f) {
  LineSocket s(socket);
  if (!s.ok()) {
    f.failures.push_back("client " + std::to_string(thread) + " could not connect");
    return;
  }
  Mutator mut(0x9e3779b97f4a7c15ull * static_cast<std::uint64_t>(thread + 1) + (filter ? 0 : 1));
  long long id = static_cast<long long>(thread + 1) * 1000000;
  int notifications = 0;
  while (!stop.load() && f.sent < max_requests && f.failures.empty()) {
    std::vector<std::pair<std::string, Reading>> batch;
    std::string out;
    while (static_cast<int>(batch.size()) < kBatch) {
      std::string line = mut.next(++id);
      Reading r = read_as_server(line);
      if (filter && changes_the_program(r)) {
        ++f.filtered;
        continue;
      }
      out += line + "\n";
      batch.emplace_back(std::move(line), std::move(r));
    }
    if (!s.send_all(out)) {
      f.failures.push_back("client " + std::to_string(thread) + ": the server closed the connection while we sent");
      return;
    }
    f.sent += static_cast<long long>(batch.size());
    // Replies are matched by id: a reply that comes later (a jog, a run: only in the
    // unfiltered pass) may be overtaken by the next lines' replies.
    std::vector<bool> matched(batch.size(), false);
    for (std::size_t k = 0; k < batch.size(); ++k) {
      json reply;
      std::string raw;
      if (!s.read_reply(reply, raw, 10.0, &notifications)) {
        f.failures.push_back("client " + std::to_string(thread) + ": no reply within 10 s to: " + batch[k].first.substr(0, 300));
        return;
      }
      ++f.replies;
      if (!well_formed_reply(reply)) {
        f.failures.push_back("malformed reply " + raw.substr(0, 300));
        return;
      }
      if (reply.contains("error")) {
        ++f.errors;
        if (reply["error"]["code"] == rpc::kInternalError) {
          f.failures.push_back("internal error " + raw.substr(0, 300));
          return;
        }
      }
      // the first unanswered line whose id it carries, else the first whose id is unknown
      std::size_t hit = batch.size();
      for (std::size_t i = 0; i < batch.size() && hit == batch.size(); ++i) {
        if (!matched[i] && batch[i].second.id_known && batch[i].second.id == reply["id"]) hit = i;
      }
      if (hit < batch.size()) {
        ++f.checked_ids;
      } else {
        for (std::size_t i = 0; i < batch.size() && hit == batch.size(); ++i) {
          if (!matched[i] && !batch[i].second.id_known) hit = i;
        }
      }
      if (hit == batch.size()) {
        std::string lines;
        for (std::size_t i = 0; i < batch.size(); ++i) lines += "\n  " + batch[i].first.substr(0, 200);
        f.failures.push_back("reply " + raw.substr(0, 300) + " carries no id of the lines sent:" + lines);
        return;
      }
      matched[hit] = true;
    }
  }
  f.notifications = notifications;
}

TEST(ProtocolFuzzLive, MutatedRequestsFromFourClientsWhileAProgramRuns) {
  ServicePair p("proto-fuzz");
  ASSERT_TRUE(p.start("real")) << p.host_log();
  const int host_pid = p.host_pid();
  const std::string prog = zigzag_program(p.dir(), 4, 16.0, 900.0);  // ~5 s at real clock
  const json run = p.call("run", {{"file", prog}});
  ASSERT_TRUE(run.contains("result")) << run.dump();

  std::atomic<bool> stop{false};
  std::vector<StormFigures> figures(kStormThreads);
  std::vector<std::thread> threads;
  const auto t0 = Clock::now();
  for (int t = 0; t < kStormThreads; ++t) threads.emplace_back([&, t] { storm(p.socket(), t, true, kMaxRequestsPerThread, stop, figures[static_cast<std::size_t>(t)]); });

  // status, always answered during the storm, on its own connection
  int status_asked = 0, status_answered = 0;
  double status_max_ms = 0.0;
  std::vector<std::string> status_failures;
  {
    LineSocket s(p.socket());
    ASSERT_TRUE(s.ok());
    int notifications = 0;
    while (std::chrono::duration<double>(Clock::now() - t0).count() < kStormSeconds) {
      const auto a = Clock::now();
      ++status_asked;
      const std::string id = std::to_string(status_asked);
      if (!s.send_all("{\"id\":" + id + ",\"method\":\"status\"}\n")) {
        status_failures.push_back("status connection closed");
        break;
      }
      json r;
      std::string raw;
      if (!s.read_reply(r, raw, 5.0, &notifications)) {
        status_failures.push_back("status " + id + " not answered within 5 s");
        break;
      }
      if (r["id"] != status_asked || !r.contains("result") || !r["result"].contains("state")) {
        status_failures.push_back("status " + id + " answered with " + raw.substr(0, 300));
        break;
      }
      ++status_answered;
      status_max_ms = std::max(status_max_ms, std::chrono::duration<double, std::milli>(Clock::now() - a).count());
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
  }
  stop = true;
  for (auto& t : threads) t.join();
  const double storm_s = std::chrono::duration<double>(Clock::now() - t0).count();

  StormFigures total;
  for (const auto& f : figures) {
    total.sent += f.sent;
    total.filtered += f.filtered;
    total.replies += f.replies;
    total.checked_ids += f.checked_ids;
    total.errors += f.errors;
    total.notifications += f.notifications;
    for (const auto& x : f.failures) ADD_FAILURE() << x;
  }
  for (const auto& x : status_failures) ADD_FAILURE() << x;
  EXPECT_EQ(total.replies, total.sent) << "every request line gets its reply";
  EXPECT_GT(total.sent, 1000) << "the storm was a storm";
  EXPECT_EQ(status_answered, status_asked);

  // The host is the same process and still answers; the program completed.
  EXPECT_EQ(p.host_pid(), host_pid);
  EXPECT_EQ(kill(host_pid, 0), 0) << "pcnc-host is gone: " << p.host_log();
  const json s = p.wait_status([](const json& x) { return x["state"] == "IDLE" && x["last_job"].is_object() && !x["job"]["active"].get<bool>(); }, 30);
  ASSERT_TRUE(s["last_job"].is_object()) << s.dump();
  EXPECT_EQ(s["last_job"]["end"], "completed") << s.dump();

  std::printf("[ figures ] storm %.1f s, %d clients: %lld requests sent (%lld filtered out as program-changing), %lld replies "
              "(%lld ids checked, %lld errors), %lld notifications; status %d/%d answered, slowest %.1f ms; program %s in "
              "%.2f s, underruns %s\n",
              storm_s, kStormThreads, total.sent, total.filtered, total.replies, total.checked_ids, total.errors,
              total.notifications, status_answered, status_asked, status_max_ms,
              s["last_job"]["end"].get<std::string>().c_str(), s["last_job"]["wall_time_s"].get<double>(),
              s["last_job"]["underruns"].dump().c_str());

  // Second pass, on the idle machine: the same storm unfiltered (run, pause, stop, estop,
  // reset, override and jog included), 1.5 s. The host stays up and answers every line;
  // afterwards the machine can be brought back to IDLE.
  std::atomic<bool> stop2{false};
  std::vector<StormFigures> figures2(kStormThreads);
  std::vector<std::thread> threads2;
  for (int t = 0; t < kStormThreads; ++t) {
    threads2.emplace_back([&, t] { storm(p.socket(), t, false, 1000, stop2, figures2[static_cast<std::size_t>(t)]); });
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  stop2 = true;
  for (auto& t : threads2) t.join();
  StormFigures total2;
  for (const auto& f : figures2) {
    total2.sent += f.sent;
    total2.replies += f.replies;
    total2.errors += f.errors;
    for (const auto& x : f.failures) ADD_FAILURE() << "unfiltered pass: " << x;
  }
  EXPECT_EQ(total2.replies, total2.sent);
  EXPECT_EQ(kill(host_pid, 0), 0) << "pcnc-host is gone: " << p.host_log();
  p.call("stop");
  p.wait_status([](const json& x) { return !x["job"]["active"].get<bool>() && x["state"] != "RUNNING" && x["state"] != "STOPPING" &&
                                           x["state"] != "JOGGING"; }, 30);
  p.call("reset");
  const json after = p.wait_status([](const json& x) { return x["state"] == "IDLE"; }, 30);
  EXPECT_EQ(after["state"], "IDLE") << after.dump();
  std::printf("[ figures ] unfiltered pass on the idle machine: %lld requests, %lld replies (%lld errors); ends %s\n", total2.sent,
              total2.replies, total2.errors, after["state"].get<std::string>().c_str());
}

}  // namespace
}  // namespace pcnc::test
