// test_proc_resume_ruled.cpp — resume inside a ruled-surface block (G5.4, issue 17) with the
// real processes on configs/desktop-5axis.toml: a program with a long slow G5.4 piece runs on
// pcnc-rt (--clock virtual) and pcnc-host --serve; the host is killed (SIGKILL) while the tool
// is inside the piece; the rt holds on it (HOST_LOST); a new host resumes there (the block cut
// at the parameter reached, host/service/resume.hpp); the program completes at its last point,
// and the rt's trace shows no jump in any joint and the tool tip on the piece after the resume.
#include <gtest/gtest.h>
#include <signal.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>

#include "config/config.hpp"
#include "config/joint_map.hpp"
#include "five_axis_trace.hpp"
#include "geometry/kinematics.hpp"
#include "geometry/ruled_model.hpp"
#include "service_procs.hpp"
#include "test_paths.hpp"
#include "test_constants.hpp"

namespace pcnc::test {
namespace {

constexpr int kPieceLine = 5;  // the G5.4

// The pair's config replaced by desktop-5axis with the pair's segment, socket and state dir.
void use_five_axis_config(ServicePair& p) {
  std::string text = read_file(source_dir() + "/configs/desktop-5axis.toml");
  auto replace = [&](const std::string& from, const std::string& to) {
    const auto at = text.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    text.replace(at, from.size(), to);
  };
  replace("shm_name = \"/pcnc-desktop-5axis\"", "shm_name = \"" + test_shm_name(p.tag()) + "\"");
  replace("# socket_path = \"/run/pcnc/desktop-mill/control.sock\"", "socket_path = \"" + p.dir() + "/pcnc.sock\"");
  replace("# state_dir = \"/var/lib/pcnc/desktop-mill\"", "state_dir = \"" + p.dir() + "/state\"");
  std::ofstream(p.config()) << text;
}

TEST(KillHostInRuled, ANewHostResumesInsideThePieceAndTheProgramCompletesWithoutAJump) {
  ServicePair p("khost-ruled");
  use_five_axis_config(p);
  const MachineConfig cfg = load_config(p.config());
  const Kinematics kin = kinematics_with_tool(cfg, 0.0);
  // The tool tilted with TCP off, then under TCP one 8 mm G5.4 piece of 41 set points at F6
  // (two blocks), its axis swinging, and short moves after it (more blocks than the ring holds).
  const Vec3 xyz = Vec3{-4.0, -2.0, -5.0} + kG54;
  const Rot3 rot{12.0 * M_PI / 180.0, 0.0, 35.0 * M_PI / 180.0};
  const ToolPose p0 = forward(kin, to_joints(cfg, xyz, rot));
  std::vector<Vec3> pts, axes;
  std::ostringstream o;
  o << "G21 G90 G94\nG0 X-4 Y-2 Z-5\nG1 A12 C35 F3600\nM428\nG5.4 F6\n";
  char buf[200];
  for (int k = 0; k <= 40; ++k) {
    const double t = k / 40.0;
    pts.push_back(p0.tip + Vec3{8.0 * t, 0.3 * std::sin(M_PI * t), 0.0});
    axes.push_back(normalized(p0.axis + (0.1 * std::sin(M_PI * t)) * Vec3{0.0, 1.0, 0.0}));
    const Vec3 q = pts.back() - kG54;
    std::snprintf(buf, sizeof buf, "X%.6f Y%.6f Z%.6f I%.9f J%.9f K%.9f\n", q[0], q[1], q[2], axes.back()[0],
                  axes.back()[1], axes.back()[2]);
    o << buf;
  }
  o << "G5.5\n";
  const Vec3 end = pts.back() - kG54;
  for (int k = 1; k <= 8; ++k) {
    std::snprintf(buf, sizeof buf, "G1 X%.6f Y%.6f F600\n", end[0], end[1] + 0.25 * k);
    o << buf;
  }
  o << "M429\nM2\n";
  // the piece as programmed, read back as written (the program's 6 and 9 decimals)
  const RuledModelResult model = ruled_model_through(pts, axes, RulingForm::kVector);
  ASSERT_TRUE(model.error.empty()) << model.error;
  const RuledCurves curves = model.model.curves();

  const std::string trace = p.dir() + "/trace.csv";
  ASSERT_TRUE(p.start("virtual", {"--trace", trace})) << p.host_log();
  const std::string prog = write_program(p.dir(), "ruled.ngc", o.str());
  const json run = p.call("run", {{"file", prog}});
  ASSERT_TRUE(run.contains("result")) << run.dump() << p.host_log();
  const json inside = p.wait_status(
      [&](const json& s) {
        return s.value("state", "") == "RUNNING" && s.value("line", 0) == kPieceLine && s.value("program_time_s", 0.0) > 15.0;
      },
      60);
  ASSERT_EQ(inside["state"], "RUNNING") << inside.dump();
  const KillAndResume k = kill_host_and_resume(p);
  ASSERT_EQ(k.error, "");
  ASSERT_EQ(k.lost.line, static_cast<std::uint32_t>(kPieceLine)) << "stopped inside the piece";
  EXPECT_EQ(k.reply["result"]["line"].get<int>(), kPieceLine);
  p.kill_rt(SIGTERM);

  // The trace: every joint inside its travel and speed on every cycle (no jump), the hold, the
  // piece's cycles after the resume with the tip on the piece, the program's end at its last point.
  const std::vector<FiveAxisRow> rows = read_five_axis_trace(trace, cfg.rotary_mask());
  ASSERT_GT(rows.size(), 1000u);
  std::size_t lost = 0, after = 0;
  bool seen_lost = false;
  double worst_off = 0.0, u_hint = -1.0;
  const double n = static_cast<double>(model.model.directrix.size());
  for (std::size_t i = 0; i < rows.size(); ++i) {
    ASSERT_EQ(commanded_joint_violation(cfg, rows, i), "") << "row " << i;
    const FiveAxisRow& row = rows[i];
    if (row.s.state == MachineState::kHostLost) ++lost, seen_lost = true;
    if (!seen_lost || row.s.state != MachineState::kRunning || row.s.line != static_cast<std::uint32_t>(kPieceLine)) continue;
    if (after++ % 10 != 0) continue;
    const Vec3 tip = forward(kin, to_joints(cfg, row.s.commanded, row.j.commanded)).tip;
    double best = 1e9, bu = std::max(0.0, u_hint);
    const bool first = u_hint < 0.0;  // the first sample searches the whole piece
    for (double u = first ? 0.0 : std::max(0.0, u_hint - 1.0); u <= (first ? n : std::min(n, u_hint + 2.0)); u += 1.0 / 64.0) {
      const double d = norm(ruled_jet(curves, u).c.p - tip);
      if (d < best) best = d, bu = u;
    }
    for (double h = 1.0 / 128.0; h > 1e-12; h *= 0.5)
      for (double c : {bu - h, bu + h})
        if (c >= 0.0 && c <= n && norm(ruled_jet(curves, c).c.p - tip) < best) best = norm(ruled_jet(curves, c).c.p - tip), bu = c;
    u_hint = bu;
    worst_off = std::max(worst_off, best);
  }
  EXPECT_GT(lost, 0u);
  EXPECT_GT(after, 100u) << "the rest of the piece ran after the resume";
  EXPECT_LT(worst_off, 1e-4) << "the tip left the piece after the resume, mm";
  const Vec3 last_tip = forward(kin, to_joints(cfg, rows.back().s.commanded, rows.back().j.commanded)).tip;
  EXPECT_LT(norm(last_tip - (kG54 + end + Vec3{0.0, 2.0, 0.0})), 1e-6) << "the program's last point";
  std::cout << "[ figures  ] kill host inside a ruled piece: trace rows " << rows.size() << ", piece cycles after resume "
            << after << ", tip off the piece at most " << worst_off * 1e3 << " um\n";
}

}  // namespace
}  // namespace pcnc::test
