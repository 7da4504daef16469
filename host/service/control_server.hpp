// control_server.hpp — the control socket's transport: a Unix-domain stream socket, one
// poll() event loop in one thread serving many clients, lines in and lines out.
//
// It knows nothing about JSON or the machine: it checks each peer's uid (SO_PEERCRED), cuts
// the input into lines with a bounded buffer per client (a line over the limit is answered
// with `too_long_reply` and the client is dropped), queues output per client with a bound
// (a client that reads slowly is throttled: its requests are not read while its replies pile
// up; one that does not read at all is dropped when its queue makes no progress for
// stall_timeout_s or exceeds the hard limit), and never blocks on any client: all sockets
// are non-blocking. Other threads hand work to the loop
// with post(), which wakes it through an eventfd.
//
// May include: the C++ and POSIX libraries only (no JSON, nothing of the machine).
#pragma once

#include <sys/types.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <mutex>
#include <string>
#include <string_view>
#include <vector>

namespace pcnc {

using ClientId = std::uint64_t;

struct ServerLimits {
  std::size_t max_line_bytes = 64 * 1024;      // a request line longer than this: error + disconnect
  std::size_t max_output_bytes = 1024 * 1024;  // queued replies beyond this: the client is dropped
  std::size_t throttle_bytes = 256 * 1024;     // above this, the client's requests wait (not read)
  double stall_timeout_s = 5.0;                // output pending without progress this long: dropped
  std::size_t max_clients = 64;                // further connections are refused with a message
  std::size_t max_lines_per_turn = 256;        // lines handled per client per loop turn (fairness)
};

struct ServerHandlers {
  std::function<void(ClientId)> on_connect;
  std::function<void(ClientId, std::string_view line)> on_line;  // without the '\n'
  std::function<void(ClientId)> on_disconnect;
  std::function<void()> on_tick;  // every tick period, on the loop thread
  // Replies sent before dropping a client (each a complete line, or empty for none).
  std::function<std::string(std::size_t limit)> too_long_reply;
  std::function<std::string(uid_t uid)> refused_reply;
};

class ControlServer {
 public:
  /// Creates the socket at `path` with file mode `mode` (e.g. 0600). A stale socket file (no
  /// one listening) is replaced; a live one (another server) is an error. Throws
  /// std::runtime_error with the reason.
  ControlServer(std::string path, int mode, ServerLimits limits, ServerHandlers handlers);
  ~ControlServer();  // closes every client and removes the socket file
  ControlServer(const ControlServer&) = delete;
  ControlServer& operator=(const ControlServer&) = delete;

  /// Runs the loop on the calling thread until `stop` is true (checked every tick).
  void run(const std::atomic<bool>& stop, double tick_s);

  // ---- loop thread only ----
  /// Queues a complete line ('\n'-terminated) for a client; false if it is gone or was
  /// dropped because its queue overflowed.
  bool send(ClientId client, std::string_view line);
  void disconnect(ClientId client);
  std::vector<ClientId> clients() const;
  uid_t peer_uid(ClientId client) const;

  // ---- any thread ----
  /// Runs `fn` on the loop thread soon (wakes the loop).
  void post(std::function<void()> fn);

  const std::string& path() const { return path_; }
  /// Counters for logs and tests.
  std::uint64_t refused_connections() const { return refused_; }
  std::uint64_t dropped_clients() const { return dropped_; }

 private:
  struct Client {
    int fd = -1;
    uid_t uid = 0;
    pid_t pid = 0;
    std::string in;
    std::string out;
    std::size_t out_sent = 0;  // bytes of `out` already written
    bool eof = false;          // the peer closed its side: answer its lines, then close
    std::chrono::steady_clock::time_point progress{};  // last time its output queue moved or was empty
  };

  void accept_clients();
  void read_client(ClientId id, Client& c);
  void flush_client(ClientId id, Client& c);
  void drop(ClientId id, const char* why);
  void run_posted();
  bool peer_allowed(uid_t uid, gid_t gid) const;

  std::string path_;
  int mode_;
  ServerLimits limits_;
  ServerHandlers handlers_;
  int listen_fd_ = -1;
  int wake_fd_ = -1;
  std::map<ClientId, Client> clients_;
  std::vector<ClientId> to_drop_;
  ClientId next_id_ = 1;
  std::mutex posted_mutex_;
  std::vector<std::function<void()>> posted_;
  std::atomic<std::uint64_t> refused_{0}, dropped_{0};
};

}  // namespace pcnc
