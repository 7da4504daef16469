// test_proc_ruled_tool.cpp — `pcnc ruled` as users run it: the program's structure (G5.4 groups
// of X Y Z I J K lines, each piece starting where the one before ended, inside the travel),
// the tips and axes against the example's formula written out here (height and gradient), the
// gap between passes measured here against P = 2 sqrt(h (2R - h)), the printed figures against
// the file, Tables 1-2, the JSON form, a surface file, and the exit codes of bad input.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "config/surface_file.hpp"
#include "geometry/bspline_surface.hpp"
#include "subprocess.hpp"
#include "test_paths.hpp"
#include "text_lines.hpp"

namespace pcnc {
namespace {

std::string pcnc_bin() { return test::bin_dir() + "/tools/pcnc"; }

std::string scratch_dir() {
  std::string t = (std::filesystem::temp_directory_path() / "pcnc-ruled-XXXXXX").string();
  EXPECT_NE(mkdtemp(t.data()), nullptr);
  return t;
}

std::string read(const std::string& path) {
  std::ifstream f(path);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

struct Point {
  double x, y, z, i, j, k;
};
struct Group {
  std::string head;
  std::vector<Point> points;
};
struct Program {
  std::vector<Group> groups;
  std::vector<std::string> other;  // lines outside groups
  bool well_formed = true;
};

Program parse(const std::string& text) {
  Program p;
  bool in = false;
  for (const std::string& l : test::split_lines(text)) {
    if (l.rfind("G5.4", 0) == 0) {
      if (in) p.well_formed = false;
      in = true;
      p.groups.push_back({l, {}});
    } else if (l == "G5.5") {
      if (!in) p.well_formed = false;
      in = false;
    } else if (in) {
      Point q{};
      char rest = 0;
      if (std::sscanf(l.c_str(), "X%lf Y%lf Z%lf I%lf J%lf K%lf%c", &q.x, &q.y, &q.z, &q.i, &q.j, &q.k, &rest) != 6)
        p.well_formed = false;
      p.groups.back().points.push_back(q);
    } else {
      p.other.push_back(l);
    }
  }
  if (in) p.well_formed = false;
  return p;
}

// The example in program coordinates on the desktop mill: 25 x 25 mm centred on program zero,
// 2.5 mm high, its top 2 mm below program zero; written out from the seed-sized formula.
constexpr double kSize = 25.0, kScale = kSize / 200.0, kBase = -2.0 - 2.5;
double z_of(double x, double y) {
  const double a = (x + 12.5) / kSize, b = (y + 12.5) / kSize;
  return kBase + kScale * (4 + 12 * (3 * b * b - 2 * b * b * b) + 16 * a * (1 - a) * (2 * b - 1));
}
std::array<double, 3> normal_of(double x, double y) {
  const double a = (x + 12.5) / kSize, b = (y + 12.5) / kSize;
  const double zx = kScale * 16 * (1 - 2 * a) * (2 * b - 1) / kSize;
  const double zy = kScale * (12 * (6 * b - 6 * b * b) + 32 * a * (1 - a)) / kSize;
  const double n = std::sqrt(zx * zx + zy * zy + 1);
  return {-zx / n, -zy / n, 1 / n};
}

double figure(const std::string& out, const std::string& key) {
  const std::size_t at = out.find(key);
  if (at == std::string::npos) return NAN;
  return std::atof(out.c_str() + at + key.size());
}

TEST(RuledTool, ExampleProgramAndFigures) {
  const std::string dir = scratch_dir(), ngc = dir + "/ex.ngc", js = dir + "/ex.json";
  const test::ProcessResult r = test::run_process(
      {pcnc_bin(), "ruled", "--config", test::default_config(), "--samples", "3", "-o", ngc, "--json", js}, 300);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Program prog = parse(read(ngc));
  ASSERT_TRUE(prog.well_formed);
  const double R = 1.0, h = 0.005, P = 2 * std::sqrt(h * (2 * R - h));

  // approach, passes and links alternating, retract
  ASSERT_GE(prog.groups.size(), 5u);
  const std::size_t passes = (prog.groups.size() - 1) / 2;
  EXPECT_EQ(prog.groups.size(), 2 * passes + 1);
  EXPECT_NEAR(figure(r.out, "pass interval     P "), P, 1e-6);
  EXPECT_EQ(figure(r.out, "passes            "), static_cast<double>(passes));
  // TCP on before the first group, off at the end
  ASSERT_GE(prog.other.size(), 5u);
  EXPECT_NE(std::find_if(prog.other.begin(), prog.other.end(), [](const std::string& l) { return l.rfind("M428", 0) == 0; }),
            prog.other.end());
  EXPECT_EQ(prog.other.back(), "M2");

  // every piece starts where the one before ended; unit axes; inside the X/Y travel
  double chord_sum = 0.0;
  for (std::size_t g = 0; g < prog.groups.size(); ++g) {
    const Group& gr = prog.groups[g];
    ASSERT_GE(gr.points.size(), 2u) << g;
    EXPECT_NE(gr.head.find(" F600.000"), std::string::npos);
    for (std::size_t i = 0; i < gr.points.size(); ++i) {
      const Point& q = gr.points[i];
      EXPECT_NEAR(std::sqrt(q.i * q.i + q.j * q.j + q.k * q.k), 1.0, 2e-7);
      EXPECT_LE(std::abs(q.x), 12.5 + 1e-5);
      EXPECT_LE(std::abs(q.y), 12.5 + 1e-5);
      EXPECT_LE(q.z, 1e-9);
      if (i > 0) {
        const Point& a = gr.points[i - 1];
        chord_sum += std::hypot(q.x - a.x, q.y - a.y, q.z - a.z);
        if (g % 2 == 1) {  // a pass: set points 1 mm apart in y (plus the slope)
          EXPECT_LE(std::hypot(q.x - a.x, q.y - a.y, q.z - a.z), 1.0 + 0.2) << g;
        }
      }
    }
    if (g > 0) {
      const Point& a = prog.groups[g - 1].points.back();
      const Point& b = gr.points.front();
      EXPECT_LT(std::hypot(a.x - b.x, a.y - b.y, a.z - b.z), 1e-9);
      EXPECT_LT(std::hypot(a.i - b.i, a.j - b.j, a.k - b.k), 1e-9);
    }
  }
  const Point& start = prog.groups.front().points.front();
  EXPECT_EQ(start.k, 1.0);
  EXPECT_NEAR(start.z, 0.0, 1e-9);  // the clearance: 2 mm above the top, program zero
  EXPECT_NEAR(prog.groups.back().points.back().z, 0.0, 1e-9);
  // the path length: the curves' length is at least the chords' and close to it
  const double length = figure(r.out, "path length       ");
  EXPECT_GE(length, chord_sum - 1e-3);
  EXPECT_LT(length, chord_sum * 1.001);
  EXPECT_NEAR(figure(r.out, "feed time         "), length / 10.0, 1e-3);
  // the model between set points: within a micrometre of the exact path at 1 mm spacing
  const double model_tip_um = figure(r.out, "ruled model       tip within ");
  EXPECT_GT(model_tip_um, 0.0);
  EXPECT_LT(model_tip_um, 1.0);

  // each pass: constant X, the tip on the surface (lead 0: the tip is the contact point), the
  // axis the formula's normal; the gap to the next pass measured here
  std::vector<const Group*> pass_groups;
  for (std::size_t g = 1; g + 1 < prog.groups.size(); g += 2) pass_groups.push_back(&prog.groups[g]);
  ASSERT_EQ(pass_groups.size(), passes);
  EXPECT_NEAR(pass_groups.front()->points.front().x, -12.5, 1e-5);
  EXPECT_NEAR(pass_groups.back()->points.front().x, 12.5, 1e-5);
  double widest = 0.0;
  for (std::size_t k = 0; k < passes; ++k) {
    const Group& g = *pass_groups[k];
    EXPECT_NEAR(std::abs(g.points.back().y - g.points.front().y), 25.0, 1e-5);
    for (const Point& q : g.points) {
      EXPECT_NEAR(q.x, g.points.front().x, 1e-9);
      EXPECT_NEAR(q.z, z_of(q.x, q.y), 1.1e-5);
      const auto n = normal_of(q.x, q.y);
      EXPECT_NEAR(q.i, n[0], 2e-6);
      EXPECT_NEAR(q.j, n[1], 2e-6);
      EXPECT_NEAR(q.k, n[2], 2e-6);
    }
    if (k + 1 < passes) {
      const double x1 = pass_groups[k + 1]->points.front().x;
      for (const Point& q : g.points) {
        // the nearest point of the next pass's contact curve (golden section over its y)
        auto dist = [&](double y) { return std::hypot(x1 - q.x, y - q.y, z_of(x1, y) - q.z); };
        double lo = q.y - 1, hi = q.y + 1;  // beyond the edge: the formula continued
        const double gr = (std::sqrt(5.0) - 1) / 2;
        for (int it = 0; it < 120; ++it) {
          const double m1 = hi - gr * (hi - lo), m2 = lo + gr * (hi - lo);
          (dist(m1) < dist(m2) ? hi : lo) = dist(m1) < dist(m2) ? m2 : m1;
        }
        const double d = dist(0.5 * (lo + hi));
        EXPECT_LE(d, P + 3e-5) << "pass " << k + 1;
        widest = std::max(widest, d);
      }
    }
  }
  EXPECT_GT(widest, 0.99 * P);

  // Tables 1-2: three samples; the first sample's A is the first pass's first axis, the frame
  // orthonormal to the printed precision
  EXPECT_NE(r.out.find("sample 3:"), std::string::npos);
  EXPECT_EQ(r.out.find("sample 4:"), std::string::npos);
  const std::size_t s1 = r.out.find("sample 1:");
  ASSERT_NE(s1, std::string::npos);
  double f[3][3];
  for (int row = 0; row < 3; ++row) {
    const std::string key = std::string(row == 0 ? "O" : row == 1 ? "A" : "N") + "  frame ";
    const std::size_t at = r.out.find(key, s1);
    ASSERT_NE(at, std::string::npos);
    ASSERT_EQ(std::sscanf(r.out.c_str() + at + key.size(), "%lf %lf %lf", &f[row][0], &f[row][1], &f[row][2]), 3);
  }
  const Point& p0 = pass_groups.front()->points.front();
  EXPECT_NEAR(f[1][0], p0.i, 1e-4);
  EXPECT_NEAR(f[1][1], p0.j, 1e-4);
  EXPECT_NEAR(f[1][2], p0.k, 1e-4);
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b)
      EXPECT_NEAR(f[a][0] * f[b][0] + f[a][1] * f[b][1] + f[a][2] * f[b][2], a == b ? 1.0 : 0.0, 3e-4);
  EXPECT_GT(figure(r.out, "ds/du "), 0.0);

  // the JSON form holds the same pieces
  const nlohmann::json j = nlohmann::json::parse(read(js));
  EXPECT_EQ(j.at("format"), "pcnc-ruled-program");
  ASSERT_EQ(j.at("pieces").size(), prog.groups.size());
  for (std::size_t g = 0; g < prog.groups.size(); g += 7) {
    const auto& pts = j.at("pieces")[g].at("points");
    const auto& axs = j.at("pieces")[g].at("axes");
    ASSERT_EQ(pts.size(), prog.groups[g].points.size());
    for (std::size_t i = 0; i < pts.size(); ++i) {
      const Point& q = prog.groups[g].points[i];
      EXPECT_NEAR(pts[i][2].get<double>(), q.z, 6e-6);
      EXPECT_NEAR(axs[i][1].get<double>(), q.j, 6e-8);
    }
  }
  std::filesystem::remove_all(dir);
}

TEST(RuledTool, SurfaceFileAndLead) {
  // a tilted plane z = 0.1 x - 3 over [-10, 10] x [-5, 5] as a bicubic surface file
  BSplineSurface s;
  s.degree = 3;
  s.count_u = 4;
  s.count_v = 4;
  s.knots_u = {0, 0, 0, 0, 1, 1, 1, 1};
  s.knots_v = s.knots_u;
  for (int jj = 0; jj < 4; ++jj)
    for (int ii = 0; ii < 4; ++ii) {
      const double x = -10 + 20.0 * ii / 3, y = -5 + 10.0 * jj / 3;
      s.points.push_back({x, y, 0.1 * x - 3});
    }
  const std::string dir = scratch_dir(), sf = dir + "/plane.json", ngc = dir + "/p.ngc";
  save_surface_file(sf, s);
  const test::ProcessResult r =
      test::run_process({pcnc_bin(), "ruled", sf, "--tool-radius", "2", "--cusp", "0.02", "--lead", "10",
                         "--point-spacing", "2.5", "--samples", "0", "-o", ngc},
                        120);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Program prog = parse(read(ngc));
  ASSERT_TRUE(prog.well_formed);
  const double R = 2.0, P = 2 * std::sqrt(0.02 * (2 * R - 0.02));
  // the plane's passes at constant x, P apart across the slope: dx sqrt(1 + 0.1^2) = P
  const std::size_t passes = (prog.groups.size() - 1) / 2;
  const double width = 20.0 * std::sqrt(1.01);
  EXPECT_EQ(passes, static_cast<std::size_t>(std::ceil(width / P)) + 1);
  const double n[3] = {-0.1 / std::sqrt(1.01), 0, 1 / std::sqrt(1.01)};
  const double lead = 10 * M_PI / 180;
  for (std::size_t g = 1; g + 1 < prog.groups.size(); g += 2) {
    const Group& gr = prog.groups[g];
    EXPECT_EQ(gr.points.size(), 5u);  // 10 mm at 2.5 mm
    const double dir = gr.points.back().y > gr.points.front().y ? 1.0 : -1.0;
    if (g + 2 < prog.groups.size() - 2) {  // not into the last pass, on the edge
      const double dx = prog.groups[g + 2].points.front().x - gr.points.front().x;
      EXPECT_NEAR(dx * std::sqrt(1.01), P, 1e-4);  // the tip moves with the contact on a plane
    }
    for (const Point& q : gr.points) {
      // the axis: the normal tilted by the lead toward the travel (+-y)
      EXPECT_NEAR(q.i, std::cos(lead) * n[0], 1e-6);
      EXPECT_NEAR(q.j, dir * std::sin(lead), 1e-6);
      EXPECT_NEAR(q.k, std::cos(lead) * n[2], 1e-6);
      // the ball centre tip + R a is R above the plane along its normal
      const double cx = q.x + R * q.i, cy = q.y + R * q.j, cz = q.z + R * q.k;
      EXPECT_NEAR((cz - (0.1 * cx - 3)) / std::sqrt(1.01), R, 2e-5);
      (void)cy;
    }
  }
  std::filesystem::remove_all(dir);
}

TEST(RuledTool, BadInputExitsTwo) {
  const std::string dir = scratch_dir(), ngc = dir + "/x.ngc", bad = dir + "/bad.json";
  std::ofstream(bad) << "{\"format\": \"nope\"}";
  const std::vector<std::vector<std::string>> cases = {
      {"--cusp", "2", "-o", ngc},                  // h > R
      {"--tool-radius", "-1", "-o", ngc},
      {"--feed", "0", "-o", ngc},
      {"-o", dir + "/no/such/dir/x.ngc"},          // cannot be written
      {},                                          // no -o
      {bad, "-o", ngc},                            // not a surface file
      {"--config", dir + "/none.toml", "-o", ngc}, // no config
      {"--frobnicate", "-o", ngc},
  };
  for (const auto& c : cases) {
    std::vector<std::string> argv{pcnc_bin(), "ruled"};
    argv.insert(argv.end(), c.begin(), c.end());
    const test::ProcessResult r = test::run_process(argv, 60);
    EXPECT_EQ(r.exit_code, 2) << (c.empty() ? std::string("(none)") : c[0]) << ": " << r.err;
    EXPECT_FALSE(r.err.empty());
  }
  EXPECT_FALSE(std::filesystem::exists(ngc));
  const test::ProcessResult help = test::run_process({pcnc_bin(), "ruled", "--help"}, 60);
  EXPECT_EQ(help.exit_code, 0);
  EXPECT_NE(help.out.find("G5.4"), std::string::npos);
  EXPECT_NE(help.out.find("--tool-radius"), std::string::npos);
  EXPECT_NE(help.out.find("Exit status"), std::string::npos) << help.out;
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace pcnc
