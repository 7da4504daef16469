// subprocess.cpp — fork/exec with captured output for the two-process tests.
#include "subprocess.hpp"

#include <fcntl.h>
#include <sys/mman.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <mutex>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "test_paths.hpp"

namespace pcnc::test {
namespace {

int decode(int status) {
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
  return -1;
}

// What the tests of this process created: removed when the process exits normally, so a
// suite leaves no /tmp/pcnc-test-* folder and no /dev/shm/pcnc-t-* segment behind (also when
// a test killed the rt that owned the segment). PCNC_KEEP_TEST_FILES=1 keeps them for a look.
class LeftoverRegistry {
 public:
  static LeftoverRegistry& get() {
    static LeftoverRegistry r;
    return r;
  }
  void add_dir(const std::string& d) {
    std::lock_guard<std::mutex> lock(mutex_);
    dirs_.push_back(d);
  }
  void add_shm(const std::string& n) {
    std::lock_guard<std::mutex> lock(mutex_);
    shms_.push_back(n);
  }
  ~LeftoverRegistry() {
    if (getpid() != owner_) return;  // a forked child never removes its parent's files
    const char* keep = std::getenv("PCNC_KEEP_TEST_FILES");
    if (keep && std::string(keep) == "1") return;
    std::error_code ec;
    for (const auto& d : dirs_) std::filesystem::remove_all(d, ec);
    for (const auto& n : shms_) shm_unlink(n.c_str());
  }

 private:
  LeftoverRegistry() : owner_(getpid()) {}
  pid_t owner_;
  std::mutex mutex_;
  std::vector<std::string> dirs_, shms_;
};

std::vector<char*> make_argv(const std::vector<std::string>& argv) {
  std::vector<char*> v;
  for (const auto& a : argv) v.push_back(const_cast<char*>(a.c_str()));
  v.push_back(nullptr);
  return v;
}

// In a child just forked from the test process `parent`: SIGTERM when the test dies. A test that
// aborts (a failed assertion in a library, a crash, ctest's timeout) never runs the destructors
// that stop its processes; pcnc-rt and pcnc-host then end as on a normal stop (removing their
// segment and socket) instead of running on beside the rest of the suite.
void die_with(pid_t parent) {
  prctl(PR_SET_PDEATHSIG, SIGTERM);
  if (getppid() != parent) _exit(127);  // it died before the line above
}

}  // namespace

ProcessResult run_process(const std::vector<std::string>& argv, double timeout_s) {
  int out[2], err[2];
  if (pipe2(out, O_CLOEXEC) != 0 || pipe2(err, O_CLOEXEC) != 0) throw std::runtime_error("pipe");
  auto args = make_argv(argv);
  const pid_t parent = getpid();
  const pid_t pid = fork();
  if (pid == 0) {
    die_with(parent);
    setpgid(0, 0);
    dup2(out[1], 1);
    dup2(err[1], 2);
    execv(args[0], args.data());
    _exit(127);
  }
  close(out[1]);
  close(err[1]);
  ProcessResult r;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  pollfd fds[2] = {{out[0], POLLIN, 0}, {err[0], POLLIN, 0}};
  int open_fds = 2;
  char buf[65536];
  while (open_fds > 0) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now()).count();
    if (left <= 0) {
      r.timed_out = true;
      kill(-pid, SIGKILL);
      break;
    }
    if (poll(fds, 2, static_cast<int>(std::min<long long>(left, 1000))) <= 0) continue;
    for (int i = 0; i < 2; ++i) {
      if (fds[i].fd < 0 || !(fds[i].revents & (POLLIN | POLLHUP | POLLERR))) continue;
      const ssize_t n = read(fds[i].fd, buf, sizeof buf);
      if (n <= 0) {
        close(fds[i].fd);
        fds[i].fd = -1;
        --open_fds;
      } else {
        (i == 0 ? r.out : r.err).append(buf, static_cast<std::size_t>(n));
      }
    }
  }
  for (auto& f : fds) {
    if (f.fd >= 0) close(f.fd);
  }
  int status = 0;
  waitpid(pid, &status, 0);
  r.exit_code = decode(status);
  return r;
}

BackgroundProcess start_process(const std::vector<std::string>& argv, const std::string& scratch_prefix) {
  BackgroundProcess p;
  p.out_path = scratch_prefix + ".out";
  p.err_path = scratch_prefix + ".err";
  auto args = make_argv(argv);
  const pid_t parent = getpid();
  p.pid = fork();
  if (p.pid == 0) {
    die_with(parent);
    const int o = open(p.out_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int e = open(p.err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    dup2(o, 1);
    dup2(e, 2);
    execv(args[0], args.data());
    _exit(127);
  }
  return p;
}

int BackgroundProcess::wait(double timeout_s) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  for (;;) {
    int status = 0;
    const pid_t r = waitpid(pid, &status, WNOHANG);
    if (r == pid) return decode(status);
    if (std::chrono::steady_clock::now() >= deadline) return -1;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
}

Reaped::~Reaped() {
  if (p.pid > 0 && p.wait(0.0) < 0) {
    kill(p.pid, SIGKILL);
    p.wait(5.0);
  }
}

int wait_for(BackgroundProcess& p, double timeout_s) {
  const int code = p.wait(timeout_s);
  if (code >= 0) p.pid = -1;
  return code;
}

std::string BackgroundProcess::out() const { return read_file(out_path); }
std::string BackgroundProcess::err() const { return read_file(err_path); }

std::string read_file(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::string make_temp_dir(const std::string& tag) {
  std::string templ = "/tmp/pcnc-test-" + tag + "-XXXXXX";
  if (!mkdtemp(templ.data())) throw std::runtime_error("mkdtemp failed");
  LeftoverRegistry::get().add_dir(templ);
  return templ;
}

std::string test_shm_name(const std::string& tag) {
  std::string name = "/pcnc-t-" + tag + "-" + std::to_string(getpid());
  LeftoverRegistry::get().add_shm(name);
  return name;
}

std::string write_test_config(const std::string& dir, const std::string& tag,
                              const std::vector<std::pair<std::string, std::string>>& extra_replacements) {
  std::string text = read_file(default_config());
  auto replace = [&](const std::string& from, const std::string& to) {
    const auto at = text.find(from);
    if (at == std::string::npos) throw std::runtime_error("test config: '" + from + "' not found");
    text.replace(at, from.size(), to);
  };
  replace("shm_name = \"/pcnc-desktop-mill\"", "shm_name = \"" + test_shm_name(tag) + "\"");
  // The test's own private directory for the socket and the journal (never the machine's
  // runtime or state directory: tests run in parallel).
  replace("# socket_path = \"/run/pcnc/desktop-mill/control.sock\"", "socket_path = \"" + dir + "/pcnc.sock\"");
  replace("# state_dir = \"/var/lib/pcnc/desktop-mill\"", "state_dir = \"" + dir + "/state\"");
  for (const auto& [from, to] : extra_replacements) replace(from, to);
  const std::string path = dir + "/" + tag + ".toml";
  std::ofstream(path) << text;
  return path;
}

}  // namespace pcnc::test
