// test_proc_ruled.cpp — ruled-surface pieces (G5.4 ... G5.5, issue 17) through the real
// pcnc-host and pcnc-rt (virtual clock) on configs/desktop-5axis.toml (XYZAC trunnion), checked
// from the trace alone: the swept tool axis (forward kinematics of the commanded joints, and of
// the measured ones) stays on the intended ruled surface (the Ferguson chains through the set
// points and tool vectors, docs/ruled-surface.md rule 5), the tip's speed is the programmed feed
// within 0.1 % where it is constant, no joint leaves its travel or exceeds its velocity, a piece
// longer than a block flows across its split, and the program reaches its end.
// The first test's program: the tool tilted away from the pole with TCP off, then under TCP a 41-point pass
// (split into two blocks), a short link with a turned tangent, and a second pass back.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cctype>
#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

#include "config/config.hpp"
#include "config/joint_map.hpp"
#include "geometry/kinematics.hpp"
#include "gcode/ruled_program.hpp"
#include "geometry/ruled_model.hpp"
#include "ipc/trace_format.hpp"
#include "five_axis_trace.hpp"
#include "test_paths.hpp"
#include "service_procs.hpp"
#include "test_constants.hpp"

namespace pcnc::test {
namespace {


using Row = FiveAxisRow;

// One piece as programmed: set points (workpiece = machine coordinates of the tip, mm) and unit
// tool vectors, and the ruled surface they define.
struct Piece {
  int line = 0;  // the G5.4's line
  std::vector<Vec3> points, axes;
  RuledModel model;
};

// Distance of the swept tool axis at (tip, axis) from the piece's ruled surface: the tip's
// nearest point c(u) on the directrix (dense search, then refined), and the larger of the tip's
// distance and the distance of the point `lever` mm up the tool from c(u) + lever e(u).
double axis_deviation(const Piece& p, const Vec3& tip, const Vec3& axis, double lever, double& u_hint) {
  const RuledCurves c = p.model.curves();
  const double n = static_cast<double>(p.model.directrix.size());
  auto dist = [&](double u) { return norm(ruled_jet(c, u).c.p - tip); };
  double best = u_hint, bd = dist(best);
  for (double u = std::max(0.0, u_hint - 2.0); u <= std::min(n, u_hint + 2.0); u += 0.01) {
    const double d = dist(u);
    if (d < bd) bd = d, best = u;
  }
  double lo = std::max(0.0, best - 0.01), hi = std::min(n, best + 0.01);
  for (int k = 0; k < 60; ++k) {  // golden-section refinement
    const double a = hi - 0.618 * (hi - lo), b = lo + 0.618 * (hi - lo);
    if (dist(a) < dist(b)) hi = b; else lo = a;
  }
  u_hint = 0.5 * (lo + hi);
  const RuledJet j = ruled_jet(c, u_hint);
  return std::max(norm(j.c.p - tip), norm((j.c.p + lever * j.e.p) - (tip + lever * axis)));
}

constexpr double kFeed = 600.0;  // mm/min

TEST(RuledRun, PiecesFollowTheRuledSurfaceAtTheFeedWithinTheJointLimits) {
  const std::string dir = make_temp_dir("ruled");
  const std::string config = write_five_axis_config(dir, "ruled");
  const MachineConfig cfg = load_config(config);
  ASSERT_EQ(cfg.kinematics.kind, KinematicsKind::kTableTable);
  const Kinematics kin = kinematics_with_tool(cfg, 0.0);  // no tool table: TCP with length 0

  // Where the tool stands after the TCP-off moves: G0 X-4 Y-2 Z-5, G1 A12 C35.
  const Vec3 xyz0 = Vec3{-4.0, -2.0, -5.0} + kG54;
  const Rot3 rot0{12.0 * kRadPerDeg, 0.0, 35.0 * kRadPerDeg};
  const ToolPose pose0 = forward(kin, to_joints(cfg, xyz0, rot0));

  std::ostringstream prog;
  int n = 0;
  auto line = [&](const std::string& text) {
    prog << text << "\n";
    return ++n;
  };
  std::vector<Piece> pieces;
  line("G21 G90 G94");
  line("G0 X-4 Y-2 Z-5");
  line("G1 A12 C35 F3600");
  line("M428");
  // pass 1: 40 segments (two blocks), 8 mm along X with a gentle Z wave, the axis swinging
  // about the start axis by up to 0.12 rad toward +Y and back
  auto swing = [&](double t, double amp, const Vec3& side) { return normalized(pose0.axis + (amp * std::sin(3.14159265358979 * t)) * side); };
  std::vector<Vec3> pts, axes;
  const Vec3 t0 = pose0.tip;
  for (int k = 0; k <= 40; ++k) {
    const double t = k / 40.0;
    pts.push_back(t0 + Vec3{8.0 * t, 0.6 * std::sin(2.0 * 3.14159265358979 * t), -0.5 * t});
    axes.push_back(swing(t, 0.12, Vec3{0.0, 1.0, 0.0}));
  }
  // link: 1 mm along +Y, the axis kept
  std::vector<Vec3> lpts{pts.back(), pts.back() + Vec3{0.0, 0.5, 0.0}, pts.back() + Vec3{0.0, 1.0, 0.0}};
  std::vector<Vec3> laxes{axes.back(), axes.back(), axes.back()};
  // pass 2: back along -X, the axis swinging toward +X
  std::vector<Vec3> p2, a2;
  for (int k = 0; k <= 20; ++k) {
    const double t = k / 20.0;
    p2.push_back(lpts.back() + Vec3{-6.0 * t, 0.0, 0.3 * std::sin(3.14159265358979 * t)});
    a2.push_back(swing(t, 0.1, Vec3{1.0, 0.0, 0.0}));
  }
  // the program's text rounds to 1e-6 mm and 1e-9: the intended surface is built from the same numbers
  auto emit = [&](const std::vector<Vec3>& P, const std::vector<Vec3>& A) {
    Piece p;
    char buf[200];
    std::snprintf(buf, sizeof buf, "G5.4 F%.0f", kFeed);
    p.line = line(buf);
    for (std::size_t k = 0; k < P.size(); ++k) {
      const Vec3 q = P[k] - kG54;
      std::snprintf(buf, sizeof buf, "X%.6f Y%.6f Z%.6f I%.9f J%.9f K%.9f", q[0], q[1], q[2], A[k][0], A[k][1], A[k][2]);
      line(buf);
      double v[6];
      std::sscanf(buf, "X%lf Y%lf Z%lf I%lf J%lf K%lf", &v[0], &v[1], &v[2], &v[3], &v[4], &v[5]);
      p.points.push_back(kG54 + Vec3{v[0], v[1], v[2]});
      p.axes.push_back(normalized(Vec3{v[3], v[4], v[5]}));
    }
    line("G5.5");
    // the host takes the first point as the pose the tool stands in (rule 3): so does the surface
    p.points[0] = pieces.empty() ? pose0.tip : pieces.back().points.back();
    p.axes[0] = pieces.empty() ? pose0.axis : pieces.back().axes.back();
    RuledModelResult m = ruled_model_through(p.points, p.axes, RulingForm::kVector);
    if (!m.error.empty()) throw std::runtime_error(m.error);
    p.model = m.model;
    pieces.push_back(p);
  };
  emit(pts, axes);
  emit(lpts, laxes);
  emit(p2, a2);
  line("G1 Z-4 F600");
  line("M429");
  line("M2");
  const std::string path = dir + "/ruled.ngc";
  std::ofstream(path) << prog.str();

  // check shows the ruled blocks: the first pass split in two, the others one each
  const ProcessResult chk = run_process({pcnc_exe(), "check", path, "--config", config, "--print-blocks"}, 120);
  ASSERT_EQ(chk.exit_code, 0) << chk.out << chk.err;
  int ruled_blocks = 0;
  for (std::size_t at = chk.out.find(" ruled ("); at != std::string::npos; at = chk.out.find(" ruled (", at + 1)) ++ruled_blocks;
  EXPECT_EQ(ruled_blocks, 4) << chk.out;

  const std::string trace = dir + "/ruled.csv";
  const ProcessResult r = run_process({pcnc_exe(), "run", path, "--config", config, "--clock", "virtual", "--trace", trace}, 300);
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("result            completed"), std::string::npos) << r.out;

  const std::vector<Row> rows = read_five_axis_trace(trace, cfg.rotary_mask());
  ASSERT_GT(rows.size(), 1000u);
  const double dt = cfg.cycle_period_s();
  const double feed = kFeed / 60.0;
  std::map<int, const Piece*> by_line;
  for (const Piece& p : pieces) by_line[p.line] = &p;
  std::map<int, double> hint;
  std::map<int, int> rows_per_piece;
  double worst_cmd = 0.0, worst_act = 0.0, worst_feed = 0.0, min_mid_speed = 1e9;
  int constant_rows = 0;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const Row& row = rows[i];
    const Joints qc = to_joints(cfg, row.s.commanded, row.j.commanded);
    const Joints qa = to_joints(cfg, row.s.actual, row.j.actual);
    ASSERT_EQ(commanded_joint_violation(cfg, rows, i), "");
    const auto pc = by_line.find(static_cast<int>(row.s.line));
    if (pc == by_line.end() || row.s.state != MachineState::kRunning) continue;
    ++rows_per_piece[pc->first];
    const ToolPose tc = forward(kin, qc), ta = forward(kin, qa);
    double& h = hint[pc->first];
    worst_cmd = std::max(worst_cmd, axis_deviation(*pc->second, tc.tip, tc.axis, 10.0, h));
    double ha = h;
    worst_act = std::max(worst_act, axis_deviation(*pc->second, ta.tip, ta.axis, 10.0, ha));
    // the feed: where the trace's speed held the programmed feed over this cycle and the one
    // before, the commanded tip travelled feed * dt (forward kinematics of the joints)
    if (i > 1 && rows[i - 1].s.line == row.s.line && std::abs(row.s.speed - feed) < 1e-9 &&
        std::abs(rows[i - 1].s.speed - feed) < 1e-9) {
      const ToolPose tp = forward(kin, to_joints(cfg, rows[i - 1].s.commanded, rows[i - 1].j.commanded));
      worst_feed = std::max(worst_feed, std::abs(norm(tc.tip - tp.tip) / dt - feed) / feed);
      ++constant_rows;
    }
    // across the first pass's split (its middle half) the speed never drops
    if (pc->second == &pieces[0] && h > 10.0 && h < 30.0) min_mid_speed = std::min(min_mid_speed, row.s.speed);
  }
  EXPECT_EQ(rows_per_piece.size(), pieces.size()) << "every piece ran";
  EXPECT_GT(constant_rows, 2000);
  EXPECT_LT(worst_feed, 1e-3) << "the tip's speed off the feed at constant-feed cycles (relative)";
  EXPECT_GT(min_mid_speed, feed * (1.0 - 1e-9)) << "the pass flows across its split into two blocks";
  EXPECT_LT(worst_cmd, 2e-3) << "commanded swept axis off the ruled surface, mm";
  EXPECT_LT(worst_act, 0.02) << "measured swept axis off the ruled surface, mm";
  // the end: the last rows stand where the program ends (tip lifted after pass 2's end, TCP off)
  const Row& last = rows.back();
  EXPECT_EQ(last.s.state, MachineState::kIdle);
  std::printf("[ figures ] ruled rows %d (constant feed %d): feed off by %.3g %% at most; swept axis (tip and 10 mm up "
              "the tool) off the surface: commanded %.3g um, measured %.3g um\n",
              static_cast<int>(rows_per_piece[pieces[0].line] + rows_per_piece[pieces[1].line] + rows_per_piece[pieces[2].line]),
              constant_rows, worst_feed * 100.0, worst_cmd * 1e3, worst_act * 1e3);
}

// What the trace of a run of `pieces` (machine coordinates, each with its G5.4's line as the
// trace names it) shows, every cycle: no commanded joint beyond its travel or speed, every
// measured linear joint inside its travel, every piece run, the machine idle at the end; and
// the swept tool axis (tip and the point 10 mm up the tool, forward kinematics of the commanded
// joints and of the measured ones, every 10th cycle of each piece) off the ruled surface
// through the piece's set points by at most 2 um commanded and 20 um measured.
struct RunOnSurface {
  double worst_cmd = 0.0, worst_act = 0.0;  // mm
  Vec3 lo{1e9, 1e9, 1e9}, hi{-1e9, -1e9, -1e9};  // measured linear joints
};

RunOnSurface check_run_on_surface(const MachineConfig& cfg, const std::vector<Piece>& pieces, const std::string& trace,
                                  std::size_t min_rows) {
  RunOnSurface out;
  const Kinematics kin = kinematics_with_tool(cfg, 0.0);
  const std::vector<Row> rows = read_five_axis_trace(trace, cfg.rotary_mask());
  EXPECT_GT(rows.size(), min_rows);
  if (rows.empty()) return out;
  std::map<int, const Piece*> by_line;
  for (const Piece& p : pieces) by_line[p.line] = &p;
  EXPECT_EQ(by_line.size(), pieces.size()) << "one line per piece";
  std::map<int, double> hint;
  std::map<int, int> rows_per_piece;
  double& worst_cmd = out.worst_cmd;
  double& worst_act = out.worst_act;
  Vec3& lo = out.lo;
  Vec3& hi = out.hi;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const Row& row = rows[i];
    const std::string violation = commanded_joint_violation(cfg, rows, i);
    EXPECT_EQ(violation, "");
    if (!violation.empty()) return out;
    for (int ax = 0; ax < kAxes; ++ax) {
      const auto k = static_cast<std::size_t>(ax);
      lo[k] = std::min(lo[k], row.s.actual[k]);
      hi[k] = std::max(hi[k], row.s.actual[k]);
    }
    const auto pc = by_line.find(static_cast<int>(row.s.line));
    if (pc == by_line.end() || row.s.state != MachineState::kRunning) continue;
    if (rows_per_piece[pc->first]++ % 10 != 0) continue;
    const ToolPose tc = forward(kin, to_joints(cfg, row.s.commanded, row.j.commanded));
    const ToolPose ta = forward(kin, to_joints(cfg, row.s.actual, row.j.actual));
    double& h = hint[pc->first];
    worst_cmd = std::max(worst_cmd, axis_deviation(*pc->second, tc.tip, tc.axis, 10.0, h));
    double ha = h;
    worst_act = std::max(worst_act, axis_deviation(*pc->second, ta.tip, ta.axis, 10.0, ha));
  }
  for (int ax = 0; ax < kAxes; ++ax) {
    const AxisConfig& a = cfg.axes[static_cast<std::size_t>(ax)];
    EXPECT_GE(lo[static_cast<std::size_t>(ax)], a.travel_min_mm) << "measured joint " << ax;
    EXPECT_LE(hi[static_cast<std::size_t>(ax)], a.travel_max_mm) << "measured joint " << ax;
  }
  EXPECT_EQ(rows_per_piece.size(), pieces.size()) << "every G5.4 group ran";
  EXPECT_LT(worst_cmd, 2e-3) << "commanded swept axis off the ruled surface, mm";
  EXPECT_LT(worst_act, 0.02) << "measured swept axis off the ruled surface, mm";
  EXPECT_EQ(rows.back().s.state, MachineState::kIdle);
  return out;
}

// The program `pcnc ruled` writes by default (the seed's example fitted to desktop-5axis's
// joints) runs on the machine as written: pcnc check shows a ruled block for every G5.4 group,
// pcnc run completes it with every commanded joint inside its travel and velocity (and every
// measured linear joint inside its travel) on every cycle, every group runs, and the swept tool
// axis (forward kinematics of the commanded joints, and of the measured ones, every 10th cycle)
// stays on the ruled surface through the program's set points.
TEST(RuledRun, TheProgramPcncRuledWritesRunsOnTheFiveAxisMachine) {
  const std::string dir = make_temp_dir("ruledex");
  const std::string config = write_five_axis_config(dir, "ruledex");
  const MachineConfig cfg = load_config(config);
  const std::string path = dir + "/ex.ngc";
  // Under the sanitizers (test_paths.hpp) a coarser cusp height: a third of the passes, the
  // same code paths (the default took 56 s under ASan).
  std::vector<std::string> gen_args{pcnc_exe(), "ruled", "--config", config, "--samples", "0", "-o", path};
  if (test::sanitizer_build()) gen_args.insert(gen_args.end(), {"--cusp", "0.05"});
  const ProcessResult gen = run_process(gen_args, 120);
  ASSERT_EQ(gen.exit_code, 0) << gen.out << gen.err;

  // the program's pieces as written (workpiece = program + G54; the first point of each is where
  // the one before ended, as written)
  std::vector<Piece> pieces;
  {
    std::istringstream in(read_file(path));
    std::string l;
    int n = 0;
    Piece* open = nullptr;
    while (std::getline(in, l)) {
      ++n;
      if (l.rfind("G5.4", 0) == 0) {
        pieces.emplace_back();
        open = &pieces.back();
        open->line = n;
      } else if (l.rfind("G5.5", 0) == 0) {
        RuledModelResult m = ruled_model_through(open->points, open->axes, RulingForm::kVector);
        ASSERT_TRUE(m.error.empty()) << m.error;
        open->model = m.model;
        open = nullptr;
      } else if (open != nullptr) {
        double v[6];
        ASSERT_EQ(std::sscanf(l.c_str(), "X%lf Y%lf Z%lf I%lf J%lf K%lf", &v[0], &v[1], &v[2], &v[3], &v[4], &v[5]), 6) << l;
        open->points.push_back(kG54 + Vec3{v[0], v[1], v[2]});
        open->axes.push_back(normalized(Vec3{v[3], v[4], v[5]}));
      }
    }
  }
  ASSERT_GT(pieces.size(), test::sanitizer_build() ? 30u : 100u);

  const ProcessResult chk = run_process({pcnc_exe(), "check", path, "--config", config, "--print-blocks"}, 120);
  ASSERT_EQ(chk.exit_code, 0) << chk.out << chk.err;
  std::size_t ruled_blocks = 0;
  for (std::size_t at = chk.out.find(" ruled ("); at != std::string::npos; at = chk.out.find(" ruled (", at + 1)) ++ruled_blocks;
  EXPECT_GE(ruled_blocks, pieces.size());

  const std::string trace = dir + "/ex.csv";
  const ProcessResult r = run_process({pcnc_exe(), "run", path, "--config", config, "--clock", "virtual", "--trace", trace}, 600);
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("result            completed"), std::string::npos) << r.out;

  const RunOnSurface run = check_run_on_surface(cfg, pieces, trace, test::sanitizer_build() ? 30000 : 100000);
  const double worst_cmd = run.worst_cmd, worst_act = run.worst_act;
  const Vec3 lo = run.lo, hi = run.hi;
  const std::size_t at = r.out.find("program time");
  std::printf("[ figures ] %zu G5.4 groups, %zu ruled blocks; %s; swept axis (tip and 10 mm up the tool, every "
              "10th cycle) off the surface: commanded %.3g um, measured %.3g um; measured joints X %.4f..%.4f Y %.4f..%.4f Z %.4f..%.4f mm\n",
              pieces.size(), ruled_blocks, at == std::string::npos ? "?" : r.out.substr(at, r.out.find('\n', at) - at).c_str(),
              worst_cmd * 1e3, worst_act * 1e3, lo[0], hi[0], lo[1], hi[1], lo[2], hi[2]);
}

// The file form (issue 17): the JSON program the real `pcnc ruled --json` writes (a coarser
// example than the test above: cusp 0.2 mm) runs through `pcnc run` as the G-code form does.
// `pcnc check --print-blocks` gives the same blocks for ex.json and ex.ngc (their source lines
// aside: the JSON's name the piece's place in the file); the run completes with every cycle
// inside the joints' travel and speed and the swept axis on the ruled surface (the same checks
// as above, each piece found by the line of its object in the JSON file); a refused JSON file
// is named at its place and nothing moves.
TEST(RuledRun, TheJsonFormPcncRuledWritesRunsThroughPcncRun) {
  const std::string dir = make_temp_dir("ruledjson");
  const std::string config = write_five_axis_config(dir, "ruledjson");
  const MachineConfig cfg = load_config(config);
  const std::string ngc = dir + "/ex.ngc", json = dir + "/ex.json";
  const ProcessResult gen =
      run_process({pcnc_exe(), "ruled", "--config", config, "--samples", "0", "--cusp", "0.2", "-o", ngc, "--json", json}, 120);
  ASSERT_EQ(gen.exit_code, 0) << gen.out << gen.err;

  const std::string text = read_file(json);
  const RuledJsonProgram prog = read_ruled_program_json(text, "ex.json");
  ASSERT_EQ(prog.error, "");
  ASSERT_GT(prog.pieces.size(), 10u);
  std::vector<Piece> pieces;
  for (std::size_t k = 0; k < prog.pieces.size(); ++k) {
    Piece p;
    p.line = prog.places[k].piece.line;
    for (std::size_t i = 0; i < prog.pieces[k].points.size(); ++i) {
      p.points.push_back(kG54 + prog.pieces[k].points[i]);
      p.axes.push_back(prog.pieces[k].axes[i]);
    }
    RuledModelResult m = ruled_model_through(p.points, p.axes, RulingForm::kVector);
    ASSERT_TRUE(m.error.empty()) << m.error;
    p.model = m.model;
    pieces.push_back(std::move(p));
  }

  // the same blocks from both forms
  auto blocks_of = [&](const std::string& path) {
    const ProcessResult chk = run_process({pcnc_exe(), "check", path, "--config", config, "--print-blocks"}, 120);
    EXPECT_EQ(chk.exit_code, 0) << chk.out << chk.err;
    std::vector<std::string> out;
    std::istringstream in(chk.out);
    for (std::string l; std::getline(in, l);) {
      if (l.empty() || !std::isdigit(static_cast<unsigned char>(l[0]))) continue;  // the summary
      const std::size_t at = l.find(" L"), end = l.find(' ', at + 1);
      out.push_back(l.substr(0, at) + l.substr(end));  // without the source line
    }
    return out;
  };
  const std::vector<std::string> from_json = blocks_of(json), from_ngc = blocks_of(ngc);
  ASSERT_GT(from_json.size(), prog.pieces.size());
  EXPECT_EQ(from_json, from_ngc);
  std::size_t ruled = 0;
  for (const std::string& l : from_json) ruled += l.find(" ruled (") != std::string::npos;
  EXPECT_GE(ruled, prog.pieces.size());

  const std::string trace = dir + "/ex.csv";
  const ProcessResult r = run_process({pcnc_exe(), "run", json, "--config", config, "--clock", "virtual", "--trace", trace}, 600);
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("result            completed"), std::string::npos) << r.out;
  const RunOnSurface run = check_run_on_surface(cfg, pieces, trace, 10000);
  const std::size_t at = r.out.find("program time");
  std::printf("[ figures ] ex.json: %zu pieces, %zu ruled blocks (the same %zu blocks as ex.ngc); %s; swept axis off the "
              "surface: commanded %.3g um, measured %.3g um\n",
              prog.pieces.size(), ruled, from_json.size(),
              at == std::string::npos ? "?" : r.out.substr(at, r.out.find('\n', at) - at).c_str(), run.worst_cmd * 1e3,
              run.worst_act * 1e3);

  // a refused file: its place, and nothing moves
  nlohmann::json j = nlohmann::json::parse(text);
  j["pieces"][2]["points"][1] = {1.0, 2.0};
  const std::string bad = dir + "/bad.json";
  std::ofstream(bad) << j.dump(1);
  const RuledJsonProgram bp = read_ruled_program_json(j.dump(1), bad);
  const ProcessResult rb = run_process({pcnc_exe(), "run", bad, "--config", config, "--clock", "virtual"}, 120);
  EXPECT_EQ(rb.exit_code, 2) << rb.out << rb.err;
  EXPECT_NE(rb.err.find(bad + ":" + std::to_string(bp.refusal.line) + ":" + std::to_string(bp.refusal.column) +
                        ": error: pieces[2].points[1]: expected three numbers"),
            std::string::npos)
      << rb.err;
  EXPECT_NE((rb.out + rb.err).find("nothing was moved"), std::string::npos) << rb.out << rb.err;
}

// A machine without rotary joints refuses G5.4 at its line and column, before anything moves.
TEST(RuledRun, ThreeAxisMachineRefusesTheGroup) {
  const std::string dir = make_temp_dir("ruled3");
  const std::string path = dir + "/r.ngc";
  std::ofstream(path) << "G21 G90 G94\nG0 X0 Y0 Z-1\n  G5.4 F600\nX0 Y0 Z-1 I0 J0 K1\nX1 Y0 Z-1 I0 J0 K1\nG5.5\nM2\n";
  const ProcessResult r = run_process({pcnc_exe(), "check", path, "--config", source_dir() + "/configs/desktop-mill.toml"}, 60);
  EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
  EXPECT_NE((r.out + r.err).find("r.ngc:3:3: error: G5.4: a ruled-surface piece needs a 5-axis machine"), std::string::npos)
      << r.out << r.err;
  EXPECT_EQ((r.out + r.err).find("tool-centre-point"), std::string::npos) << "one error, not the TCP rule's too";
}

}  // namespace
}  // namespace pcnc::test
