// test_proc_smoothing.cpp — smoothing with the real processes (issue 14): a CAM-like run of
// short G1 moves under M21 with a path tolerance runs through `pcnc run --clock virtual
// --trace`; the traced commanded path stays within the tolerance of the programmed polyline
// (measured here against the programmed segments, not the curve the host made), the summary
// says how many moves were smoothed into how many blocks, and smoothing takes less machine
// time than the seed's rule (tolerance 0).
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "geometry/spline_fit.hpp"
#include "subprocess.hpp"
#include "test_paths.hpp"

namespace pcnc::test {
namespace {

constexpr double kTolerance = 0.005;

// A wavy 3D pass of 0.1 mm moves (program coordinates; the desktop mill's G54 is 12.5, 12.5, 25).
std::vector<Vec3> programmed_points() {
  std::vector<Vec3> p;
  for (int i = 0; i <= 160; ++i) {
    const double x = -8.0 + 0.1 * i;
    p.push_back({x, 3.0 * std::sin(x / 2.0), -1.0 - 0.5 * std::sin(x)});
  }
  return p;
}

std::string program_text() {
  std::ostringstream o;
  o.precision(6);
  o << std::fixed << "G21 G90 G17 G54 M21\n";
  const std::vector<Vec3> p = programmed_points();
  o << "G00 X" << p[0][0] << " Y" << p[0][1] << " Z" << p[0][2] << "\nG01 F1500\n";
  for (std::size_t i = 1; i < p.size(); ++i) o << "X" << p[i][0] << " Y" << p[i][1] << " Z" << p[i][2] << "\n";
  o << "M30\n";
  return o.str();
}

struct TracedRun {
  ProcessResult r;
  std::string trace, summary;
};

TracedRun run_traced(const std::string& dir, const std::string& config, const std::string& prog, const char* tolerance) {
  TracedRun x;
  x.trace = dir + "/trace-" + tolerance + ".csv";
  x.summary = dir + "/summary-" + tolerance + ".json";
  x.r = run_process({bin_dir() + "/tools/pcnc", "run", prog, "--clock", "virtual", "--config", config, "--tolerance",
                     tolerance, "--trace", x.trace, "--summary", x.summary, "-q"},
                    300);
  return x;
}

// The largest distance of the trace's commanded points (while the program's feed moves run)
// from the programmed polyline, in machine coordinates.
double commanded_deviation(const std::string& trace, const std::vector<Vec3>& machine_points) {
  std::ifstream in(trace);
  std::string line;
  std::getline(in, line);
  double worst = 0.0;
  while (std::getline(in, line)) {
    std::stringstream ss(line);
    std::string f[13];
    for (auto& x : f) std::getline(ss, x, ',');
    if (std::stoi(f[1]) < 4) continue;  // the rapid to the start
    const Vec3 c{std::stod(f[3]), std::stod(f[4]), std::stod(f[5])};
    double d = 1e300;
    for (std::size_t i = 0; i + 1 < machine_points.size(); ++i)
      d = std::min(d, point_segment_distance(c, machine_points[i], machine_points[i + 1]));
    worst = std::max(worst, d);
  }
  return worst;
}

double program_time(const std::string& out) {
  const auto at = out.find("program time");
  return at == std::string::npos ? -1.0 : std::stod(out.substr(out.find_first_of("0123456789", at)));
}

TEST(PcncRunSmoothing, TheCommandedPathStaysWithinTheToleranceOfTheProgrammedPolyline) {
  const std::string dir = make_temp_dir("smooth");
  const std::string config = write_test_config(dir, "smooth");
  const std::string prog = dir + "/wave.ngc";
  std::ofstream(prog) << program_text();
  std::vector<Vec3> machine;
  for (const Vec3& p : programmed_points()) machine.push_back(p + Vec3{12.5, 12.5, 25.0});

  const TracedRun smooth = run_traced(dir, config, prog, "0.005");
  ASSERT_EQ(smooth.r.exit_code, 0) << smooth.r.out << smooth.r.err;
  const double dev = commanded_deviation(smooth.trace, machine);
  EXPECT_LE(dev, kTolerance * 1.0001) << "the commanded path left the tolerance band of the programmed moves";
  EXPECT_GT(dev, 1e-5) << "the path was smoothed, not run through the points";
  std::ifstream sj(smooth.summary);
  std::stringstream s;
  s << sj.rdbuf();
  const std::string summary = s.str();
  EXPECT_NE(summary.find("\"smoothed_moves\": 160"), std::string::npos) << summary.substr(0, 2000);
  EXPECT_NE(smooth.r.out.find("160 G1 moves smoothed into"), std::string::npos) << smooth.r.out;

  const TracedRun seed = run_traced(dir, config, prog, "0");
  ASSERT_EQ(seed.r.exit_code, 0) << seed.r.out << seed.r.err;
  EXPECT_LE(commanded_deviation(seed.trace, machine), 1e-6) << "tolerance 0: through the programmed points";
  const double t_smooth = program_time(smooth.r.out), t_seed = program_time(seed.r.out);
  EXPECT_LT(t_smooth, t_seed);
  std::cout << "[ figures  ] wave of 160 G1 moves: smoothed " << t_smooth << " s (commanded path " << dev * 1000.0
            << " um from the polyline), seed rule " << t_seed << " s\n";
}

}  // namespace
}  // namespace pcnc::test
