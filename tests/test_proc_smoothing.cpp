// test_proc_smoothing.cpp — smoothing with the real processes (issue 14): a CAM-like run of
// short G1 moves under M21 with a path tolerance runs through `pcnc run --clock virtual
// --trace`; the traced commanded path stays within the tolerance of the programmed polyline
// (measured here against the programmed segments, not the curve the host made), the summary
// says how many moves were smoothed into how many blocks, and smoothing takes less machine
// time than the seed's rule (tolerance 0). A chain of short tangent arcs is packed into exact
// curves (host/gcode/arc_packing.hpp): the traced path stays on the programmed arcs, the ring
// carries fewer blocks, and the chain runs in less machine time than as arcs.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "geometry/spline_fit.hpp"
#include <nlohmann/json.hpp>
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

// A chain of 120 tangent arcs of 6° on radii 5.5-6.5 mm (0.6 mm each), G3 with I J, in
// program coordinates: each arc's center, radius and start angle for the check.
struct ProgramArc {
  double cx, cy, r, a0;
};

std::string arc_chain_text(std::vector<ProgramArc>& arcs) {
  std::ostringstream o;
  o.precision(6);
  // a lead-in along +X, tangent to the first arc: the only corner is the rapid's, on line 2
  o << std::fixed << "G21 G90 G17 G54 M21\nG00 X-2 Y-6 Z-1\nG01 X0 F6000\n";
  double x = 0.0, y = -6.0, heading = 0.0;
  const double sweep = 6.0 * M_PI / 180.0;
  for (int k = 0; k < 120; ++k) {
    const double r = 6.0 + 0.5 * std::sin(0.1 * k);
    const double cx = x - r * std::sin(heading), cy = y + r * std::cos(heading);  // left of travel
    const double a0 = std::atan2(y - cy, x - cx);
    const double ex = cx + r * std::cos(a0 + sweep), ey = cy + r * std::sin(a0 + sweep);
    o << "G03 X" << ex << " Y" << ey << " I" << cx - x << " J" << cy - y << "\n";
    arcs.push_back({cx, cy, r, a0});
    x = ex;
    y = ey;
    heading += sweep;
  }
  o << "M30\n";
  return o.str();
}

TEST(PcncRunSmoothing, AChainOfShortArcsIsPackedExactlyAndRunsFaster) {
  const std::string dir = make_temp_dir("arcpack");
  const std::string config = write_test_config(dir, "arcpack");
  const std::string prog = dir + "/arcs.ngc";
  std::vector<ProgramArc> arcs;
  std::ofstream(prog) << arc_chain_text(arcs);

  const TracedRun packed = run_traced(dir, config, prog, "0.005");
  ASSERT_EQ(packed.r.exit_code, 0) << packed.r.out << packed.r.err;
  // every commanded point of the arcs' lines on one of the programmed arcs (machine coordinates:
  // the desktop mill's G54 is 12.5, 12.5, 25), within 0.2 um: the rt rounds each flowing
  // junction between blocks of different curvature within its blend budget, here by up to
  // 0.08 um, as it does between the arc blocks themselves (at F600, not packed, the same)
  {
    std::ifstream in(packed.trace);
    std::string line;
    std::getline(in, line);
    double worst = 0.0;
    int rows = 0;
    while (std::getline(in, line)) {
      std::stringstream ss(line);
      std::string f[13];
      for (auto& v : f) std::getline(ss, v, ',');
      if (std::stoi(f[1]) < 4 || std::stoi(f[1]) > 123) continue;  // the G03 lines are 4..123
      const double px = std::stod(f[3]) - 12.5, py = std::stod(f[4]) - 12.5;
      double d = 1e300;
      for (const ProgramArc& a : arcs) {
        double phi = std::remainder(std::atan2(py - a.cy, px - a.cx) - a.a0, 2.0 * M_PI);
        if (phi < -1e-6 || phi > 6.0 * M_PI / 180.0 + 1e-6) continue;
        d = std::min(d, std::abs(std::hypot(px - a.cx, py - a.cy) - a.r));
      }
      worst = std::max(worst, d);
      ++rows;
    }
    EXPECT_GT(rows, 500);
    EXPECT_LT(worst, 2e-4) << "the packed curves are the programmed arcs";
  }
  std::ifstream sj(packed.summary);
  const nlohmann::json summary = nlohmann::json::parse(sj);
  EXPECT_EQ(summary.at("check").at("packed_arcs").get<int>(), 120);
  const int blocks = summary.at("check").at("packed_blocks").get<int>();
  EXPECT_GE(blocks, 120 / 15);  // at most 15 arcs of 2 control points each in a 32-point block
  EXPECT_LT(blocks, 20);
  EXPECT_LT(summary.at("check").at("packed_max_deviation_mm").get<double>(), 1e-6);
  EXPECT_NE(packed.r.out.find("120 arcs packed into"), std::string::npos) << packed.r.out;

  // tolerance 0 (the seed's rule): the arcs run as arc blocks, 4 of them in the ring, slower
  const TracedRun arcs_run = run_traced(dir, config, prog, "0");
  ASSERT_EQ(arcs_run.r.exit_code, 0) << arcs_run.r.out << arcs_run.r.err;
  std::ifstream sj0(arcs_run.summary);
  EXPECT_EQ(nlohmann::json::parse(sj0).at("check").at("packed_arcs").get<int>(), 0);
  const double t_packed = program_time(packed.r.out), t_arcs = program_time(arcs_run.r.out);
  EXPECT_LT(t_packed, t_arcs);
  std::cout << "[ figures  ] chain of 120 arcs of 0.6 mm: packed " << t_packed << " s in " << blocks
            << " blocks, as arcs " << t_arcs << " s\n";
}

}  // namespace
}  // namespace pcnc::test
