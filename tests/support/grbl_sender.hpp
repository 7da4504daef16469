// grbl_sender.hpp — tests and the bench talk to `pcnc grbl`'s pseudo-terminal the way a
// G-code sender does: open the port raw, read lines, send lines and real-time bytes, stream a
// program by character counting (grbl's 128-byte receive buffer), ask for status reports.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "subprocess.hpp"

namespace pcnc::test {

/// A parsed `<State|MPos:x,y,z|...|FS:f,s|Ov:a,b,c|...>` report.
struct GrblStatus {
  std::string state;  // "Idle", "Run", "Hold:0", ...
  double mpos[3] = {0, 0, 0};
  double feed = 0.0;
  int ov_feed = 0, ov_rapid = 0, ov_spindle = 0;
  bool has_wco = false;
  std::string raw;
};
std::optional<GrblStatus> parse_grbl_status(const std::string& line);

class GrblSender {
 public:
  /// Opens `path` (waiting up to timeout_s for it to appear) in raw mode.
  explicit GrblSender(const std::string& path, double timeout_s = 20.0);
  ~GrblSender();
  GrblSender(const GrblSender&) = delete;
  GrblSender& operator=(const GrblSender&) = delete;

  bool is_open() const { return fd_ >= 0; }
  void send_line(const std::string& line);
  void send_byte(unsigned char b);
  /// The next non-empty line within timeout_s.
  std::optional<std::string> read_line(double timeout_s = 10.0);
  /// Lines until one for which `stop` holds (included); empty optional on timeout.
  std::optional<std::vector<std::string>> read_until(const std::function<bool(const std::string&)>& stop,
                                                     double timeout_s = 10.0);
  /// Sends a line and collects the lines up to its `ok` / `error:N` (the last element).
  std::vector<std::string> command(const std::string& line, double timeout_s = 10.0);
  /// `?` and its report (other lines that arrive meanwhile are kept in `others`).
  std::optional<GrblStatus> status(double timeout_s = 10.0);
  /// Polls `?` until `pred` holds or timeout_s passes; returns the last report.
  std::optional<GrblStatus> wait_status(const std::function<bool(const GrblStatus&)>& pred, double timeout_s = 60.0);

  /// Streams `lines` by character counting. Each `?` sent every `status_every` lines (0: none)
  /// adds its report to `reports`. Returns the answers, one per line, in order.
  std::vector<std::string> stream(const std::vector<std::string>& lines, std::vector<GrblStatus>* reports = nullptr,
                                  int status_every = 0, double timeout_s = 300.0);

  std::vector<std::string> others;  // lines read that were not what a call waited for

 private:
  int fd_ = -1;
  std::string buffer_;
};

/// The lines of a G-code file (without line ends).
std::vector<std::string> read_lines(const std::string& path);

/// `pcnc grbl --config CONFIG --link DIR/tty` in the background, and the port's path.
struct GrblProcess {
  BackgroundProcess proc;
  std::string link;
  ~GrblProcess();  // SIGINT, then SIGKILL if it hangs
};
std::unique_ptr<GrblProcess> start_grbl(const std::string& config, const std::string& dir,
                                        const std::vector<std::string>& extra = {});

}  // namespace pcnc::test
