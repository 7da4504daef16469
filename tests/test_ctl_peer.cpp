// test_ctl_peer.cpp — `pcnc ctl` (CtlClient) talks only to a server that runs as root or as
// the client's own user (issue 19, squatting): a socket another uid listens on is refused
// before anything is sent. Needs root to run the squatter as another uid.
#include <grp.h>
#include <gtest/gtest.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstring>
#include <stdexcept>
#include <string>

#include "ctl.hpp"
#include "subprocess.hpp"

namespace pcnc::test {
namespace {

// A child that becomes `uid`, listens on `path`, accepts one connection and reports on its
// exit status whether it received any byte (1) or none (0).
pid_t squatter(const std::string& path, uid_t uid, int ready_fd) {
  const pid_t pid = fork();
  if (pid != 0) return pid;
  if (setgroups(0, nullptr) != 0 || setgid(uid) != 0 || setuid(uid) != 0) _exit(30);
  const int fd = socket(AF_UNIX, SOCK_STREAM, 0);
  sockaddr_un addr{};
  addr.sun_family = AF_UNIX;
  std::strncpy(addr.sun_path, path.c_str(), sizeof addr.sun_path - 1);
  if (bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0 || listen(fd, 1) != 0) _exit(31);
  if (write(ready_fd, "r", 1) != 1) _exit(32);
  const int c = accept(fd, nullptr, nullptr);
  if (c < 0) _exit(33);
  char b;
  const ssize_t n = recv(c, &b, 1, 0);  // EOF when the client hangs up without a word
  _exit(n > 0 ? 1 : 0);
}

TEST(CtlPeer, AServerOfAnotherUserIsRefused) {
  if (geteuid() != 0) GTEST_SKIP() << "needs root to listen as another uid (setuid in a forked child)";
  const std::string dir = make_temp_dir("ctl-peer");
  ASSERT_EQ(chmod(dir.c_str(), 0777), 0);
  const std::string path = dir + "/squat.sock";
  int ready[2];
  ASSERT_EQ(pipe(ready), 0);
  const pid_t child = squatter(path, 65534, ready[1]);
  close(ready[1]);
  char r;
  ASSERT_EQ(read(ready[0], &r, 1), 1) << "squatter did not start";
  close(ready[0]);
  std::string message;
  try {
    CtlClient c(path);
    c.call("status", nlohmann::json::object(), 1.0);
  } catch (const std::runtime_error& e) {
    message = e.what();
  }
  EXPECT_NE(message.find("refusing to talk to"), std::string::npos) << message;
  EXPECT_NE(message.find("uid 65534"), std::string::npos) << message;
  int status = 0;
  ASSERT_EQ(waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0) << "the client must not send anything to a foreign server";
}

}  // namespace
}  // namespace pcnc::test
