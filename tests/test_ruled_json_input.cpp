// test_ruled_json_input.cpp — the JSON file form of a ruled-surface program through the one
// front end (host/gcode/ruled_json_input.hpp, no processes, configs/desktop-5axis.toml): a
// `.json` program becomes the G-code form `pcnc ruled` writes, with the preamble made from the
// config, so check and the block stream give the same blocks for both forms; blocks and
// diagnostics name the places in the JSON file; a refused file runs nothing.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "config/joint_map.hpp"
#include "gcode/program.hpp"
#include "gcode/ruled_json_input.hpp"
#include "gcode/ruled_program.hpp"
#include "geometry/kinematics.hpp"
#include "test_paths.hpp"
#include "subprocess.hpp"
#include "test_constants.hpp"
#include "machine_runner.hpp"

namespace pcnc {
namespace {


// What `pcnc ruled` writes, in miniature (program coordinates): an approach down from 3 mm above
// the tilted tool's tip, a 24-point pass along X with the axis swinging toward +Y by `swing`
// rad, and a retract back up.
std::vector<RuledPiece> pieces(const MachineConfig& cfg, double swing = 0.1, double drop = 0.0) {
  const Rot3 rot{12.0 * kRadPerDeg, 0.0, 35.0 * kRadPerDeg};
  const ToolPose p0 = forward(kinematics_with_tool(cfg, 0.0), to_joints(cfg, Vec3{-4.0, -2.0, -5.0} + kG54, rot));
  const Vec3 tip = p0.tip - kG54 - Vec3{0.0, 0.0, drop};
  RuledPiece pass;
  for (int k = 0; k <= 24; ++k) {
    const double t = k / 24.0;
    pass.points.push_back(tip + Vec3{6.0 * t, 0.3 * std::sin(M_PI * t), 0.0});
    pass.axes.push_back(normalized(p0.axis + (swing * std::sin(M_PI * t)) * Vec3{0.0, 1.0, 0.0}));
  }
  const Vec3 up{0.0, 0.0, 3.0};
  RuledPiece approach{{tip + up, tip}, {p0.axis, p0.axis}, "approach"};
  RuledPiece retract{{pass.points.back(), pass.points.back() + up}, {pass.axes.back(), pass.axes.back()}, "retract"};
  return {approach, pass, retract};
}

// The G-code form as `pcnc ruled` writes it: header, the turn words at the first tool vector
// (G54 of the config), the clearance at the first set point.
std::string gcode_form(const MachineConfig& cfg, const std::vector<RuledPiece>& ps, double feed) {
  RuledProgramOptions o;
  o.feed_mm_min = feed;
  o.clearance_z = ps.front().points.front()[2];
  const RuledTurnWords w = ruled_turn_words(cfg, ps.front().points.front() + kG54, ps.front().axes.front());
  o.turn_joints = w.turn;
  o.turn_back = w.back;
  o.header = {"a header comment", "and another"};
  std::string text;
  for (const std::string& l : ruled_program_lines(ps, o)) text += l + "\n";
  return text;
}

std::string errors(const CheckResult& r) {
  std::string s;
  for (const Diagnostic& d : r.diagnostics)
    if (d.severity == Diagnostic::Severity::kError) s += format_diagnostic(d) + "\n";
  return s;
}

// Blocks equal in everything but the source line.
void expect_same_blocks(const std::vector<Block>& a, const std::vector<Block>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    Block x = a[i], y = b[i];
    x.line = y.line = 0;
    EXPECT_EQ(format_block(x), format_block(y)) << "block " << i;
    EXPECT_EQ(x.seq, y.seq);
    EXPECT_EQ(std::memcmp(&x.ruled, &y.ruled, sizeof x.ruled), 0) << "block " << i << ": ruled geometry";
    EXPECT_EQ(std::memcmp(&x.rotary, &y.rotary, sizeof x.rotary), 0) << "block " << i << ": joints";
    EXPECT_EQ(x.speed, y.speed);
    EXPECT_EQ(x.end, y.end);
  }
}

TEST(RuledJsonInput, BothFormsGiveTheSameBlocksThroughCheckAndStream) {
  const MachineConfig cfg = test::five_axis_config();
  const std::vector<RuledPiece> ps = pieces(cfg);
  const std::string ngc = gcode_form(cfg, ps, 600.0), json = ruled_program_json(ps, 600.0);
  std::vector<Block> from_ngc, from_json;
  const CheckResult rn = check_program_text(ngc, "p.ngc", cfg, JobOptions{}, [&](const Block& b) { from_ngc.push_back(b); });
  const CheckResult rj = check_program_text(json, "p.json", cfg, JobOptions{}, [&](const Block& b) { from_json.push_back(b); });
  ASSERT_TRUE(rn.ok) << errors(rn);
  ASSERT_TRUE(rj.ok) << errors(rj);
  int ruled = 0, rapids = 0;
  for (const Block& b : from_json) {
    ruled += b.kind == BlockKind::kRuled;
    rapids += b.kind == BlockKind::kRapid;
  }
  EXPECT_EQ(ruled, 3) << "approach, pass, retract";
  EXPECT_GE(rapids, 3) << "the turn with TCP off, the rapids to the first point";
  expect_same_blocks(from_ngc, from_json);
  EXPECT_EQ(rj.planned_time_s, rn.planned_time_s);

  // the stream (what run and jobs send) gives the check's blocks
  std::vector<Block> streamed;
  BlockStream s(BlockStream::FromText{}, json, "p.json", cfg, JobOptions{}, rj.transform);
  for (Block b; s.next(b);) streamed.push_back(b);
  ASSERT_EQ(streamed.size(), from_json.size());
  for (std::size_t i = 0; i < streamed.size(); ++i) EXPECT_EQ(format_block(streamed[i]), format_block(from_json[i]));

  // a file on disk reads the same (check_program and BlockStream by path)
  const std::string dir = test::make_temp_dir("ruledjson");
  const std::string path = dir + "/p.json";
  std::ofstream(path) << json;
  std::vector<Block> from_file;
  const CheckResult rf = check_program(path, cfg, JobOptions{}, [&](const Block& b) { from_file.push_back(b); });
  ASSERT_TRUE(rf.ok) << errors(rf);
  BlockStream fs(path, cfg, JobOptions{}, rf.transform);
  std::size_t n = 0;
  for (Block b; fs.next(b); ++n) ASSERT_EQ(format_block(b), format_block(from_json.at(n)));
  EXPECT_EQ(n, from_json.size());
}

// A JSON program's blocks carry the lines of the JSON file: the preamble's rapids the first set
// point's (the turn its tool vector's), each piece's blocks the line of its object, the end the
// last set point's.
TEST(RuledJsonInput, BlocksNameTheirPlaceInTheJsonFile) {
  const MachineConfig cfg = test::five_axis_config();
  const std::string json = ruled_program_json(pieces(cfg), 600.0);
  const RuledJsonProgram places = read_ruled_program_json(json, "p.json");
  ASSERT_EQ(places.error, "");
  std::vector<Block> blocks;
  const CheckResult r = check_program_text(json, "p.json", cfg, JobOptions{}, [&](const Block& b) { blocks.push_back(b); });
  ASSERT_TRUE(r.ok) << errors(r);
  std::vector<std::uint32_t> ruled_lines;
  for (const Block& b : blocks)
    if (b.kind == BlockKind::kRuled) ruled_lines.push_back(b.line);
  ASSERT_EQ(ruled_lines.size(), 3u);
  for (std::size_t k = 0; k < 3; ++k) EXPECT_EQ(ruled_lines[k], static_cast<std::uint32_t>(places.places[k].piece.line));
  EXPECT_EQ(blocks.front().kind, BlockKind::kRapid);
  EXPECT_EQ(blocks.front().line, static_cast<std::uint32_t>(places.places[0].first_axis.line)) << "the turn";
  EXPECT_EQ(blocks[1].line, static_cast<std::uint32_t>(places.places[0].points[0].line)) << "the rapids";
  EXPECT_EQ(blocks.back().kind, BlockKind::kEnd);
  EXPECT_EQ(blocks.back().line, static_cast<std::uint32_t>(places.places[2].points[1].line));
}

// The preamble from the config: the joints turned with TCP off to the first tool vector, M428,
// the rapids (Z to the higher end, X Y, down to the first point), back up, M429, the joints back.
TEST(RuledJsonInput, PreambleIsMadeFromTheConfig) {
  const MachineConfig cfg = test::five_axis_config();
  std::vector<RuledPiece> ps = pieces(cfg);
  ps.erase(ps.begin());  // start with the pass itself, 3 mm lower than its end point after the retract
  const RuledJsonInput in = ruled_json_input(ruled_program_json(ps, 450.0), "p.json", cfg, kG54, 1.0);
  ASSERT_EQ(in.refusal_text, "");
  const RuledTurnWords w = ruled_turn_words(cfg, ps.front().points.front() + kG54, ps.front().axes.front());
  EXPECT_EQ(w.turn.rfind("A12.000000 C35.000000", 0), 0u) << w.turn << ": the joints the first tool vector came from";
  EXPECT_EQ(w.back, "A0 C0");
  char zc[64], z0[64];
  std::snprintf(zc, sizeof zc, "G0 Z%.5f", ps.back().points.back()[2]);
  std::snprintf(z0, sizeof z0, "G0 Z%.5f", ps.front().points.front()[2]);
  const std::string want_head = "G21 G90 G17 G94\nG0 " + w.turn + " (the tool axis of the first set point, TCP off)\n" +
                                "M428 (tool-centre-point control on)\n" + zc + "\n";
  EXPECT_EQ(in.text.rfind(want_head, 0), 0u) << in.text.substr(0, 300);
  EXPECT_NE(in.text.find("\n" + std::string(z0) + "\nG5.4 F450.000\n"), std::string::npos) << "down to the first point";
  const std::string tail = std::string(zc) + "\nM429 (tool-centre-point control off)\nG0 A0 C0\nM2\n";
  EXPECT_EQ(in.text.substr(in.text.size() - tail.size()), tail);
  ASSERT_TRUE(in.places);
  EXPECT_EQ(in.places->size(), static_cast<std::size_t>(std::count(in.text.begin(), in.text.end(), '\n')));
  const CheckResult r = check_program_text(ruled_program_json(ps, 450.0), "p.json", cfg, JobOptions{});
  EXPECT_TRUE(r.ok) << errors(r);
}

// Refusals name the JSON file, the line and column and the key path; nothing runs then.
TEST(RuledJsonInput, RefusedAtThePlaceInTheFileBeforeAnythingRuns) {
  const MachineConfig cfg = test::five_axis_config();
  int blocks = 0;
  auto count = [&](const Block&) { ++blocks; };
  // a tool vector that is not a unit vector (the reader's rules)
  std::string json = ruled_program_json(pieces(cfg), 600.0);
  const RuledJsonProgram places = read_ruled_program_json(json, "p.json");
  nlohmann::json j = nlohmann::json::parse(json);
  j["pieces"][1]["axes"][3] = {0.0, 0.0, 0.9};
  const std::string bad = j.dump(1);
  const RuledJsonProgram bp = read_ruled_program_json(bad, "p.json");
  CheckResult r = check_program_text(bad, "p.json", cfg, JobOptions{}, count);
  EXPECT_FALSE(r.ok);
  EXPECT_EQ(blocks, 0);
  ASSERT_EQ(r.diagnostics.size(), 1u) << errors(r);
  EXPECT_EQ(format_diagnostic(r.diagnostics[0]),
            "p.json:" + std::to_string(bp.refusal.line) + ":" + std::to_string(bp.refusal.column) +
                ": error: pieces[1].axes[3]: tool vector of length 0.9: expected a unit vector");
  EXPECT_GT(bp.refusal.line, 1);

  // not JSON: where the parser stopped
  r = check_program_text("{\"format\": \"pcnc-ruled-program\",\n  \"pieces\": [}", "p.json", cfg, JobOptions{}, count);
  EXPECT_FALSE(r.ok);
  EXPECT_EQ(errors(r).rfind("p.json:2:", 0), 0u) << errors(r);
  EXPECT_NE(errors(r).find("not JSON"), std::string::npos) << errors(r);

  // the machine refuses what the file allows: a pass 30 mm lower leaves the joints' travel, at
  // the place of the set point whose move leaves it (check fails: run and jobs start nothing)
  r = check_program_text(ruled_program_json(pieces(cfg, 0.1, 30.0), 600.0), "p.json", cfg, JobOptions{});
  EXPECT_FALSE(r.ok);
  EXPECT_EQ(errors(r).rfind("p.json:" + std::to_string(places.places[0].points[0].line) + ":", 0), 0u) << errors(r);
  EXPECT_NE(errors(r).find("error: pieces[0].points[0]: Z"), std::string::npos) << errors(r);
  EXPECT_NE(errors(r).find("below the travel minimum"), std::string::npos) << errors(r);

  // a 3-axis machine: refused once, at the first piece
  r = check_program_text(json, "p.json", load_config(test::source_dir() + "/configs/desktop-mill.toml"), JobOptions{}, count);
  EXPECT_FALSE(r.ok);
  ASSERT_EQ(r.diagnostics.size(), 1u) << errors(r);
  EXPECT_EQ(format_diagnostic(r.diagnostics[0]).rfind("p.json:" + std::to_string(places.places[0].piece.line) + ":" +
                                                          std::to_string(places.places[0].piece.column) +
                                                          ": error: pieces[0]: a ruled-surface program needs a 5-axis machine",
                                                      0),
            0u)
      << errors(r);
  EXPECT_EQ(blocks, 0);

  // a file that cannot be read: named
  r = check_program("/nonexistent/p.json", cfg, JobOptions{});
  EXPECT_FALSE(r.ok);
  EXPECT_NE(errors(r).find("/nonexistent/p.json: cannot open"), std::string::npos) << errors(r);
}

}  // namespace
}  // namespace pcnc
