// pause_prompt.cpp — asking the launcher at a program pause (see pause_prompt.hpp).
#include "service/pause_prompt.hpp"

#include <poll.h>
#include <unistd.h>

#include <cerrno>
#include <string>

#include "service/progress_update.hpp"

namespace pcnc {

bool ask_over_progress_channel(int fd, const PauseAt& at, const std::atomic<bool>& interrupt) {
  const std::string request = format_pause_request({at.line, at.optional});
  std::size_t sent = 0;
  while (sent < request.size()) {  // a few bytes: the socket takes them, or we wait for room
    const ssize_t n = write(fd, request.data() + sent, request.size() - sent);
    if (n > 0) {
      sent += static_cast<std::size_t>(n);
      continue;
    }
    if (n < 0 && errno != EAGAIN && errno != EINTR) return false;
    if (interrupt.load()) return false;
    pollfd out{fd, POLLOUT, 0};
    (void)poll(&out, 1, 100);
  }
  std::string pending;
  while (!interrupt.load()) {
    pollfd in{fd, POLLIN, 0};
    const int ready = poll(&in, 1, 100);  // the interrupt is looked at ten times a second
    if (ready < 0 && errno != EINTR) return false;
    if (ready <= 0) continue;
    char chunk[64];
    const ssize_t n = read(fd, chunk, sizeof chunk);
    if (n == 0) return false;  // the launcher went away
    if (n < 0) {
      if (errno == EAGAIN || errno == EINTR) continue;
      return false;
    }
    pending.append(chunk, static_cast<std::size_t>(n));
    for (std::size_t nl; (nl = pending.find('\n')) != std::string::npos;) {
      const std::string answer = pending.substr(0, nl);
      pending.erase(0, nl + 1);
      if (answer == "resume") return true;
      if (answer == "stop") return false;
    }
  }
  return false;
}

}  // namespace pcnc
