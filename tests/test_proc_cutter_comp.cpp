// test_proc_cutter_comp.cpp — G41 around a NURBS contour, end to end: `pcnc run --trace` (both
// processes, virtual clock), and the tool centre the rt commanded along the curve against the
// exact offset of the curve, computed here by an independent method: the rational B-spline
// evaluated by the Cox-de Boor recursion written below, sampled densely, each sample moved by
// the tool radius along the normal of a central-difference tangent. The biarcs are fitted
// within cutter_comp.fit_tolerance_mm (1 um): the commanded path must stay within 1 um + 1 um.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "service_procs.hpp"
#include "subprocess.hpp"
#include "test_paths.hpp"

namespace pcnc::test {
namespace {

struct P {
  double x, y;
};

// The G5.2 curve below: order 4, control points (program mm) with weight 1, LinuxCNC's open
// uniform knots 0 0 0 0 1 2 2 2 2.
const std::vector<P> kPoints = {{-6, -6}, {-2, 0}, {2, -6}, {6, 0}, {6, 6}};
const std::vector<double> kKnots = {0, 0, 0, 0, 1, 2, 2, 2, 2};
constexpr int kDegree = 3;

double basis(int i, int k, double u) {  // Cox-de Boor, N_{i,k}
  if (k == 0) {
    const bool last = u == kKnots.back() && kKnots[static_cast<std::size_t>(i + 1)] == kKnots.back() &&
                      kKnots[static_cast<std::size_t>(i)] < kKnots[static_cast<std::size_t>(i + 1)];
    return (kKnots[static_cast<std::size_t>(i)] <= u && u < kKnots[static_cast<std::size_t>(i + 1)]) || last ? 1.0 : 0.0;
  }
  double v = 0.0;
  const double d1 = kKnots[static_cast<std::size_t>(i + k)] - kKnots[static_cast<std::size_t>(i)];
  const double d2 = kKnots[static_cast<std::size_t>(i + k + 1)] - kKnots[static_cast<std::size_t>(i + 1)];
  if (d1 > 0) v += (u - kKnots[static_cast<std::size_t>(i)]) / d1 * basis(i, k - 1, u);
  if (d2 > 0) v += (kKnots[static_cast<std::size_t>(i + k + 1)] - u) / d2 * basis(i + 1, k - 1, u);
  return v;
}

P curve(double u) {
  P p{0, 0};
  for (int i = 0; i < static_cast<int>(kPoints.size()); ++i) {
    const double b = basis(i, kDegree, u);
    p.x += b * kPoints[static_cast<std::size_t>(i)].x;
    p.y += b * kPoints[static_cast<std::size_t>(i)].y;
  }
  return p;
}

double segment_distance(P a, P b, P q) {
  const double dx = b.x - a.x, dy = b.y - a.y, l2 = dx * dx + dy * dy;
  double t = l2 > 0 ? ((q.x - a.x) * dx + (q.y - a.y) * dy) / l2 : 0.0;
  t = std::fmax(0.0, std::fmin(1.0, t));
  return std::hypot(a.x + t * dx - q.x, a.y + t * dy - q.y);
}

TEST(CutterCompEndToEnd, G41NurbsToolPathStaysOnTheExactOffset) {
  const std::string dir = make_temp_dir("ccomp-nurbs");
  const std::string config = write_test_config(dir, "ccomp-nurbs");
  const std::string prog = dir + "/nurbs.ngc";
  {
    std::ofstream f(prog);
    f << "G21 G17 G90 F300\nG0 X-9 Y-9 Z0\nG1 Z-1\nG41.1 D2\nG1 X-6 Y-6\n"
         "G5.2 X-2 Y0 P1 L4\nX2 Y-6 P1\nX6 Y0 P1\nX6 Y6 P1\nG5.3\n"
         "G1 X8 Y8\nG40\nG1 X10 Y10\nG0 Z0\nM2\n";
  }
  const std::string trace = dir + "/trace.csv";
  const ProcessResult r =
      run_process({pcnc_exe(), "run", prog, "--clock", "virtual", "--config", config, "--trace", trace}, 120);
  ASSERT_EQ(r.exit_code, 0) << r.err;

  // The exact offset: program zero is the config's G54 (12.5, 12.5); the tool radius 1 mm on
  // the left (G41) of the direction of travel.
  constexpr double kOx = 12.5, kOy = 12.5, kR = 1.0;
  constexpr int kN = 200000;
  std::vector<P> offset;
  offset.reserve(kN + 1);
  const double u1 = kKnots.back(), h = 1e-6;
  for (int i = 0; i <= kN; ++i) {
    const double u = u1 * i / kN;
    const P a = curve(std::fmax(0.0, u - h)), b = curve(std::fmin(u1, u + h)), c = curve(u);
    const double tx = b.x - a.x, ty = b.y - a.y, tl = std::hypot(tx, ty);
    offset.push_back({kOx + c.x - kR * ty / tl, kOy + c.y + kR * tx / tl});
  }

  // The rows the rt commanded on the curve's line (6: its G5.2).
  std::ifstream in(trace);
  std::string row;
  std::getline(in, row);
  ASSERT_EQ(row.rfind("t,line,state,cmd_x,cmd_y", 0), 0u) << row;
  std::size_t k = 0, rows = 0;
  double worst = 0.0;
  while (std::getline(in, row)) {
    std::stringstream ss(row);
    std::string t, line, state, x, y;
    std::getline(ss, t, ',');
    std::getline(ss, line, ',');
    std::getline(ss, state, ',');
    std::getline(ss, x, ',');
    std::getline(ss, y, ',');
    if (line != "6") continue;
    const P q{std::stod(x), std::stod(y)};
    // The nearest offset sample, searched from the last one forward (the rows follow the curve).
    double best = 1e9;
    std::size_t best_k = k;
    const std::size_t lo = k > 4000 ? k - 4000 : 0;
    for (std::size_t j = lo; j < offset.size() && j < k + 40000; ++j) {
      const double d = std::hypot(offset[j].x - q.x, offset[j].y - q.y);
      if (d < best) best = d, best_k = j;
    }
    k = best_k;
    double d = 1e9;
    if (k > 0) d = std::fmin(d, segment_distance(offset[k - 1], offset[k], q));
    if (k + 1 < offset.size()) d = std::fmin(d, segment_distance(offset[k], offset[k + 1], q));
    worst = std::fmax(worst, d);
    ++rows;
  }
  EXPECT_GT(rows, 1000u) << "the curve is about 25 mm at 5 mm/s: thousands of 2 kHz rows";
  EXPECT_LE(worst, 0.001 + 0.001) << "largest distance of the commanded tool centre from the exact offset, mm";
  std::cout << "G41 NURBS: " << rows << " trace rows on the curve, max distance from the exact offset "
            << worst * 1000.0 << " um\n";
}

}  // namespace
}  // namespace pcnc::test
