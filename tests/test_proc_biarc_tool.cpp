// test_proc_biarc_tool.cpp — `pcnc biarc` as users run it, on corpus programs: the lines it
// does not rewrite come out byte for byte, the output passes `pcnc check` as the input does,
// and the rewritten path stays within the tolerance of the input path. The deviation is
// computed here: the output's G2/G3 lines read by a small reader of this file, the input
// NURBS from the project's G5.2 reader (not the tool's), both densely sampled.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "gcode/nurbs_reader.hpp"
#include "geometry/nurbs.hpp"
#include "subprocess.hpp"
#include "test_paths.hpp"
#include "text_lines.hpp"

namespace pcnc {
namespace {

constexpr double kTol = 0.001;
constexpr double kRounding = 2e-6;  // the output's 6 decimals

std::string pcnc_bin() { return test::bin_dir() + "/tools/pcnc"; }

using test::split_lines;

// The words of a line, read by the project's G5.2 reader (not the tool's lexer); a line it
// cannot read has none.
struct Words {
  std::map<char, double> v;
  std::vector<double> g;
  bool has(char c) const { return v.count(c) != 0; }
};
Words words(const std::string& line) {
  GcodeWords w;
  std::string err;
  if (!split_gcode_words(line, w, err)) return {};
  return {w.value, w.g};
}

struct ToolRun {
  std::string out, err;
  int code = -1;
  std::vector<std::pair<int, int>> ranges;  // input lines replaced, from stderr
  std::vector<int> written;                 // the output lines that replaced each
};

ToolRun biarc(const std::string& file, const std::vector<std::string>& extra = {}) {
  std::vector<std::string> argv{pcnc_bin(), "biarc", file};
  argv.insert(argv.end(), extra.begin(), extra.end());
  const test::ProcessResult r = test::run_process(argv, 300);
  ToolRun run{r.out, r.err, r.exit_code, {}, {}};
  std::istringstream in(r.err);
  std::string l;
  while (std::getline(in, l)) {
    const std::string head = file + ":";
    if (l.rfind(head, 0) != 0) continue;
    int a = 0, b = 0;
    if (std::sscanf(l.c_str() + head.size(), "%d-%d:", &a, &b) != 2) continue;
    const std::size_t arrow = l.find("-> ");
    if (arrow == std::string::npos) continue;
    run.ranges.push_back({a, b});
    run.written.push_back(std::atoi(l.c_str() + arrow + 3));
  }
  return run;
}

// Every input line outside the replaced ranges is in the output, in order, unchanged; each
// replaced range became as many G1/G2/G3 lines as stderr says.
void expect_passthrough(const std::string& in_text, const ToolRun& r) {
  const std::vector<std::string> in = split_lines(in_text), out = split_lines(r.out);
  std::size_t o = 0, range = 0;
  for (std::size_t i = 0; i < in.size(); ++i) {
    const int line = static_cast<int>(i) + 1;
    if (range < r.ranges.size() && line == r.ranges[range].first) {
      ASSERT_GT(r.written[range], 0);
      for (int k = 0; k < r.written[range]; ++k, ++o) {
        ASSERT_LT(o, out.size());
        EXPECT_TRUE(out[o].rfind("G2 ", 0) == 0 || out[o].rfind("G3 ", 0) == 0 || out[o].rfind("G1 ", 0) == 0)
            << "output line " << o + 1 << ": " << out[o];
      }
      i = static_cast<std::size_t>(r.ranges[range].second) - 1;
      ++range;
      continue;
    }
    ASSERT_LT(o, out.size()) << "input line " << line << " missing";
    ASSERT_EQ(out[o], in[i]) << "input line " << line << " changed";
    ++o;
  }
  EXPECT_EQ(o, out.size());
  EXPECT_EQ(range, r.ranges.size());
}

// Writes `text` to a fresh temporary directory; returns the file's path.
std::string write_temp(const std::string& tag, const std::string& name, const std::string& text) {
  const std::string path = test::make_temp_dir(tag) + "/" + name;
  FILE* f = std::fopen(path.c_str(), "w");
  std::fwrite(text.data(), 1, text.size(), f);
  std::fclose(f);
  return path;
}

int check_status(const std::string& path) {
  return test::run_process({pcnc_bin(), "check", "--fit", path}, 300).exit_code;
}

// ---- the output's path, read here --------------------------------------------------------

struct Piece {  // one output move in plane coordinates
  bool arc = false;
  double x0, y0, x1, y1, cx = 0, cy = 0;
  bool ccw = false;
};

std::vector<std::pair<double, double>> sample(const Piece& p, int n) {
  std::vector<std::pair<double, double>> pts;
  if (!p.arc) {
    for (int i = 0; i <= n; ++i) pts.push_back({p.x0 + (p.x1 - p.x0) * i / n, p.y0 + (p.y1 - p.y0) * i / n});
    return pts;
  }
  const double r = std::hypot(p.x0 - p.cx, p.y0 - p.cy);
  const double a0 = std::atan2(p.y0 - p.cy, p.x0 - p.cx);
  double a1 = std::atan2(p.y1 - p.cy, p.x1 - p.cx);
  if (p.ccw) while (a1 <= a0) a1 += 2 * M_PI;
  else while (a1 >= a0) a1 -= 2 * M_PI;
  for (int i = 0; i <= n; ++i) {
    const double a = a0 + (a1 - a0) * i / n;
    pts.push_back({p.cx + r * std::cos(a), p.cy + r * std::sin(a)});
  }
  return pts;
}

double seg_dist(double px, double py, double ax, double ay, double bx, double by) {
  const double dx = bx - ax, dy = by - ay, L = dx * dx + dy * dy;
  double f = L > 0 ? ((px - ax) * dx + (py - ay) * dy) / L : 0;
  f = std::max(0.0, std::min(1.0, f));
  return std::hypot(px - ax - f * dx, py - ay - f * dy);
}

double poly_dist(double x, double y, const std::vector<std::pair<double, double>>& poly) {
  double best = 1e300;
  for (std::size_t i = 0; i + 1 < poly.size(); ++i)
    best = std::min(best, seg_dist(x, y, poly[i].first, poly[i].second, poly[i + 1].first, poly[i + 1].second));
  if (poly.size() == 1) best = std::hypot(x - poly[0].first, y - poly[0].second);
  return best;
}

// Reads the output (absolute G90, G91.1 centres, mm) and returns, per replaced range, its
// pieces in the plane, and the input's G1 points of that range.
struct Reading {
  std::vector<std::vector<Piece>> out_pieces;
  std::vector<std::vector<std::pair<double, double>>> in_points;
  std::vector<int> plane;  // normal axis per range
};

int plane_of(const Words& w, int current) {
  for (double g : w.g) {
    if (std::abs(g - 17) < 1e-9) return 2;
    if (std::abs(g - 18) < 1e-9) return 1;
    if (std::abs(g - 19) < 1e-9) return 0;
  }
  return current;
}

Reading read_ranges(const std::string& in_text, const ToolRun& r) {
  Reading rd;
  const char axes[3] = {'X', 'Y', 'Z'};
  auto plane_axes = [](int n) { return n == 2 ? std::pair{0, 1} : n == 1 ? std::pair{2, 0} : std::pair{1, 2}; };
  // input: positions before and after each line
  {
    double pos[3] = {0, 0, 0};
    int plane = 2;
    const std::vector<std::string> in = split_lines(in_text);
    std::size_t range = 0;
    for (std::size_t i = 0; i < in.size(); ++i) {
      const Words w = words(in[i]);
      plane = plane_of(w, plane);
      const int line = static_cast<int>(i) + 1;
      const bool inside = range < r.ranges.size() && line >= r.ranges[range].first && line <= r.ranges[range].second;
      if (inside && line == r.ranges[range].first) {
        const auto [a0, a1] = plane_axes(plane);
        rd.in_points.push_back({{pos[a0], pos[a1]}});
        rd.plane.push_back(plane);
      }
      for (int a = 0; a < 3; ++a)
        if (w.has(axes[a])) pos[a] = w.v.at(axes[a]);
      if (inside) {
        const auto [a0, a1] = plane_axes(plane);
        rd.in_points.back().push_back({pos[a0], pos[a1]});
        if (line == r.ranges[range].second) ++range;
      }
    }
  }
  // output: the lines that replaced each range, where the line counts place them
  {
    const std::vector<std::string> out = split_lines(r.out);
    long delta = 0;
    for (std::size_t k = 0; k < r.ranges.size(); ++k) {
      const int plane = rd.plane[k];
      const auto [a0, a1] = plane_axes(plane);
      double pos[3] = {0, 0, 0};
      pos[a0] = rd.in_points[k].front().first, pos[a1] = rd.in_points[k].front().second;
      rd.out_pieces.emplace_back();
      const long first = r.ranges[k].first - 1 + delta;
      for (long o = first; o < first + r.written[k]; ++o) {
        const std::string& l = out[static_cast<std::size_t>(o)];
        const Words w = words(l);
        double next[3] = {pos[0], pos[1], pos[2]};
        for (int a = 0; a < 3; ++a)
          if (w.has(axes[a])) next[a] = w.v.at(axes[a]);
        Piece p;
        p.x0 = pos[a0], p.y0 = pos[a1], p.x1 = next[a0], p.y1 = next[a1];
        p.arc = l[1] != '1';
        p.ccw = l[1] == '3';
        const char off[3] = {'I', 'J', 'K'};
        p.cx = p.x0 + (w.has(off[a0]) ? w.v.at(off[a0]) : 0.0);
        p.cy = p.y0 + (w.has(off[a1]) ? w.v.at(off[a1]) : 0.0);
        rd.out_pieces.back().push_back(p);
        for (int a = 0; a < 3; ++a) pos[a] = next[a];
      }
      delta += r.written[k] - (r.ranges[k].second - r.ranges[k].first + 1);
    }
  }
  return rd;
}

std::vector<std::pair<double, double>> dense_pieces(const std::vector<Piece>& ps, int per) {
  std::vector<std::pair<double, double>> pts;
  for (const Piece& p : ps)
    for (const auto& q : sample(p, per)) pts.push_back(q);
  return pts;
}

// ---- tests --------------------------------------------------------------------------------

TEST(BiarcTool, HelpIsTrue) {
  const test::ProcessResult r = test::run_process({pcnc_bin(), "biarc", "--help"});
  EXPECT_EQ(r.exit_code, 0);
  for (const char* opt : {"--tolerance", "--max-tool-radius", "--side", "--min-moves", "--max-segment", "--max-turn"})
    EXPECT_NE(r.out.find(opt), std::string::npos) << opt;
  EXPECT_EQ(test::run_process({pcnc_bin(), "biarc", "/nonexistent.ngc"}).exit_code, 2);
  EXPECT_EQ(test::run_process({pcnc_bin(), "biarc", test::shared_dir() + "/gcode/nurbs/g5.2/nurbs-xy.ngc", "--tolerance", "0"})
                .exit_code,
            2);
}

void expect_nurbs_file(const std::string& rel, int curves) {
  const std::string file = test::shared_dir() + rel;
  const ToolRun r = biarc(file);
  ASSERT_EQ(r.code, 0) << r.err;
  ASSERT_EQ(static_cast<int>(r.ranges.size()), curves) << r.err;
  const std::string text = test::read_file(file);
  expect_passthrough(text, r);
  // the output is a program pcnc accepts, as it accepts the input
  const std::string out_path = write_temp("biarc_tool", "out.ngc", r.out);
  EXPECT_EQ(check_status(out_path), check_status(file));
  // the arcs against the curves of the project's reader
  const NurbsProgram prog = read_nurbs_program(file);
  ASSERT_TRUE(prog.error.empty()) << prog.error;
  const Reading rd = read_ranges(text, r);
  ASSERT_EQ(rd.out_pieces.size(), prog.curves.size());
  for (std::size_t c = 0; c < prog.curves.size(); ++c) {
    const NurbsCurve& curve = prog.curves[c].curve;
    const int n = rd.plane[c];
    const int a0 = n == 2 ? 0 : n == 1 ? 2 : 1, a1 = n == 2 ? 1 : n == 1 ? 0 : 2;
    std::vector<std::pair<double, double>> dense_curve;
    for (int i = 0; i <= 20000; ++i) {
      const Vec3 p = nurbs_point(curve.view(), curve.u_min() + (curve.u_max() - curve.u_min()) * i / 20000);
      dense_curve.push_back({p[static_cast<std::size_t>(a0)], p[static_cast<std::size_t>(a1)]});
    }
    const auto arcs = dense_pieces(rd.out_pieces[c], 100);
    double h = 0;
    for (const auto& q : arcs) h = std::max(h, poly_dist(q.first, q.second, dense_curve));
    for (std::size_t i = 0; i < dense_curve.size(); i += 4)
      h = std::max(h, poly_dist(dense_curve[i].first, dense_curve[i].second, arcs));
    EXPECT_LE(h, kTol + kRounding) << rel << " curve " << c;
    EXPECT_GT(rd.out_pieces[c].size(), 1u);
  }
}

TEST(BiarcTool, LoopRemovalOutputStillChecks) {
  // every corpus NURBS and CAM program rewritten for a 3 mm tool: the arcs stay whole arcs
  for (const char* rel : {"/gcode/nurbs/g5.2/leto-xy.ngc", "/gcode/nurbs/g5.2/trident-xy-yz-zx.ngc",
                          "/gcode/cam/camotics/vcarve.ngc", "/gcode/cam/linuxcnc-tp/LHchips4.ngc"}) {
    const std::string file = test::shared_dir() + rel;
    const ToolRun r = biarc(file, {"--max-tool-radius", "3"});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find(" removed,"), std::string::npos) << rel;
    EXPECT_EQ(check_status(write_temp("biarc_tool_r3", "out.ngc", r.out)), check_status(file)) << rel;
  }
}

TEST(BiarcTool, NurbsXYWithinToleranceAndRestUnchanged) { expect_nurbs_file("/gcode/nurbs/g5.2/nurbs-xy.ngc", 1); }
TEST(BiarcTool, NurbsZXPlane) { expect_nurbs_file("/gcode/nurbs/g5.2/nurbs-zx.ngc", 1); }
TEST(BiarcTool, ThreePlanes) { expect_nurbs_file("/gcode/nurbs/g5.2/trident-xy-yz-zx.ngc", 3); }

TEST(BiarcTool, CamPolylineRunsWithinToleranceOfEveryPoint) {
  const std::string file = test::shared_dir() + "/gcode/cam/ugs/ShapeOko_Calibration_Pattern_01b.ngc";
  const ToolRun r = biarc(file);
  ASSERT_EQ(r.code, 0) << r.err;
  ASSERT_GT(r.ranges.size(), 5u);
  const std::string text = test::read_file(file);
  expect_passthrough(text, r);
  const std::string out_path = write_temp("biarc_tool_cam", "out.ngc", r.out);
  EXPECT_EQ(check_status(out_path), 0);
  EXPECT_EQ(split_lines(r.out).size() < split_lines(text).size(), true);  // fewer blocks
  const Reading rd = read_ranges(text, r);
  ASSERT_EQ(rd.out_pieces.size(), rd.in_points.size());
  for (std::size_t k = 0; k < rd.in_points.size(); ++k) {
    const auto& pts = rd.in_points[k];
    const auto arcs = dense_pieces(rd.out_pieces[k], 200);
    double point_dev = 0;
    for (const auto& p : pts) point_dev = std::max(point_dev, poly_dist(p.first, p.second, arcs));
    EXPECT_LE(point_dev, kTol + kRounding) << "range " << r.ranges[k].first;
    // arcs to the programmed segments: the tolerance plus the chords' own sagitta, estimated
    // here from the circle through each three consecutive points
    double sag = 0;
    for (std::size_t i = 1; i + 1 < pts.size(); ++i) {
      const double ax = pts[i - 1].first, ay = pts[i - 1].second, bx = pts[i].first, by = pts[i].second,
                   cx = pts[i + 1].first, cy = pts[i + 1].second;
      const double cr = std::abs((bx - ax) * (cy - ay) - (by - ay) * (cx - ax));
      const double ab = std::hypot(bx - ax, by - ay), bc = std::hypot(cx - bx, cy - by), ca = std::hypot(cx - ax, cy - ay);
      const double kappa = ab * bc * ca > 0 ? 2 * cr / (ab * bc * ca) : 0;
      sag = std::max(sag, std::max(ab, bc) * std::max(ab, bc) * kappa / 8);
    }
    double seg_dev = 0;
    for (const auto& q : arcs) seg_dev = std::max(seg_dev, poly_dist(q.first, q.second, pts));
    EXPECT_LE(seg_dev, kTol + 2 * sag + kRounding) << "range " << r.ranges[k].first;
  }
}

TEST(BiarcTool, RunsBeforeModalLinesEndOnAnExplicitG1) {
  // LHchips4 (G18, modal X Z lines after each run): the output still checks, and no line of
  // the output moves by a modal G2/G3 it did not have
  const std::string file = test::shared_dir() + "/gcode/cam/linuxcnc-tp/LHchips4.ngc";
  const ToolRun r = biarc(file);
  ASSERT_EQ(r.code, 0);
  ASSERT_FALSE(r.ranges.empty());
  expect_passthrough(test::read_file(file), r);
  const std::vector<std::string> out = split_lines(r.out);
  for (std::size_t i = 1; i < out.size(); ++i) {
    const bool arc = out[i - 1].rfind("G2 ", 0) == 0 || out[i - 1].rfind("G3 ", 0) == 0;
    if (!arc) continue;
    const Words w = words(out[i]);
    const bool axis_words = w.has('X') || w.has('Y') || w.has('Z');
    EXPECT_FALSE(axis_words && w.g.empty()) << "output line " << i + 1 << " would move as an arc: " << out[i];
  }
  const std::string out_path = write_temp("biarc_tool_lh", "out.ngc", r.out);
  EXPECT_EQ(check_status(out_path), check_status(file));
}

// "the contour moved up to X mm" from the summary line of stderr.
double moved(const std::string& err) {
  const std::string key = "the contour moved up to ";
  const std::size_t at = err.rfind(key);
  return at == std::string::npos ? -1.0 : std::atof(err.c_str() + at + key.size());
}

TEST(BiarcTool, LoopRemovalOnlyWithATool) {
  // a smooth G1 run around a 1 mm radius: a 2 mm tool inside it tangles
  // an inverted U: a leg up at 8 degrees from the vertical, a half circle of radius 1 about
  // (1, 0), a leg down splaying out the same way; 2 mm wide at the top, 12 mm long legs: the
  // offsets of the legs by 2 mm inside cross where the slot is 4 mm wide
  const double t = std::tan(8.0 * M_PI / 180.0);
  std::string prog = "G21 G90 G17\nG0 X" + std::to_string(-12 * t) + " Y-12\nG1 F300\n";
  auto add = [&prog](double x, double y) {
    char l[64];
    std::snprintf(l, sizeof l, "X%.4f Y%.4f\n", x, y);
    prog += l;
  };
  for (int i = 1; i <= 40; ++i) add(-12 * t + 0.3 * t * i, -12 + 0.3 * i);
  for (int i = 1; i <= 60; ++i) add(1.0 - std::cos(M_PI * i / 60), std::sin(M_PI * i / 60));
  for (int i = 1; i <= 40; ++i) add(2 + 0.3 * t * i, -0.3 * i);
  prog += "G0 Z5\nM2\n";
  const std::string path = write_temp("biarc_tool_loop", "bend.ngc", prog);
  const ToolRun plain = biarc(path);
  ASSERT_EQ(plain.code, 0) << plain.err;
  EXPECT_EQ(plain.err.find("removed"), std::string::npos);
  // the bend turns right: a tool of radius 2 on the right (inside) tangles
  const ToolRun tool = biarc(path, {"--max-tool-radius", "2", "--side", "right"});
  ASSERT_EQ(tool.code, 0) << tool.err;
  EXPECT_NE(tool.err.find("removed"), std::string::npos) << tool.err;
  EXPECT_NE(tool.out, plain.out);
  EXPECT_GT(moved(tool.err), 1.0) << tool.err;  // the slot is bridged where it is 4 mm wide
  EXPECT_EQ(check_status(write_temp("biarc_tool_loop_out", "out.ngc", tool.out)), 0);
  // outside (left) the contour is convex: at most the fit's own micrometre wiggles where the
  // legs meet the half circle are touched
  const ToolRun left = biarc(path, {"--max-tool-radius", "2", "--side", "left"});
  ASSERT_EQ(left.code, 0);
  EXPECT_LT(moved(left.err), 0.01) << left.err;
}

}  // namespace
}  // namespace pcnc
