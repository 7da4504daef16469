// control_server.cpp — the Unix-socket event loop (see control_server.hpp).
#include "service/control_server.hpp"

#include <fcntl.h>
#include <poll.h>
#include <spdlog/spdlog.h>
#include <sys/eventfd.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>
#include <grp.h>
#include <pwd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace pcnc {
namespace {

std::runtime_error sys_error(const std::string& what) { return std::runtime_error(what + ": " + std::strerror(errno)); }

sockaddr_un make_address(const std::string& path) {
  sockaddr_un addr{};
  addr.sun_family = AF_UNIX;
  if (path.empty() || path.size() >= sizeof addr.sun_path) {
    throw std::runtime_error("socket path '" + path + "' is empty or longer than " + std::to_string(sizeof addr.sun_path - 1) +
                             " bytes");
  }
  std::memcpy(addr.sun_path, path.c_str(), path.size() + 1);
  return addr;
}

// A socket file left by a server that died is removed; one with a live server is an error.
void clear_stale_socket(const std::string& path, const sockaddr_un& addr) {
  struct stat st {};
  if (lstat(path.c_str(), &st) != 0) return;
  if (!S_ISSOCK(st.st_mode)) throw std::runtime_error("'" + path + "' exists and is not a socket; refusing to replace it");
  const int probe = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (probe >= 0) {
    const bool live = connect(probe, reinterpret_cast<const sockaddr*>(&addr), sizeof addr) == 0;
    close(probe);
    if (live) throw std::runtime_error("another server is already listening on '" + path + "'");
  }
  if (unlink(path.c_str()) != 0 && errno != ENOENT) throw sys_error("cannot remove stale socket '" + path + "'");
  spdlog::info("removed stale control socket {}", path);
}

// The loop must outlive anything a handler throws: one request, tick or posted job failing
// is logged, and the loop (every other client, the machine's commands) goes on.
template <typename F>
void guarded(const char* what, F&& f) {
  try {
    f();
  } catch (const std::exception& e) {
    spdlog::error("control socket: {} failed: {}; the service goes on", what, e.what());
  } catch (...) {
    spdlog::error("control socket: {} failed (unknown exception); the service goes on", what);
  }
}

}  // namespace

ControlServer::ControlServer(std::string path, int mode, gid_t group, ServerLimits limits, ServerHandlers handlers)
    : path_(std::move(path)),
      mode_(mode),
      group_(group == static_cast<gid_t>(-1) ? getegid() : group),
      limits_(limits),
      handlers_(std::move(handlers)) {
  const sockaddr_un addr = make_address(path_);
  clear_stale_socket(path_, addr);
  listen_fd_ = socket(AF_UNIX, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  if (listen_fd_ < 0) throw sys_error("socket");
  if (bind(listen_fd_, reinterpret_cast<const sockaddr*>(&addr), sizeof addr) != 0) {
    const auto e = sys_error("cannot bind control socket '" + path_ + "'");
    close(listen_fd_);
    throw e;
  }
  // bind() used the umask; set the configured mode and group before anyone can be accepted.
  if (chmod(path_.c_str(), static_cast<mode_t>(mode_)) != 0 ||
      (group != static_cast<gid_t>(-1) && lchown(path_.c_str(), static_cast<uid_t>(-1), group) != 0) ||
      listen(listen_fd_, 16) != 0) {
    const auto e = sys_error("cannot set up control socket '" + path_ + "'");
    close(listen_fd_);
    unlink(path_.c_str());
    throw e;
  }
  wake_fd_ = eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
  if (wake_fd_ < 0) {
    const auto e = sys_error("eventfd");
    close(listen_fd_);
    unlink(path_.c_str());
    throw e;
  }
}

ControlServer::~ControlServer() {
  for (auto& [id, c] : clients_) close(c.fd);
  clients_.clear();
  if (listen_fd_ >= 0) close(listen_fd_);
  if (wake_fd_ >= 0) close(wake_fd_);
  unlink(path_.c_str());
}

bool ControlServer::peer_allowed(uid_t uid, gid_t gid, pid_t pid) const {
  if (uid == geteuid()) return true;
  // A socket opened to the group (e.g. 0660) admits members of its group: the peer's primary
  // group or any of its supplementary groups.
  return (mode_ & 0060) == 0060 && peer_in_group(pid, uid, gid, group_);
}

bool peer_in_group(pid_t pid, uid_t uid, gid_t gid, gid_t group) {
  if (gid == group) return true;
  // The peer process's own supplementary groups (what the kernel checks for its file
  // access); its effective uid must still be the one SO_PEERCRED gave (pid not reused).
  std::ifstream status("/proc/" + std::to_string(pid) + "/status");
  std::string line;
  bool uid_matches = false, have_groups = false, member = false;
  while (status && std::getline(status, line)) {
    std::istringstream fields(line);
    std::string key;
    fields >> key;
    if (key == "Uid:") {
      unsigned long real = 0, effective = 0;
      fields >> real >> effective;
      uid_matches = fields && effective == uid;
    } else if (key == "Groups:") {
      have_groups = true;
      unsigned long g = 0;
      while (fields >> g) member = member || g == group;
    }
  }
  if (have_groups) return uid_matches && member;
  // No /proc: the groups of the peer's user in the group database.
  const passwd* pw = getpwuid(uid);
  if (!pw) return false;
  int n = 64;
  std::vector<gid_t> groups(static_cast<std::size_t>(n));
  if (getgrouplist(pw->pw_name, gid, groups.data(), &n) < 0) {
    groups.resize(static_cast<std::size_t>(n));
    if (getgrouplist(pw->pw_name, gid, groups.data(), &n) < 0) return false;
  }
  groups.resize(static_cast<std::size_t>(n));
  return std::find(groups.begin(), groups.end(), group) != groups.end();
}

void ControlServer::accept_clients() {
  for (;;) {
    const int fd = accept4(listen_fd_, nullptr, nullptr, SOCK_NONBLOCK | SOCK_CLOEXEC);
    if (fd < 0) {
      if (errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR) spdlog::warn("control socket accept: {}", std::strerror(errno));
      return;
    }
    ucred cred{};
    socklen_t len = sizeof cred;
    if (getsockopt(fd, SOL_SOCKET, SO_PEERCRED, &cred, &len) != 0) {
      spdlog::warn("control socket: cannot read peer credentials ({}); connection refused", std::strerror(errno));
      close(fd);
      ++refused_;
      continue;
    }
    if (!peer_allowed(cred.uid, cred.gid, cred.pid)) {
      spdlog::warn("control socket: refused connection from uid {} gid {} pid {}: only uid {}{} may connect", cred.uid, cred.gid,
                   cred.pid, geteuid(), (mode_ & 0060) == 0060 ? " and members of group " + std::to_string(group_) : std::string());
      if (handlers_.refused_reply) {
        const std::string msg = handlers_.refused_reply(cred.uid);
        (void)!::send(fd, msg.data(), msg.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
      }
      close(fd);
      ++refused_;
      continue;
    }
    const std::size_t reserves = reserve_count();
    const bool full = clients_.size() - reserves >= limits_.max_clients;
    if (full && reserves >= limits_.reserve_clients) {
      spdlog::warn("control socket: refused connection from pid {}: {} clients and {} reserve connections already", cred.pid,
                   clients_.size() - reserves, reserves);
      if (handlers_.full_reply) {
        const std::string msg = handlers_.full_reply(limits_.max_clients);
        (void)!::send(fd, msg.data(), msg.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
      }
      close(fd);
      ++refused_;
      continue;
    }
    const ClientId id = next_id_++;
    Client c;
    c.fd = fd;
    c.progress = c.since = c.activity = std::chrono::steady_clock::now();
    c.uid = cred.uid;
    c.pid = cred.pid;
    c.reserve = full;
    if (full) spdlog::warn("control socket: {} clients connected; pid {} gets a reserve connection (stop, estop, status only)",
                           limits_.max_clients, cred.pid);
    clients_.emplace(id, std::move(c));
    spdlog::debug("control socket: client {} connected (pid {})", id, cred.pid);
    if (handlers_.on_connect) guarded("a connect", [&] { handlers_.on_connect(id); });
  }
}

void ControlServer::read_client(ClientId id, Client& c) {
  char buf[64 * 1024];
  const ssize_t n = recv(c.fd, buf, sizeof buf, MSG_DONTWAIT);
  if (n == 0) {
    c.eof = true;  // answer what it sent, then close
    return;
  }
  if (n < 0) {
    if (errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR) drop(id, std::strerror(errno));
    return;
  }
  c.in.append(buf, static_cast<std::size_t>(n));
  c.activity = std::chrono::steady_clock::now();
}

void ControlServer::flush_client(ClientId id, Client& c) {
  if (c.out_sent == c.out.size()) c.progress = std::chrono::steady_clock::now();
  while (c.out_sent < c.out.size()) {
    const ssize_t n = ::send(c.fd, c.out.data() + c.out_sent, c.out.size() - c.out_sent, MSG_NOSIGNAL | MSG_DONTWAIT);
    if (n < 0) {
      if (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR) break;
      drop(id, std::strerror(errno));
      return;
    }
    c.out_sent += static_cast<std::size_t>(n);
    c.progress = c.activity = std::chrono::steady_clock::now();
  }
  if (c.out_sent == c.out.size()) {
    c.out.clear();
    c.out_sent = 0;
  } else if (c.out_sent > c.out.size() / 2) {
    c.out.erase(0, c.out_sent);
    c.out_sent = 0;
  }
}

bool ControlServer::send(ClientId client, std::string_view line) {
  auto it = clients_.find(client);
  if (it == clients_.end() || it->second.fd < 0) return false;
  Client& c = it->second;
  if (c.out_sent == c.out.size()) c.progress = std::chrono::steady_clock::now();  // the stall clock starts now
  c.out.append(line);
  if (c.out.size() - c.out_sent > limits_.max_output_bytes) {
    spdlog::warn("control socket: dropping client {} (pid {}): more than {} bytes of replies queued, it does not read",
                 client, c.pid, limits_.max_output_bytes);
    drop(client, nullptr);
    return false;
  }
  flush_client(client, c);
  return it->second.fd >= 0;
}

void ControlServer::disconnect(ClientId client) {
  auto it = clients_.find(client);
  if (it == clients_.end() || it->second.fd < 0) return;
  flush_client(client, it->second);
  drop(client, nullptr);
}

void ControlServer::drop(ClientId id, const char* why) {
  auto it = clients_.find(id);
  if (it == clients_.end() || it->second.fd < 0) return;
  if (why) spdlog::info("control socket: client {} dropped: {}", id, why);
  close(it->second.fd);
  it->second.fd = -1;  // erased at the end of the loop turn (callers may hold references)
  it->second.in.clear();
  it->second.out.clear();
  to_drop_.push_back(id);
  ++dropped_;
}

std::vector<ClientId> ControlServer::clients() const {
  std::vector<ClientId> ids;
  for (const auto& [id, c] : clients_) {
    if (c.fd >= 0) ids.push_back(id);
  }
  return ids;
}

uid_t ControlServer::peer_uid(ClientId client) const {
  auto it = clients_.find(client);
  return it == clients_.end() ? static_cast<uid_t>(-1) : it->second.uid;
}

void ControlServer::post(std::function<void()> fn) {
  {
    std::lock_guard<std::mutex> lock(posted_mutex_);
    posted_.push_back(std::move(fn));
  }
  const std::uint64_t one = 1;
  (void)!write(wake_fd_, &one, sizeof one);
}

void ControlServer::run_posted() {
  std::uint64_t count = 0;
  (void)!read(wake_fd_, &count, sizeof count);
  std::vector<std::function<void()>> work;
  {
    std::lock_guard<std::mutex> lock(posted_mutex_);
    work.swap(posted_);
  }
  for (auto& fn : work) guarded("a posted reply or event", fn);
}

std::size_t ControlServer::reserve_count() const {
  std::size_t n = 0;
  for (const auto& [id, c] : clients_) n += c.fd >= 0 && c.reserve;
  return n;
}

void ControlServer::handle_lines(ClientId id, Client& c) {
  if (c.fd >= 0 && c.reserve) return reserve_line(id, c);
  std::size_t handled = 0;
  std::size_t start = 0;
  while (c.fd >= 0 && handled < limits_.max_lines_per_turn && c.out.size() - c.out_sent <= limits_.throttle_bytes) {
    const std::size_t nl = c.in.find('\n', start);
    const std::size_t len = (nl == std::string::npos ? c.in.size() : nl) - start;
    if (len > limits_.max_line_bytes) {
      spdlog::warn("control socket: client {} (pid {}) sent a line longer than {} bytes; disconnecting", id, c.pid,
                   limits_.max_line_bytes);
      if (handlers_.too_long_reply) c.out.append(handlers_.too_long_reply(limits_.max_line_bytes));
      disconnect(id);
      break;
    }
    if (nl == std::string::npos) break;
    std::string_view line(c.in.data() + start, len);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    start = nl + 1;
    ++handled;
    if (!line.empty() && handlers_.on_line) guarded("a request", [&] { handlers_.on_line(id, line); });
  }
  if (c.fd >= 0 && start > 0) c.in.erase(0, start);
  if (c.fd >= 0 && c.eof && c.in.find('\n') == std::string::npos) disconnect(id);
}

// A reserve connection (the table was full): its first line is served when it is stop,
// e-stop or status, else refused; either way the connection is then closed.
void ControlServer::reserve_line(ClientId id, Client& c) {
  const std::size_t nl = c.in.find('\n');
  if (nl == std::string::npos) {
    if (c.in.size() > limits_.max_line_bytes || c.eof) {
      if (!c.eof && handlers_.too_long_reply) c.out.append(handlers_.too_long_reply(limits_.max_line_bytes));
      disconnect(id);
    }
    return;
  }
  std::string_view line(c.in.data(), nl);
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
  const std::string request(line);
  c.in.clear();
  if (handlers_.reserve_allows && handlers_.reserve_allows(request)) {
    if (handlers_.on_line) guarded("a request", [&] { handlers_.on_line(id, request); });
  } else {
    spdlog::warn("control socket: {} clients connected; refused a request other than stop, estop or status from pid {}",
                 limits_.max_clients, c.pid);
    if (handlers_.full_reply) c.out.append(handlers_.full_reply(limits_.max_clients));
  }
  disconnect(id);  // flushes the reply first
}

// Clients that do not read their replies, idle clients and silent reserve connections are
// closed.
void ControlServer::expire_clients() {
  using clock = std::chrono::steady_clock;
  const auto now = clock::now();
  const auto secs = [](double s) { return std::chrono::duration_cast<clock::duration>(std::chrono::duration<double>(s)); };
  for (auto& [id, c] : clients_) {
    if (c.fd < 0) continue;
    // A client whose replies have not moved for the stall timeout does not read: drop it.
    if (c.out_sent < c.out.size() && now - c.progress > secs(limits_.stall_timeout_s)) {
      spdlog::warn("control socket: dropping client {} (pid {}): it does not read its replies ({} bytes pending for {:.1f} s)", id,
                   c.pid, c.out.size() - c.out_sent, limits_.stall_timeout_s);
      drop(id, nullptr);
      continue;
    }
    if (c.reserve) {
      if (now - c.since > secs(limits_.reserve_timeout_s)) {
        spdlog::info("control socket: reserve connection {} (pid {}) sent no request in {:.1f} s; closed", id, c.pid,
                     limits_.reserve_timeout_s);
        drop(id, nullptr);
      }
      continue;
    }
    if (limits_.idle_timeout_s <= 0.0 || c.out_sent < c.out.size()) continue;  // (a partial line is no activity)
    if (now - c.activity <= secs(limits_.idle_timeout_s)) continue;
    if (handlers_.busy && handlers_.busy(id)) {
      c.activity = now;  // waiting for something it asked for is not idleness
      continue;
    }
    spdlog::info("control socket: client {} (pid {}) idle for {:.1f} s; closed", id, c.pid, limits_.idle_timeout_s);
    if (handlers_.idle_reply) c.out.append(handlers_.idle_reply(limits_.idle_timeout_s));
    ++idle_closed_;
    disconnect(id);
  }
}

void ControlServer::run(const std::atomic<bool>& stop, double tick_s) {
  using clock = std::chrono::steady_clock;
  const auto tick = std::chrono::duration_cast<clock::duration>(std::chrono::duration<double>(tick_s));
  auto next_tick = clock::now() + tick;
  std::vector<pollfd> fds;
  std::vector<ClientId> ids;
  while (!stop.load()) {
    fds.clear();
    ids.clear();
    fds.push_back({listen_fd_, POLLIN, 0});
    fds.push_back({wake_fd_, POLLIN, 0});
    bool backlog = false;  // some client has complete lines waiting (fairness cap hit)
    for (auto& [id, c] : clients_) {
      if (c.fd < 0) continue;
      const bool throttled = c.out.size() - c.out_sent > limits_.throttle_bytes;
      const bool pending_line = c.in.find('\n') != std::string::npos;
      backlog = backlog || (pending_line && !throttled);
      // Finish buffered lines before reading more; read nothing while its replies pile up.
      short events = pending_line || c.eof || throttled ? 0 : POLLIN;
      if (c.out_sent < c.out.size()) events |= POLLOUT;
      fds.push_back({c.fd, events, 0});
      ids.push_back(id);
    }
    // Sleep to the next tick to the nanosecond (ppoll): poll's whole milliseconds, rounded
    // down, made the last part of every tick a busy loop of zero timeouts, a fifth of a core
    // for an idle service with the 5 ms tick.
    const auto left = backlog ? clock::duration::zero() : std::max(clock::duration::zero(), next_tick - clock::now());
    const auto left_ns = std::chrono::duration_cast<std::chrono::nanoseconds>(left).count();
    const timespec timeout{static_cast<time_t>(left_ns / 1000000000), static_cast<long>(left_ns % 1000000000)};
    const int r = ppoll(fds.data(), fds.size(), &timeout, nullptr);
    if (r < 0 && errno != EINTR) {
      spdlog::error("control socket poll: {}", std::strerror(errno));
      break;
    }
    if (r > 0) {
      if (fds[1].revents & POLLIN) run_posted();
      if (fds[0].revents & POLLIN) accept_clients();
      for (std::size_t i = 0; i < ids.size(); ++i) {
        auto it = clients_.find(ids[i]);
        if (it == clients_.end() || it->second.fd < 0) continue;
        const short rev = fds[i + 2].revents;
        if (rev & POLLOUT) flush_client(ids[i], it->second);
        if (it->second.fd >= 0 && (rev & (POLLIN | POLLHUP | POLLERR))) read_client(ids[i], it->second);
      }
    }
    // What other threads posted before these lines arrived goes first (a job's end and the
    // offsets it left are then in the status a client asks for next); the wake-up fd is
    // non-blocking, so this costs a lock when nothing was posted.
    run_posted();
    // Hand complete lines to the handler, a bounded number per client per turn.
    for (auto& [id, c] : clients_) handle_lines(id, c);
    expire_clients();
    if (clock::now() >= next_tick) {
      next_tick += tick;
      if (next_tick < clock::now()) next_tick = clock::now() + tick;
      if (handlers_.on_tick) guarded("the tick (status pushes, jog deadman)", handlers_.on_tick);
    }
    for (ClientId id : to_drop_) {
      clients_.erase(id);
      if (handlers_.on_disconnect) guarded("a disconnect", [&] { handlers_.on_disconnect(id); });
    }
    to_drop_.clear();
  }
}

}  // namespace pcnc
