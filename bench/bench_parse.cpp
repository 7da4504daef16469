// bench_parse.cpp — figures for the G-code front end (prints, never pass/fail): lines per second
// and peak RSS of parse + interpret + preflight (+ preprocess) as a whole process, single thread,
// on tiny200k.ngc (made by ../shared/bench/gen_peer_programs.py in a temp dir), on the largest
// CAM program of ../shared/gcode/cam, and on a generated 1,000,000-line program.
//
// Each measurement runs this program again as a child (`bench_parse --child ...`), so the time
// and the peak RSS are those of a whole process: start, config load, check, blocks, exit.
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "bench_cli.hpp"
#include "config/config.hpp"
#include "gcode/program.hpp"

namespace fs = std::filesystem;

namespace {

// The peers' setup (../shared/bench/README.md): travel +-100 mm, program zero at the origin.
pcnc::MachineConfig peer_config(pcnc::MachineConfig c) {
  for (pcnc::AxisConfig& a : c.axes) {
    a.travel_min_mm = -100.0;
    a.travel_max_mm = 100.0;
  }
  c.axes[0].max_velocity_mm_s = c.axes[1].max_velocity_mm_s = 5000.0 / 60.0;
  c.axes[2].max_velocity_mm_s = 2000.0 / 60.0;
  c.axes[0].max_accel_mm_s2 = c.axes[1].max_accel_mm_s2 = 500.0;
  c.axes[2].max_accel_mm_s2 = 200.0;
  c.gcode.work_offsets[0] = {0.0, 0.0, 0.0};
  return c;
}

int child(const std::string& file, const std::string& config_path, bool peer, bool fit, bool blocks) {
  pcnc::MachineConfig config = pcnc::load_config(config_path);
  if (peer) config = peer_config(config);
  pcnc::JobOptions options;
  options.fit = fit;
  const pcnc::CheckResult r = pcnc::check_program(file, config, options);
  if (!r.ok) {
    for (const auto& d : r.diagnostics) std::fprintf(stderr, "%s\n", pcnc::format_diagnostic(d).c_str());
    return 1;
  }
  std::uint64_t n = 0;
  double sum = 0.0;
  if (blocks) {
    pcnc::BlockStream s(file, config, options, r.transform);
    pcnc::Block b;
    while (s.next(b)) {
      ++n;
      sum += b.length;  // keep the work observable
    }
  }
  std::printf("%llu %llu %.6f\n", static_cast<unsigned long long>(r.lines), static_cast<unsigned long long>(n), sum);
  return 0;
}

struct Figure {
  double wall_s = 0.0;
  double user_s = 0.0;
  long peak_rss_kb = 0;
  unsigned long long lines = 0;
  bool ok = false;
};

Figure measure(const std::string& self, const std::vector<std::string>& args) {
  Figure f;
  int pipefd[2];
  if (pipe(pipefd) != 0) return f;
  const auto t0 = std::chrono::steady_clock::now();
  const pid_t pid = fork();
  if (pid == 0) {
    dup2(pipefd[1], 1);
    close(pipefd[0]);
    std::vector<char*> argv;
    argv.push_back(const_cast<char*>(self.c_str()));
    for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    execv(self.c_str(), argv.data());
    _exit(127);
  }
  close(pipefd[1]);
  std::string out;
  char buf[256];
  ssize_t n;
  while ((n = read(pipefd[0], buf, sizeof buf)) > 0) out.append(buf, static_cast<std::size_t>(n));
  close(pipefd[0]);
  int status = 0;
  struct rusage ru {};
  wait4(pid, &status, 0, &ru);
  const auto t1 = std::chrono::steady_clock::now();
  f.wall_s = std::chrono::duration<double>(t1 - t0).count();
  f.user_s = static_cast<double>(ru.ru_utime.tv_sec) + 1e-6 * static_cast<double>(ru.ru_utime.tv_usec) +
             static_cast<double>(ru.ru_stime.tv_sec) + 1e-6 * static_cast<double>(ru.ru_stime.tv_usec);
  f.peak_rss_kb = ru.ru_maxrss;
  f.ok = WIFEXITED(status) && WEXITSTATUS(status) == 0;
  f.lines = std::strtoull(out.c_str(), nullptr, 10);
  return f;
}

void report(const char* name, const char* what, const std::string& self, const std::vector<std::string>& args,
            int repeats, unsigned long long known_lines = 0) {
  Figure best;
  best.wall_s = 1e9;
  for (int i = 0; i < repeats; ++i) {
    const Figure f = measure(self, args);
    if (!f.ok) {
      std::printf("%-30s %-34s FAILED (see stderr)\n", name, what);
      return;
    }
    if (f.wall_s < best.wall_s) best = f;
  }
  if (known_lines) best.lines = known_lines;
  std::printf("%-30s %-34s %9llu lines  wall %7.4f s  cpu %7.4f s  %6.2f M lines/s  peak RSS %6.1f MB\n", name, what,
              best.lines, best.wall_s, best.user_s, static_cast<double>(best.lines) / best.wall_s / 1e6,
              static_cast<double>(best.peak_rss_kb) / 1024.0);
}

// The peers' machine as a TOML file for the pcnc CLI: the given config with +-100 mm travel and
// G54 at the origin (text edits of the keys the default config spells out).
bool write_peer_config(const std::string& from, const std::string& to) {
  std::ifstream in(from);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  auto replace_all = [&](const std::string& a, const std::string& b) {
    int n = 0;
    for (std::size_t pos = text.find(a); pos != std::string::npos; pos = text.find(a, pos + b.size()), ++n)
      text.replace(pos, a.size(), b);
    return n;
  };
  const int mins = replace_all("travel_min_mm = 0.0", "travel_min_mm = -100.0");
  const int maxs = replace_all("travel_max_mm = 25.0", "travel_max_mm = 100.0");
  const int g54 = replace_all("g54 = [12.5, 12.5, 25.0]", "g54 = [0.0, 0.0, 0.0]");
  std::ofstream(to) << text;
  return mins == 3 && maxs == 3 && g54 == 1;
}

void write_big_program(const std::string& path, int n) {
  // The shape of tiny.ngc: short G1 segments on an R20 circle with a small Z ripple.
  std::FILE* f = std::fopen(path.c_str(), "w");
  std::fprintf(f, "G21 G90 G17 G94\nG0 Z1\nG0 X20 Y0\nG1 Z0 F300\nG1 F1000\n");
  for (int i = 1; i <= n; ++i) {
    const double a = 2 * 3.14159265358979323846 * 50.0 * i / n;
    std::fprintf(f, "G1 X%.4f Y%.4f Z%.4f\n", 20 * std::cos(a), 20 * std::sin(a), -0.5 + 0.5 * std::cos(8 * a));
  }
  std::fprintf(f, "G0 Z5\nM2\n");
  std::fclose(f);
}

}  // namespace

int main(int argc, char** argv) {
  pcnc::BenchCli app{"bench_parse: G-code front-end throughput and memory (figures, not a test)"};
  std::string config_path = pcnc::default_config_path();
  std::string shared;
  std::string child_file;
  bool peer = false, fit = false, blocks = false;
  int repeats = 3;
  app.add_option("--config", config_path, "machine configuration");
  app.add_option("--shared", shared,
                 "the shared folder (default: $PCNC_SHARED_DIR, else ../shared of the source tree)");
  app.add_option("--repeats", repeats, "runs per figure (the fastest is printed)");
  app.add_option("--child", child_file, "internal: run one measurement in this process");
  app.add_flag("--peer", peer, "internal: the peers' machine (travel +-100 mm)");
  app.add_flag("--fit", fit, "internal: --fit");
  app.add_flag("--blocks", blocks, "internal: also stream the blocks");
  if (const int rc = app.parse(argc, argv); rc >= 0) return rc;
  if (!child_file.empty()) return child(child_file, config_path, peer, fit, blocks);

  const std::string self = fs::canonical("/proc/self/exe").string();
  if (shared.empty()) {
    const char* env = std::getenv("PCNC_SHARED_DIR");
    shared = env ? env : (fs::path(config_path).parent_path().parent_path().parent_path() / "shared").string();
  }
  if (!fs::exists(shared + "/bench/gen_peer_programs.py")) {
    std::fprintf(stderr, "bench_parse: %s/bench/gen_peer_programs.py not found; pass --shared DIR\n", shared.c_str());
    return 2;
  }
  char tmpl[] = "/tmp/pcnc-bench-parse-XXXXXX";
  const char* tmp = mkdtemp(tmpl);
  if (!tmp) return 2;
  const std::string dir = tmp;
  const std::string gen = "cd '" + dir + "' && python3 '" + shared + "/bench/gen_peer_programs.py'";
  if (std::system(gen.c_str()) != 0) {
    std::fprintf(stderr, "bench_parse: %s failed\n", gen.c_str());
    return 2;
  }
  // The largest CAM program, by size.
  std::string largest;
  std::uintmax_t largest_size = 0;
  for (const auto& e : fs::recursive_directory_iterator(shared + "/gcode/cam")) {
    if (e.is_regular_file() && e.file_size() > largest_size) {
      largest_size = e.file_size();
      largest = e.path().string();
    }
  }
  const std::string big = dir + "/tiny1m.ngc";
  write_big_program(big, 1000000);

  std::printf("config %s; %d runs per figure, fastest shown; whole process (fork+exec, config load, check, blocks)\n",
              config_path.c_str(), repeats);
  const std::string tiny = dir + "/tiny200k.ngc";
  report("tiny200k.ngc", "check (peer travel +-100 mm)", self, {"--child", tiny, "--config", config_path, "--peer"},
         repeats);
  report("tiny200k.ngc", "check + blocks (peer travel)", self,
         {"--child", tiny, "--config", config_path, "--peer", "--blocks"}, repeats);
  report("tiny200k.ngc", "check --fit + blocks (25 mm mill)", self,
         {"--child", tiny, "--config", config_path, "--fit", "--blocks"}, repeats);
  // The real command line, if it was built next to this bench (build/tools/pcnc).
  const std::string pcnc = (fs::path(self).parent_path().parent_path() / "tools" / "pcnc").string();
  const std::string peer_toml = dir + "/bench-peers.toml";
  if (fs::exists(pcnc) && write_peer_config(config_path, peer_toml)) {
    report("tiny200k.ngc", "pcnc check -q (the CLI, peer config)", pcnc, {"check", tiny, "--config", peer_toml, "-q"},
           repeats, 200009);
    report("tiny200k.ngc", "pcnc check --fit -q (the CLI, 25 mm)", pcnc,
           {"check", tiny, "--config", config_path, "--fit", "-q"}, repeats, 200009);
  }
  const std::string lname = fs::relative(largest, shared + "/gcode/cam").string();
  report(lname.c_str(), "check --fit", self, {"--child", largest, "--config", config_path, "--fit"}, repeats);
  report(lname.c_str(), "check --fit + blocks", self,
         {"--child", largest, "--config", config_path, "--fit", "--blocks"}, repeats);
  report("tiny1m.ngc (1,000,005 lines)", "check + blocks (peer travel)", self,
         {"--child", big, "--config", config_path, "--peer", "--blocks"}, 1);
  fs::remove_all(dir);
  return 0;
}
