// grbl_sender.cpp — a G-code sender on `pcnc grbl`'s pseudo-terminal (see grbl_sender.hpp).
#include "grbl_sender.hpp"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <termios.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <deque>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <thread>

namespace pcnc::test {

using Clock = std::chrono::steady_clock;

namespace {
Clock::time_point after(double s) { return Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(s)); }
bool is_answer(const std::string& l) { return l == "ok" || l.rfind("error:", 0) == 0; }
}  // namespace

std::optional<GrblStatus> parse_grbl_status(const std::string& line) {
  if (line.size() < 3 || line.front() != '<' || line.back() != '>') return std::nullopt;
  GrblStatus s;
  s.raw = line;
  std::stringstream fields(line.substr(1, line.size() - 2));
  std::string f;
  bool first = true;
  while (std::getline(fields, f, '|')) {
    if (first) {
      s.state = f;
      first = false;
      continue;
    }
    const auto colon = f.find(':');
    if (colon == std::string::npos) continue;
    const std::string key = f.substr(0, colon), value = f.substr(colon + 1);
    std::vector<double> v;
    std::stringstream vs(value);
    std::string item;
    while (std::getline(vs, item, ',')) v.push_back(std::strtod(item.c_str(), nullptr));
    if (key == "MPos" && v.size() == 3) {
      for (int i = 0; i < 3; ++i) s.mpos[i] = v[static_cast<std::size_t>(i)];
    } else if (key == "FS" && !v.empty()) {
      s.feed = v[0];
    } else if (key == "Ov" && v.size() == 3) {
      s.ov_feed = static_cast<int>(v[0]);
      s.ov_rapid = static_cast<int>(v[1]);
      s.ov_spindle = static_cast<int>(v[2]);
    } else if (key == "WCO") {
      s.has_wco = true;
    }
  }
  return s;
}

GrblSender::GrblSender(const std::string& path, double timeout_s) {
  const auto deadline = after(timeout_s);
  while (Clock::now() < deadline) {
    fd_ = ::open(path.c_str(), O_RDWR | O_NOCTTY | O_CLOEXEC);
    if (fd_ >= 0) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  if (fd_ < 0) return;
  termios t{};
  tcgetattr(fd_, &t);
  cfmakeraw(&t);
  tcsetattr(fd_, TCSANOW, &t);
}

GrblSender::~GrblSender() {
  if (fd_ >= 0) ::close(fd_);
}

void GrblSender::send_line(const std::string& line) {
  const std::string s = line + "\n";
  if (::write(fd_, s.data(), s.size()) != static_cast<ssize_t>(s.size())) throw std::runtime_error("write to the port failed");
}

void GrblSender::send_byte(unsigned char b) {
  if (::write(fd_, &b, 1) != 1) throw std::runtime_error("write to the port failed");
}

std::optional<std::string> GrblSender::read_line(double timeout_s) {
  const auto deadline = after(timeout_s);
  for (;;) {
    std::size_t nl;
    while ((nl = buffer_.find('\n')) != std::string::npos) {
      std::string l = buffer_.substr(0, nl);
      buffer_.erase(0, nl + 1);
      if (!l.empty() && l.back() == '\r') l.pop_back();
      if (!l.empty()) return l;
    }
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
    if (left <= 0) return std::nullopt;
    pollfd p{fd_, POLLIN, 0};
    if (poll(&p, 1, static_cast<int>(std::min<long long>(left, 100))) <= 0) continue;
    char buf[4096];
    const ssize_t n = ::read(fd_, buf, sizeof buf);
    if (n > 0) buffer_.append(buf, static_cast<std::size_t>(n));
  }
}

std::optional<std::vector<std::string>> GrblSender::read_until(const std::function<bool(const std::string&)>& stop,
                                                               double timeout_s) {
  std::vector<std::string> out;
  const auto deadline = after(timeout_s);
  while (Clock::now() < deadline) {
    auto l = read_line(std::chrono::duration<double>(deadline - Clock::now()).count());
    if (!l) break;
    out.push_back(*l);
    if (stop(*l)) return out;
  }
  return std::nullopt;
}

std::vector<std::string> GrblSender::command(const std::string& line, double timeout_s) {
  send_line(line);
  auto lines = read_until(is_answer, timeout_s);
  return lines ? *lines : std::vector<std::string>{"<timeout>"};
}

std::optional<GrblStatus> GrblSender::status(double timeout_s) {
  send_byte('?');
  const auto deadline = after(timeout_s);
  while (Clock::now() < deadline) {
    auto l = read_line(std::chrono::duration<double>(deadline - Clock::now()).count());
    if (!l) break;
    if (auto s = parse_grbl_status(*l)) return s;
    others.push_back(*l);
  }
  return std::nullopt;
}

std::optional<GrblStatus> GrblSender::wait_status(const std::function<bool(const GrblStatus&)>& pred, double timeout_s) {
  const auto deadline = after(timeout_s);
  std::optional<GrblStatus> last;
  while (Clock::now() < deadline) {
    last = status();
    if (last && pred(*last)) return last;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return last;
}

std::vector<std::string> GrblSender::stream(const std::vector<std::string>& lines, std::vector<GrblStatus>* reports,
                                            int status_every, double timeout_s) {
  constexpr std::size_t kBuffer = 128;
  std::deque<std::size_t> in_flight;  // bytes of each line sent and not answered
  std::size_t used = 0;
  std::vector<std::string> answers;
  const auto deadline = after(timeout_s);
  auto read_one = [&] {
    auto l = read_line(std::chrono::duration<double>(deadline - Clock::now()).count());
    if (!l) throw std::runtime_error("the port stopped answering while streaming");
    if (is_answer(*l)) {
      answers.push_back(*l);
      used -= in_flight.front();
      in_flight.pop_front();
    } else if (auto s = parse_grbl_status(*l)) {
      if (reports) reports->push_back(*s);
    } else {
      others.push_back(*l);
    }
  };
  int n = 0;
  for (const std::string& raw : lines) {
    std::string line = raw;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const std::size_t bytes = line.size() + 1;
    while (used + bytes > kBuffer && !in_flight.empty()) read_one();
    send_line(line);
    used += bytes;
    in_flight.push_back(bytes);
    if (status_every > 0 && ++n % status_every == 0) send_byte('?');
  }
  while (!in_flight.empty()) read_one();
  return answers;
}

std::vector<std::string> read_lines(const std::string& path) {
  std::ifstream in(path);
  std::vector<std::string> out;
  std::string l;
  while (std::getline(in, l)) out.push_back(l);
  return out;
}

GrblProcess::~GrblProcess() {
  if (proc.pid <= 0) return;
  kill(proc.pid, SIGINT);
  if (proc.wait(15.0) < 0) {
    kill(proc.pid, SIGKILL);
    proc.wait(5.0);
  }
}

std::unique_ptr<GrblProcess> start_grbl(const std::string& config, const std::string& dir,
                                        const std::vector<std::string>& extra) {
  auto g = std::make_unique<GrblProcess>();
  g->link = dir + "/tty";
  std::vector<std::string> argv = {std::string(PCNC_BIN_DIR) + "/tools/pcnc", "grbl", "--config", config, "--link", g->link};
  argv.insert(argv.end(), extra.begin(), extra.end());
  g->proc = start_process(argv, dir + "/grbl");
  return g;
}

}  // namespace pcnc::test
