// control_server.hpp — the control socket's transport: a Unix-domain stream socket, one
// poll() event loop in one thread serving many clients, lines in and lines out.
//
// It knows nothing about JSON or the machine: it checks each peer's uid (SO_PEERCRED), cuts
// the input into lines with a bounded buffer per client (a line over the limit is answered
// with `too_long_reply` and the client is dropped), queues output per client with a bound
// (a client that reads slowly is throttled: its requests are not read while its replies pile
// up; one that does not read at all is dropped when its queue makes no progress for
// stall_timeout_s or exceeds the hard limit), and never blocks on any client: all sockets
// are non-blocking. Connection limits: max_clients normal connections; an idle one (no
// request and no reply pending for idle_timeout_s, and not busy) is closed; when the table is
// full a few reserve connections are still accepted, each for one request that is served
// only when it is stop, e-stop or status (ServerLimits). Other threads hand work to the loop
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
  std::size_t max_clients = 64;                // connections served normally at once
  // Beyond max_clients, up to this many more connections are accepted to read one request
  // each: a stop, e-stop or status is served (reserve_allows), anything else refused; then
  // the connection is closed. So a full table never locks out stop and e-stop.
  std::size_t reserve_clients = 8;
  double reserve_timeout_s = 2.0;              // a reserve connection that sends no line this long is closed
  double idle_timeout_s = 60.0;                // no request, no reply pending, not busy: closed (0: never)
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
  // A reserve connection's request: true when it may be served (stop, e-stop, status).
  std::function<bool(std::string_view line)> reserve_allows;
  std::function<std::string(std::size_t max_clients)> full_reply;   // the request is refused: table full
  std::function<std::string(double idle_s)> idle_reply;             // sent before an idle client is closed
  // A client that waits for something (a subscription, a delayed reply) is not idle.
  std::function<bool(ClientId)> busy;
};

/// The peer (SO_PEERCRED's pid, uid, primary gid) is a member of `group`: its primary group,
/// or one of its process's supplementary groups (/proc/<pid>/status; without /proc, those of
/// its user in the group database).
bool peer_in_group(pid_t pid, uid_t uid, gid_t gid, gid_t group);

class ControlServer {
 public:
  /// Creates the socket at `path` with file mode `mode` (e.g. 0600) and, when `group` is not
  /// -1, that group (else the server's). A stale socket file (no one listening) is replaced; a
  /// live one (another server) is an error. Throws std::runtime_error with the reason.
  ControlServer(std::string path, int mode, gid_t group, ServerLimits limits, ServerHandlers handlers);
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
  std::uint64_t idle_closed() const { return idle_closed_; }

 private:
  struct Client {
    int fd = -1;
    uid_t uid = 0;
    pid_t pid = 0;
    std::string in;
    std::string out;
    std::size_t out_sent = 0;  // bytes of `out` already written
    bool eof = false;          // the peer closed its side: answer its lines, then close
    bool reserve = false;      // accepted beyond max_clients: one request (stop/estop/status), then closed
    std::chrono::steady_clock::time_point since{};     // connected
    std::chrono::steady_clock::time_point activity{};  // last request bytes read or reply bytes sent
    std::chrono::steady_clock::time_point progress{};  // last time its output queue moved or was empty
  };

  void accept_clients();
  void read_client(ClientId id, Client& c);
  void flush_client(ClientId id, Client& c);
  void drop(ClientId id, const char* why);
  void run_posted();
  void handle_lines(ClientId id, Client& c);
  void reserve_line(ClientId id, Client& c);
  void expire_clients();
  std::size_t reserve_count() const;
  bool peer_allowed(uid_t uid, gid_t gid, pid_t pid) const;

  std::string path_;
  int mode_;
  gid_t group_;  // members may connect when the mode grants the group read and write
  ServerLimits limits_;
  ServerHandlers handlers_;
  int listen_fd_ = -1;
  int wake_fd_ = -1;
  std::map<ClientId, Client> clients_;
  std::vector<ClientId> to_drop_;
  ClientId next_id_ = 1;
  std::mutex posted_mutex_;
  std::vector<std::function<void()>> posted_;
  std::atomic<std::uint64_t> refused_{0}, dropped_{0}, idle_closed_{0};
};

}  // namespace pcnc
