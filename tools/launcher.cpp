// launcher.cpp — process management for `pcnc run` and `pcnc serve` (see launcher.hpp):
// fork/exec, readiness pipe, signal forwarding, restarts when supervising, and reporting
// which process ended and how.
#include "launcher.hpp"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/syscall.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>
#include <thread>

#include "service/progress_update.hpp"

namespace pcnc {
namespace {

volatile sig_atomic_t g_signal = 0;
volatile pid_t g_children[2] = {0, 0};     // rt, host
volatile sig_atomic_t g_signalled[2] = {0, 0};  // that child has had its stop signal

// Hands a stop signal on to both children, once: pcnc-rt takes its first SIGTERM/SIGINT as
// "bring the machine to rest, then exit" and a second one as "exit at once", so the launcher
// never sends a second one of its own. A signal the kernel sent (a terminal's Ctrl-C or
// hang-up) has reached the whole foreground process group, children included: not again.
// SIGHUP is handed on as SIGTERM (it would end pcnc-rt without a stop).
void forward_signal(int sig, siginfo_t* info, void*) {
  g_signal = sig;
  const bool from_terminal = info != nullptr && info->si_code == SI_KERNEL;
  for (int i = 0; i < 2; ++i) {
    const pid_t p = g_children[i];
    if (p <= 0 || g_signalled[i]) continue;
    g_signalled[i] = 1;
    if (!from_terminal) kill(p, sig == SIGHUP ? SIGTERM : sig);
  }
}

pid_t spawn(const std::string& path, const std::vector<std::string>& args, int keep_fd) {
  std::vector<char*> argv;
  argv.push_back(const_cast<char*>(path.c_str()));
  for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  const pid_t pid = fork();
  if (pid == 0) {
    // Children get default signal dispositions; the terminal's Ctrl-C reaches them anyway
    // (same process group), the launcher forwards SIGTERM.
    signal(SIGINT, SIG_DFL);
    signal(SIGTERM, SIG_DFL);
    if (keep_fd >= 0) fcntl(keep_fd, F_SETFD, 0);
    execv(path.c_str(), argv.data());
    std::fprintf(stderr, "pcnc: cannot start %s: %s\n", path.c_str(), std::strerror(errno));
    _exit(127);
  }
  return pid;
}

// At a program pause (pcnc run --pauses ask): true when the operator pressed Enter; false
// when stdin ended or failed (no one can answer), a stop signal came, or the host went away
// (the progress channel `fd` hung up).
bool wait_for_enter(int fd) {
  for (;;) {
    if (g_signal) return false;
    pollfd p[2] = {{STDIN_FILENO, POLLIN, 0}, {fd, 0, 0}};
    const int ready = poll(p, 2, 100);
    if (ready < 0 && errno != EINTR) return false;
    if (ready <= 0) continue;
    if (p[1].revents & (POLLHUP | POLLERR)) return false;
    if (p[0].revents & (POLLIN | POLLHUP)) {
      char c = 0;  // a byte at a time: what follows the Enter is the next pause's answer
      const ssize_t n = read(STDIN_FILENO, &c, 1);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) return false;
      if (c == '\n') return true;
    } else if (p[0].revents & (POLLERR | POLLNVAL)) {
      return false;
    }
  }
}

std::string describe_end(int status) {
  if (WIFEXITED(status)) return "exited with status " + std::to_string(WEXITSTATUS(status));
  if (WIFSIGNALED(status)) {
    const int sig = WTERMSIG(status);
    return "was killed by signal " + std::to_string(sig) + " (" + strsignal(sig) + ")";
  }
  return "ended (status " + std::to_string(status) + ")";
}

// Asks child `which` (0 rt, 1 host) to end with SIGTERM, unless it has had its stop signal
// already, and waits up to timeout for it (pcnc-rt first brings a moving machine to rest);
// then SIGKILL. Returns its wait status.
int stop_and_reap(int which, pid_t pid, double timeout_s) {
  int status = 0;
  if (!g_signalled[which]) {
    g_signalled[which] = 1;
    kill(pid, SIGTERM);
  }
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  // A pidfd turns readable when the child exits: the wait ends then, not at the next poll.
  // (the system call itself: glibc 2.36's <sys/pidfd.h> has no C linkage for C++)
  const int pidfd = static_cast<int>(syscall(SYS_pidfd_open, pid, 0));
  for (;;) {
    const pid_t r = waitpid(pid, &status, WNOHANG);
    if (r == pid) break;
    if (r < 0 && errno != EINTR) {
      status = 0;
      break;
    }
    const auto now = std::chrono::steady_clock::now();
    if (now >= deadline) {
      kill(pid, SIGKILL);
      waitpid(pid, &status, 0);
      break;
    }
    if (pidfd >= 0) {
      pollfd pfd{pidfd, POLLIN, 0};
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - now).count() + 1;
      (void)poll(&pfd, 1, static_cast<int>(left));  // EINTR or readable: look again
    } else {
      std::this_thread::sleep_for(std::chrono::milliseconds(5));  // no pidfd (old kernel): shutdown only
    }
  }
  if (pidfd >= 0) close(pidfd);
  return status;
}

}  // namespace

std::string executable_dir() {
  std::error_code ec;
  auto exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  return ec ? std::string(".") : exe.parent_path().string();
}

namespace {

// Starts pcnc-rt and waits for its "ready" line. Returns its pid, or 0 after saying why not.
pid_t start_rt(const LaunchOptions& options) {
  int ready[2];
  if (pipe2(ready, O_CLOEXEC) != 0) {
    std::fprintf(stderr, "pcnc: pipe: %s\n", std::strerror(errno));
    return 0;
  }
  std::vector<std::string> rt_args = options.rt_args;
  rt_args.push_back("--ready-fd");
  rt_args.push_back(std::to_string(ready[1]));
  g_signalled[0] = 0;
  const pid_t rt = spawn(options.rt_path, rt_args, ready[1]);
  close(ready[1]);
  g_children[0] = rt;

  // Wait for "ready" from pcnc-rt, or its death, or the timeout.
  char buf[16];
  pollfd pfd{ready[0], POLLIN, 0};
  int pr;
  do {
    pr = poll(&pfd, 1, static_cast<int>(options.rt_start_timeout_s * 1000));
  } while (pr < 0 && errno == EINTR && !g_signal);
  const ssize_t n = pr > 0 ? read(ready[0], buf, sizeof buf) : -1;
  close(ready[0]);
  if (n > 0) return rt;
  // EOF (n == 0): pcnc-rt closed the pipe without "ready", i.e. it is exiting; wait for it.
  // Timeout (no data): it hangs; stop it.
  int status = 0;
  const bool exited = n == 0 ? waitpid(rt, &status, 0) == rt : waitpid(rt, &status, WNOHANG) == rt;
  if (exited) {
    std::fprintf(stderr, "pcnc: pcnc-rt failed to start: it %s\n", describe_end(status).c_str());
  } else {
    stop_and_reap(0, rt, 2.0);
    if (!g_signal) std::fprintf(stderr, "pcnc: pcnc-rt did not become ready within %.1f s\n", options.rt_start_timeout_s);
  }
  g_children[0] = 0;
  return 0;
}

// Restarts of one process within the sliding window.
struct RestartBudget {
  std::vector<std::chrono::steady_clock::time_point> times;
  bool take(const LaunchOptions& o) {
    const auto now = std::chrono::steady_clock::now();
    const auto window = std::chrono::duration<double>(o.restart_window_s);
    std::erase_if(times, [&](auto t) { return now - t > window; });
    if (static_cast<int>(times.size()) >= o.max_restarts) return false;
    times.push_back(now);
    return true;
  }
};

bool ended_on_its_own(int status) {
  return !g_signal && !(WIFEXITED(status) && WEXITSTATUS(status) == 0);
}

// Exit status 2: the process refused its input (config, paths, command line); starting it
// again would only be refused again.
bool refused_its_input(int status) { return WIFEXITED(status) && WEXITSTATUS(status) == 2; }

}  // namespace

int launch_pair(const LaunchOptions& options) {
  struct sigaction sa {};
  sa.sa_sigaction = forward_signal;
  sa.sa_flags = SA_SIGINFO;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
  sigaction(SIGHUP, &sa, nullptr);

  pid_t rt = start_rt(options);
  if (rt == 0) return g_signal ? 128 + g_signal : 3;

  // progress channel (a socket pair): the host writes lines, a thread here hands them on
  // until the host exits, and answers "done" so the display is cleared before the report
  std::vector<std::string> host_args = options.host_args;
  int progress[2] = {-1, -1};
  if (options.on_progress_line && socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, progress) == 0) {
    host_args.push_back("--progress-fd");
    host_args.push_back(std::to_string(progress[1]));
  }
  g_signalled[1] = 0;
  pid_t host = spawn(options.host_path, host_args, progress[1]);
  g_children[1] = host;
  std::thread progress_reader;
  if (progress[0] >= 0) {
    close(progress[1]);
    progress_reader = std::thread([fd = progress[0], &options] {
      std::string pending;
      char chunk[4096];
      for (;;) {
        const ssize_t got = read(fd, chunk, sizeof chunk);
        if (got < 0 && errno == EINTR) continue;
        if (got <= 0) break;
        pending.append(chunk, static_cast<std::size_t>(got));
        std::size_t nl;
        while ((nl = pending.find('\n')) != std::string::npos) {
          const std::string line = pending.substr(0, nl);
          pending.erase(0, nl + 1);
          options.on_progress_line(line);
          // "done": the host waits for this answer before it prints its report
          // (MSG_NOSIGNAL: a host that has gone is EPIPE, not a SIGPIPE that would end pcnc
          // itself with status 141 in place of the run's)
          if (line == "done" && send(fd, "ok\n", 3, MSG_NOSIGNAL) < 0) break;
          // a program pause under --pauses ask: the machine waits at rest for the operator
          if (parse_pause_request(line)) {
            const char* answer = wait_for_enter(fd) ? "resume\n" : "stop\n";
            if (send(fd, answer, std::strlen(answer), MSG_NOSIGNAL) < 0) break;
          }
        }
      }
      close(fd);
    });
  }

  RestartBudget rt_restarts, host_restarts;
  int exit_code = 0;
  for (;;) {
    int status = 0;
    const pid_t who = waitpid(-1, &status, 0);
    if (who < 0) {
      if (errno == EINTR) continue;
      break;
    }
    if (who == host) {
      g_children[1] = 0;
      if (options.supervise && ended_on_its_own(status) && refused_its_input(status)) {
        std::fprintf(stderr, "pcnc: pcnc-host refused its configuration (its message above says why); not restarting it\n");
      } else if (options.supervise && ended_on_its_own(status)) {
        // The rt has noticed (or will, within process.host_timeout_s) and brings the machine
        // to rest on the path; the new host finds it HOST_LOST and can resume.
        if (host_restarts.take(options)) {
          std::fprintf(stderr, "pcnc: pcnc-host %s; pcnc-rt stays up and holds the machine; starting pcnc-host again\n",
                       describe_end(status).c_str());
          std::this_thread::sleep_for(std::chrono::duration<double>(options.restart_delay_s));
          if (!g_signal) {
            g_signalled[1] = 0;
            host = spawn(options.host_path, options.host_args, -1);
            g_children[1] = host;
            continue;
          }
        } else {
          std::fprintf(stderr, "pcnc: pcnc-host %s after %d restarts within %.0f s; giving up\n",
                       describe_end(status).c_str(), options.max_restarts, options.restart_window_s);
          exit_code = 3;
        }
      }
      // SIGTERM asks the rt to bring a moving machine to rest before it exits (it gives up
      // after 5 s; SIGKILL only if it hangs beyond that).
      const int rt_status = stop_and_reap(0, rt, 10.0);
      g_children[0] = 0;
      if (exit_code == 0) {
        if (WIFEXITED(status)) {
          exit_code = WEXITSTATUS(status);
        } else {
          std::fprintf(stderr, "pcnc: pcnc-host %s\n", describe_end(status).c_str());
          exit_code = WIFSIGNALED(status) ? 128 + WTERMSIG(status) : 1;
        }
      }
      const bool rt_clean = (WIFEXITED(rt_status) && WEXITSTATUS(rt_status) == 0) ||
                            (WIFSIGNALED(rt_status) && WTERMSIG(rt_status) == SIGTERM);
      if (!rt_clean && WIFEXITED(rt_status) && WEXITSTATUS(rt_status) == 1) {
        // pcnc-rt ran to its end and reported a failure of its own above (its trace could not
        // be written, or the machine did not come to rest in time): the run is not clean.
        std::fprintf(stderr, "pcnc: pcnc-rt reported a failure (exit status 1; its message above names it)\n");
        if (exit_code == 0) exit_code = 1;
      } else if (!rt_clean) {
        std::fprintf(stderr, "pcnc: pcnc-rt %s while stopping\n", describe_end(rt_status).c_str());
        if (exit_code == 0) exit_code = 3;
      }
      break;
    }
    if (who == rt) {
      g_children[0] = 0;
      if (options.supervise && ended_on_its_own(status)) {
        // The host refuses motion while the rt is gone and attaches to the new one.
        if (rt_restarts.take(options)) {
          std::fprintf(stderr, "pcnc: pcnc-rt %s; starting pcnc-rt again (pcnc-host stays up and re-attaches)\n",
                       describe_end(status).c_str());
          std::this_thread::sleep_for(std::chrono::duration<double>(options.restart_delay_s));
          if (!g_signal && (rt = start_rt(options)) != 0) continue;
          if (!g_signal) std::fprintf(stderr, "pcnc: pcnc-rt could not be started again; stopping pcnc-host\n");
        } else {
          std::fprintf(stderr, "pcnc: pcnc-rt %s after %d restarts within %.0f s; giving up\n",
                       describe_end(status).c_str(), options.max_restarts, options.restart_window_s);
        }
      } else if (!g_signal) {
        std::fprintf(stderr, "pcnc: pcnc-rt %s; stopping pcnc-host\n", describe_end(status).c_str());
      }
      const int host_status = stop_and_reap(1, host, 5.0);
      g_children[1] = 0;
      if (!g_signal) std::fprintf(stderr, "pcnc: pcnc-host %s\n", describe_end(host_status).c_str());
      exit_code = 3;
      break;
    }
  }
  if (progress_reader.joinable()) progress_reader.join();  // EOF: the host has exited
  if (g_signal) exit_code = 128 + g_signal;
  return exit_code;
}

}  // namespace pcnc
