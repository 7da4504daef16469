// bench_grbl.cpp — the grbl port's figures (never pass/fail): `pcnc grbl` on a private copy of
// a config, a sender on its pseudo-terminal (tests/support/grbl_sender.hpp), real clock.
//   * status-report round trip: `?` to its `<...>` line, N times (min, median, p99, max);
//   * streaming throughput over the pty: lines/s by character counting, in check mode ($C:
//     the whole pipeline and the rt's block check, no motion) and of lines that set modes only;
//   * machine time of a program streamed by character counting against `pcnc run` of the same
//     file on the same config (goal: no more than 5 % slower), with both runs' underruns.
//   bench_grbl [--program FILE] [--config FILE] [--queries N] [--lines N]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "bench_cli.hpp"
#include "ctl.hpp"
#include "grbl_sender.hpp"
#include "ipc/segment.hpp"
#include "subprocess.hpp"

using namespace pcnc;
using namespace pcnc::test;
using json = nlohmann::json;
using Clock = std::chrono::steady_clock;

namespace {

// A private copy of `config`: its own segment, socket and state directory.
std::string private_config(const std::string& config, const std::string& dir, const std::string& tag) {
  std::ifstream in(config);
  std::stringstream ss;
  ss << in.rdbuf();
  std::string text = ss.str();
  text = std::regex_replace(text, std::regex("(^|\\n)shm_name = [^\\n]*"), "$1shm_name = \"/pcnc-" + tag + "\"");
  text = std::regex_replace(text, std::regex("(^|\\n)# socket_path = [^\\n]*"), "$1socket_path = \"" + dir + "/pcnc.sock\"");
  text = std::regex_replace(text, std::regex("(^|\\n)# state_dir = [^\\n]*"), "$1state_dir = \"" + dir + "/state\"");
  const std::string path = dir + "/bench.toml";
  std::ofstream(path) << text;
  return path;
}

double ms(Clock::duration d) { return std::chrono::duration<double, std::milli>(d).count(); }

double throughput(GrblSender& port, const std::vector<std::string>& lines) {
  const auto t0 = Clock::now();
  const auto answers = port.stream(lines);
  const double s = std::chrono::duration<double>(Clock::now() - t0).count();
  const auto errors = std::count_if(answers.begin(), answers.end(), [](const std::string& a) { return a != "ok"; });
  if (errors) std::printf("  (%ld lines answered with an error)\n", static_cast<long>(errors));
  return static_cast<double>(lines.size()) / s;
}

}  // namespace

int main(int argc, char** argv) {
  pcnc::BenchCli app("bench_grbl: the grbl port's latency, throughput and machine time");
  std::string program = std::string(PCNC_SOURCE_DIR) + "/examples/demo.ngc";
  std::string config = std::string(PCNC_SOURCE_DIR) + "/configs/desktop-mill.toml";
  int queries = 500, lines = 2000;
  app.add_option("--program", program, "G-code file to stream and to run")->show_default();
  app.add_option("--config", config, "machine config")->show_default();
  app.add_option("--queries", queries, "status queries for the round trip")->show_default();
  app.add_option("--lines", lines, "lines per throughput run")->show_default();
  if (const int rc = app.parse(argc, argv); rc >= 0) return rc;

  const std::string tag = "bench-grbl-" + std::to_string(getpid());
  const std::string dir = make_temp_dir(tag);
  const std::string cfg = private_config(config, dir, tag);
  auto grbl = start_grbl(cfg, dir);
  GrblSender port(grbl->link);
  if (!port.is_open() || !port.read_until([](const std::string& l) { return l.rfind("Grbl", 0) == 0; }, 30.0)) {
    std::fprintf(stderr, "bench_grbl: the port did not come up\n%s", grbl->proc.err().c_str());
    return 1;
  }
  std::setvbuf(stdout, nullptr, _IOLBF, 0);
  std::printf("pcnc grbl on %s, config %s, real clock\n", grbl->link.c_str(), config.c_str());

  // 1. status round trip
  std::vector<double> rtt;
  for (int i = 0; i < queries; ++i) {
    const auto t0 = Clock::now();
    if (!port.status()) break;
    rtt.push_back(ms(Clock::now() - t0));
  }
  std::sort(rtt.begin(), rtt.end());
  if (!rtt.empty()) {
    auto q = [&](double p) { return rtt[std::min(rtt.size() - 1, static_cast<std::size_t>(p * static_cast<double>(rtt.size())))]; };
    std::printf("status report round trip ('?' to '<...>'), %zu queries: min %.3f ms, median %.3f ms, p99 %.3f ms, max %.3f ms\n",
                rtt.size(), rtt.front(), q(0.5), q(0.99), rtt.back());
  }

  // 2. throughput: mode lines (no motion), then moves in check mode
  std::vector<std::string> modes, moves;
  for (int i = 0; i < lines; ++i) modes.push_back(i % 2 ? "G90 F600" : "G21 G17");
  for (int i = 0; i < lines; ++i) moves.push_back(i % 2 ? "G1 X-1 Y-1" : "G1 X1 Y1 F600");
  std::printf("streaming throughput, character counting, %d lines: mode lines %.0f lines/s", lines, throughput(port, modes));
  port.command("$C");
  std::printf("; moves in check mode ($C) %.0f lines/s\n", throughput(port, moves));
  port.command("$C");
  port.read_until([](const std::string& l) { return l.rfind("Grbl", 0) == 0; }, 10.0);

  // 3. machine time: streamed vs pcnc run
  const auto text = read_lines(program);
  const auto t0 = Clock::now();
  const auto answers = port.stream(text);
  port.wait_status([](const GrblStatus& s) { return s.state == "Idle"; }, 600.0);
  const double wall = std::chrono::duration<double>(Clock::now() - t0).count();
  CtlClient c(dir + "/pcnc.sock");
  json st = c.call("status")["result"];
  if (st["job"].value("active", false)) {  // a program without M2/M30: end its stream
    port.command("$C");
    port.command("$C");
    st = c.call("status")["result"];
  }
  const json last = st["last_job"];
  const double streamed = last.value("program_time_s", 0.0);
  grbl.reset();  // Ctrl-C: frees the segment for pcnc run
  const std::string summary = dir + "/run.json";
  const auto r = run_process({std::string(PCNC_BIN_DIR) + "/tools/pcnc", "run", program, "--config", cfg, "--clock", "real", "--summary",
                              summary},
                             900.0);
  double run_time = 0.0;
  long run_underruns = -1;
  if (r.exit_code == 0) {
    std::ifstream in(summary);
    const json s = json::parse(in);
    run_time = s["status"].value("program_time_s", 0.0);
    run_underruns = s["status"].value("underruns", 0L);
  }
  const long errors = std::count_if(answers.begin(), answers.end(), [](const std::string& a) { return a != "ok"; });
  std::printf("machine time of %s (%zu lines, %ld answered with an error): streamed %.3f s (%s, %.1f s wall), pcnc run %.3f s "
              "(%ld underruns): streamed/run %.4f (%+.2f %%)\n",
              program.c_str(), text.size(), errors, streamed, last.value("end", std::string("?")).c_str(), wall, run_time,
              run_underruns, run_time > 0 ? streamed / run_time : 0.0, run_time > 0 ? (streamed / run_time - 1.0) * 100.0 : 0.0);
  if (r.exit_code != 0) std::printf("pcnc run failed (%d): %s\n", r.exit_code, r.err.substr(r.err.size() > 2000 ? r.err.size() - 2000 : 0).c_str());
  remove_segment("/pcnc-" + tag);
  return 0;
}
