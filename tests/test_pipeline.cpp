// test_pipeline.cpp — the one front-end pipeline (host/gcode/pipeline.hpp): `check` and the
// streamed path (BlockStream) make the same blocks for every program of ../shared/gcode, and
// check refuses a block the rt's block check would refuse, at the block's source line.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "check.hpp"
#include "gcode/move_source.hpp"
#include "gcode_test_util.hpp"

namespace pcnc {
namespace {

namespace fs = std::filesystem;

std::string corpus_gcode_dir() { return test::shared_dir() + "/gcode"; }

std::vector<std::string> corpus_programs() {
  std::vector<std::string> out;
  for (const auto& e : fs::recursive_directory_iterator(corpus_gcode_dir())) {
    const std::string ext = e.path().extension().string();
    if (e.is_regular_file() && (ext == ".ngc" || ext == ".nc" || ext == ".gcode" || ext == ".tap"))
      out.push_back(e.path().string());
  }
  std::sort(out.begin(), out.end());
  return out;
}

// The bytes of a block that mean something: everything before the NURBS storage, and that
// storage only for a NURBS block (other blocks leave its arrays as they were, counts zeroed).
std::string meaningful_bytes(const Block& b) {
  const auto* p = reinterpret_cast<const char*>(&b);
  if (b.kind == BlockKind::kNurbs) return std::string(p, sizeof(Block));
  std::string s(p, offsetof(Block, nurbs));
  s.append(reinterpret_cast<const char*>(&b.nurbs.point_count), 8);  // the counts and the degree
  return s;
}

std::string first_check_error(const CheckResult& r) {
  for (const Diagnostic& d : r.diagnostics) {
    if (d.severity == Diagnostic::Severity::kError) return format_diagnostic(d);
  }
  return "(no error)";
}

// Check (collecting the blocks it made) and stream the program; compare block by block.
// Returns false when check refuses the program under these options.
bool same_blocks_from_check_and_stream(const std::string& path, const MachineConfig& c, const JobOptions& o) {
  std::vector<std::string> checked;
  std::vector<std::string> checked_text;
  const CheckResult r = check_program(path, c, o, [&](const Block& b) {
    checked.push_back(meaningful_bytes(b));
    checked_text.push_back(format_block(b));
  });
  if (!r.ok) {
    EXPECT_EQ(r.rapid_lines.size(), 0u) << path;
    return false;
  }
  EXPECT_EQ(r.blocks, checked.size()) << path;
  BlockStream s(path, c, o, r.transform);
  Block b;
  std::size_t n = 0;
  while (s.next(b)) {
    if (n >= checked.size()) {
      ADD_FAILURE() << path << ": the stream has more blocks than check made (" << checked.size() << ")";
      return true;
    }
    EXPECT_EQ(b.seq, n + 1) << path << ": numbered as the ring feeder numbers them";
    if (meaningful_bytes(b) != checked[n]) {
      ADD_FAILURE() << path << ": block " << n + 1 << " differs\n  check:  " << checked_text[n]
                    << "\n  stream: " << format_block(b);
      return true;
    }
    ++n;
  }
  EXPECT_EQ(n, checked.size()) << path << ": the stream ended early";
  return true;
}

TEST(Pipeline, CheckAndStreamMakeTheSameBlocksForEveryCorpusProgram) {
  const MachineConfig c = test::mill_config();
  int programs = 0, accepted = 0;
  for (const std::string& path : corpus_programs()) {
    ++programs;
    JobOptions o;
    o.start_position = Vec3{0.0, 0.0, 25.0};
    if (same_blocks_from_check_and_stream(path, c, o)) {
      ++accepted;
      continue;
    }
    o.fit = true;  // most parts are larger than the 25 mm travel
    if (same_blocks_from_check_and_stream(path, c, o)) ++accepted;
  }
  EXPECT_GE(programs, 100);
  EXPECT_GE(accepted, 30) << "of " << programs;  // the rest use what the dialect rejects
}

// The merge stage (on with a corner tolerance) and contouring on: the same under both paths.
TEST(Pipeline, CheckAndStreamAgreeWithTheSegmentMergeOn) {
  MachineConfig c = load_config(test::source_dir() + "/configs/bench-peers.toml");
  int accepted = 0;
  for (const char* rel : {"cam/fusion360/cnc_Face.nc", "cam/ugs/arc_rword_test.gcode", "nurbs/g5.2/nurbs-xy.ngc",
                          "cam/linuxcnc-tp/Cereal.ngc"}) {
    JobOptions o;
    o.contouring = true;
    o.fit = true;
    if (same_blocks_from_check_and_stream(corpus_gcode_dir() + "/" + rel, c, o)) ++accepted;
  }
  EXPECT_GE(accepted, 3);
}

// regress/bad-block-z.ngc: an arc whose end radius differs from its start radius by 3.5 µm
// (G20: accepted by LinuxCNC's inch rule) was refused by the rt's block check ("bad block on
// axis Z") although check accepted it. The arc block now carries the mean radius (issue 14):
// check accepts it and every block passes the rt's check.
JobOptions bad_block_z_options() {
  JobOptions o;
  o.offset = Vec3{-42.4053, -61.7220, 2.9312};
  o.contouring = true;
  return o;
}

TEST(Pipeline, BadBlockZPassesTheRtsBlockCheckNow) {
  const MachineConfig c = load_config(test::source_dir() + "/configs/bench-peers.toml");
  const CheckResult r = check_program(corpus_gcode_dir() + "/regress/bad-block-z.ngc", c, bad_block_z_options());
  EXPECT_TRUE(r.ok) << first_check_error(r);
  EXPECT_GE(r.blocks, 8u);
}

// A block the rt would refuse is an error of check at its source line. Made here with a config
// whose arc tolerance is wide (0.05 mm, none relative) and an inch arc: the interpreter's inch
// rule accepts an end radius up to 2.54 times that apart, the rt checks each radius against
// the mean within the tolerance itself (plus the block tolerance).
MachineConfig wide_arc_config() {
  MachineConfig c = load_config(test::source_dir() + "/configs/bench-peers.toml");
  c.gcode.arc_radius_tolerance_mm = 0.05;
  c.gcode.arc_radius_tolerance_rel = 0.0;
  return c;
}
const char* kRefusedArc = "G20 G17 G90\nG0 X0 Y0 Z0\nG1 X0.1 F10\nG2 X0.30453 Y0.004 I0.1 J0.004\nG1 X0.4\nM30\n";

TEST(Pipeline, CheckRefusesTheBlockTheRtRefuses) {
  const CheckResult r = check_program_text(kRefusedArc, "refused.ngc", wide_arc_config(), JobOptions{});
  EXPECT_FALSE(r.ok);
  const std::string e = first_check_error(r);
  EXPECT_NE(e.find("refused.ngc:4:"), std::string::npos) << e;
  EXPECT_NE(e.find("refused by the rt's block check"), std::string::npos) << e;
  EXPECT_NE(e.find("not on the radius"), std::string::npos) << e;
}

// A block check refusal stops the blocks but not the diagnostics: a later front-end error
// in the same program is still reported.
TEST(Pipeline, ARefusedBlockDoesNotHideLaterErrors) {
  std::string text = kRefusedArc;
  text.replace(text.rfind("M30"), 3, "G1 X1 Q7\nM30");
  const CheckResult r = check_program_text(text, "bad.ngc", wide_arc_config(), JobOptions{});
  EXPECT_FALSE(r.ok);
  int errors = 0;
  for (const Diagnostic& d : r.diagnostics) errors += d.severity == Diagnostic::Severity::kError;
  EXPECT_GE(errors, 2) << first_check_error(r);
}

// Every program of ../shared/gcode under every shipped config (configs/*.toml), contouring
// on so that the path tolerance smooths and merges: no block the host makes is refused by
// the rt's block check (check runs that check on every block it makes). A program the
// dialect or the travel refuses is fine; a block check refusal is not (issue 14).
TEST(Pipeline, EveryCorpusProgramUnderEveryShippedConfigPassesTheBlockCheck) {
  std::vector<std::string> configs;
  for (const auto& e : fs::directory_iterator(test::source_dir() + "/configs"))
    if (e.path().extension() == ".toml") configs.push_back(e.path().string());
  std::sort(configs.begin(), configs.end());
  ASSERT_GE(configs.size(), 2u);
  const std::vector<std::string> programs = corpus_programs();
  int sampled_accepted = 0;
  for (std::size_t k = 0; k < configs.size(); ++k) {
    const std::string& cfg = configs[k];
    const MachineConfig c = load_config(cfg);
    int checked = 0, accepted = 0;
    for (std::size_t i = 0; i < programs.size(); ++i) {
      // under the sanitizers: program i under config i mod n only (test_paths.hpp)
      if (test::sanitizer_build() && i % configs.size() != k) continue;
      const std::string& path = programs[i];
      JobOptions o;
      o.contouring = true;
      o.fit = true;
      const CheckResult r = check_program(path, c, o);
      ++checked;
      if (r.ok) {
        ++accepted;
        continue;
      }
      const std::string e = first_check_error(r);
      EXPECT_EQ(e.find("refused by the rt's block check"), std::string::npos) << cfg << ": " << e;
    }
    if (test::sanitizer_build()) {
      sampled_accepted += accepted;
      continue;
    }
    EXPECT_GE(accepted, 30) << cfg << ": of " << checked;
  }
  if (test::sanitizer_build()) {
    EXPECT_GE(sampled_accepted, 30) << "of " << programs.size();
  }
}

// Smoothing in the pipeline: a run of short G1 moves becomes curves (far fewer blocks), an arc
// in the middle passes unchanged, and the smoothed blocks start and end where the run does.
TEST(Pipeline, SmoothingMakesFewBlocksOfARunAndPassesArcsUnchanged) {
  std::ostringstream prog;
  prog << "G21 G90 G17 M21\nG0 X0 Y0 Z-1\nG1 F1200\n";
  for (int i = 1; i <= 200; ++i) prog << "X" << 0.05 * i << " Y" << std::sin(0.05 * i) << "\n";
  prog << "G2 X12 Y" << std::sin(10.0) << " I1 J0\n";
  prog << "G1 ";
  for (int i = 1; i <= 100; ++i) prog << "X" << 12.0 + 0.05 * i << " Y" << std::sin(10.0) + 0.2 * std::sin(0.1 * i) << "\n";
  prog << "M30\n";
  std::vector<Block> smoothed, plain;
  MachineConfig c = test::wide_config();
  set_operator_tolerance(c.motion, 0.005);
  const CheckResult r = check_program_text(prog.str(), "s.ngc", c, JobOptions{}, [&](const Block& b) { smoothed.push_back(b); });
  ASSERT_TRUE(r.ok) << first_check_error(r);
  set_operator_tolerance(c.motion, 0.0);
  const CheckResult r0 = check_program_text(prog.str(), "s.ngc", c, JobOptions{}, [&](const Block& b) { plain.push_back(b); });
  ASSERT_TRUE(r0.ok) << first_check_error(r0);
  EXPECT_EQ(r.smoothed_moves, 300u);
  EXPECT_EQ(r.smoothed_curves, 2u);
  EXPECT_EQ(r.smoothed_blocks, r.blocks - 3) << "the rapid, the arc and the End are not smoothed";
  EXPECT_LT(r.blocks, 40u) << "300 moves in a few dozen blocks";
  EXPECT_EQ(r0.blocks, 303u);
  EXPECT_EQ(r0.smoothed_moves, 0u);
  EXPECT_GT(r.max_path_deviation_mm, 0.0);
  EXPECT_LE(r.max_path_deviation_mm, 0.005);
  const auto arc = [](const std::vector<Block>& v) {
    return *std::find_if(v.begin(), v.end(), [](const Block& b) { return b.kind == BlockKind::kArc; });
  };
  const Block a = arc(smoothed), a0 = arc(plain);
  EXPECT_EQ(a.start, a0.start);
  EXPECT_EQ(a.end, a0.end);
  EXPECT_EQ(a.arc.center, a0.arc.center);
  EXPECT_EQ(a.arc.sweep, a0.arc.sweep);
  EXPECT_EQ(a.path_tolerance_mm, 0.005f);
  EXPECT_EQ(a0.path_tolerance_mm, 0.0f);
  // the curves start and end exactly at the run's ends: the arc's start is the last G1's end
  std::size_t ai = 0;
  while (smoothed[ai].kind != BlockKind::kArc) ++ai;
  EXPECT_EQ(smoothed[ai - 1].kind, BlockKind::kNurbs);
  EXPECT_EQ(smoothed[ai - 1].end, a0.start);
}

// G64 P sets the path tolerance (program units), G64 alone takes the config's, G61 and M22
// keep exact stops; --tolerance (set_operator_tolerance) holds over G64 P.
TEST(Pipeline, G64PSetsThePathTolerance) {
  const auto blocks_of = [](const std::string& text, const MachineConfig& c) {
    std::vector<Block> v;
    const CheckResult r = check_program_text(text, "t.ngc", c, JobOptions{}, [&](const Block& b) { v.push_back(b); });
    EXPECT_TRUE(r.ok) << first_check_error(r);
    return v;
  };
  MachineConfig c = test::wide_config();
  c.motion.path_tolerance_mm = 0.005;
  const std::string moves = "G1 X1 F600\nX2 Y0.5\n";
  EXPECT_EQ(blocks_of("G64 P0.02\n" + moves + "M30\n", c)[0].path_tolerance_mm, 0.02f);
  EXPECT_EQ(blocks_of("G20 G64 P0.001\n" + moves + "M30\n", c)[0].path_tolerance_mm, static_cast<float>(0.0254));
  EXPECT_EQ(blocks_of("G64 P0.02\nG64\n" + moves + "M30\n", c)[0].path_tolerance_mm, 0.005f);
  EXPECT_EQ(blocks_of("G64 P0.02\nG61\n" + moves + "M30\n", c)[0].path_tolerance_mm, 0.0f);
  EXPECT_EQ(blocks_of("G64 P0.02\nM22\n" + moves + "M30\n", c)[0].path_tolerance_mm, 0.0f);
  set_operator_tolerance(c.motion, 0.003);
  EXPECT_EQ(blocks_of("G64 P0.02\n" + moves + "M30\n", c)[0].path_tolerance_mm, 0.003f);
}

// The run's check records which lines hold rapids (the report draws them dashed from this).
TEST(Pipeline, CheckRecordsTheLinesOfRapidBlocks) {
  const std::string text = "G21 G90\nG0 X1\nG0 Y1\nG1 X2 F600\nG0 Z-1\nG1 X3\nM30\n";
  const CheckResult r = check_program_text(text, "r.ngc", test::wide_config(), JobOptions{});
  ASSERT_TRUE(r.ok) << first_check_error(r);
  ASSERT_EQ(r.rapid_lines.size(), 2u);
  EXPECT_EQ(r.rapid_lines[0].first, 2u);
  EXPECT_EQ(r.rapid_lines[0].last, 3u);
  EXPECT_EQ(r.rapid_lines[1].first, 5u);
  EXPECT_EQ(r.rapid_lines[1].last, 5u);
  EXPECT_EQ(r.blocks, 6u);  // five moves and the End block
}

// A UTF-8 byte order mark before the first line (Notepad's "UTF-8") is the file's encoding,
// not G-code: the program runs as without it, from a file and from text, and a column on line 1
// counts from after it. Anywhere else those bytes are an error, as any stray byte is.
TEST(Pipeline, AByteOrderMarkBeforeTheFirstLineIsNotPartOfTheProgram) {
  const std::string bom = "\xEF\xBB\xBF";
  const std::string text = "G21 G90\r\nG0 X1 Y1 Z-1\r\nG1 X2 F300\r\nM30\r\n";
  const MachineConfig c = test::wide_config();
  std::vector<std::string> plain, marked, from_file;
  const CheckResult a = check_program_text(text, "p.ngc", c, JobOptions{}, [&](const Block& b) { plain.push_back(format_block(b)); });
  const CheckResult b = check_program_text(bom + text, "p.ngc", c, JobOptions{}, [&](const Block& x) { marked.push_back(format_block(x)); });
  ASSERT_TRUE(a.ok) << first_check_error(a);
  ASSERT_TRUE(b.ok) << first_check_error(b);
  EXPECT_EQ(marked, plain);
  const std::string path = (fs::temp_directory_path() / ("pcnc-bom-" + std::to_string(::getpid()) + ".ngc")).string();
  std::ofstream(path, std::ios::binary) << bom << text;
  const CheckResult f = check_program(path, c, JobOptions{}, [&](const Block& x) { from_file.push_back(format_block(x)); });
  fs::remove(path);
  ASSERT_TRUE(f.ok) << first_check_error(f);
  EXPECT_EQ(from_file, plain);

  const CheckResult bad = check_program_text(bom + "G21 Q1\nM30\n", "p.ngc", c, JobOptions{});
  ASSERT_FALSE(bad.ok);
  EXPECT_EQ(bad.diagnostics[0].line, 1);
  EXPECT_EQ(bad.diagnostics[0].column, 5) << first_check_error(bad);
  const CheckResult inside = check_program_text("G21\n" + bom + "G0 X1\nM30\n", "p.ngc", c, JobOptions{});
  ASSERT_FALSE(inside.ok);
  EXPECT_EQ(inside.diagnostics[0].line, 2) << first_check_error(inside);
}

// ---- progress of a long check (gcode/check_progress.hpp) ----

// A program of `n` short G1 moves on a spiral (smoothing makes curves of them), in memory.
std::string long_program(int n) {
  std::string text = "G21 G90 G17\nG0 X0 Y0 Z1\nG1 Z0 F600\n";
  char line[96];
  for (int i = 0; i < n; ++i) {
    const double a = 0.01 * i, r = 2.0 + 0.0005 * i;
    std::snprintf(line, sizeof line, "G1 X%.4f Y%.4f\n", r * std::cos(a), r * std::sin(a));
    text += line;
  }
  return text + "G0 Z1\nM2\n";
}

// The check reports its progress as it reads: the --fit pass, then the check, each line and
// byte count moving forward within the text, the blocks made so far; and a report changes
// nothing the check finds.
TEST(CheckProgress, ReportsBothPassesInOrderAndChangesNothing) {
  const std::string text = long_program(6000);
  const MachineConfig c = test::wide_config();
  JobOptions plain;
  plain.fit = true;
  const CheckResult quiet = check_program_text(text, "p.ngc", c, plain);
  ASSERT_TRUE(quiet.ok) << first_check_error(quiet);

  std::vector<CheckProgress> seen;
  JobOptions o = plain;
  o.check_progress_interval_s = 0.0;  // every MoveSource::kLineHookEvery lines
  o.on_check_progress = [&](const CheckProgress& p) { seen.push_back(p); };
  const CheckResult r = check_program_text(text, "p.ngc", c, o);
  ASSERT_TRUE(r.ok) << first_check_error(r);
  EXPECT_FALSE(r.interrupted);
  EXPECT_EQ(r.blocks, quiet.blocks);
  EXPECT_EQ(r.moves, quiet.moves);
  EXPECT_DOUBLE_EQ(r.planned_time_s, quiet.planned_time_s);
  EXPECT_EQ(r.transform.scale, quiet.transform.scale);

  const std::size_t lines = 6005;  // run once each: both passes report every 1024 lines
  const std::size_t per_pass = lines / MoveSource::kLineHookEvery;
  ASSERT_EQ(seen.size(), 2 * per_pass);
  for (std::size_t i = 0; i < seen.size(); ++i) {
    const CheckProgress& p = seen[i];
    const std::size_t k = i % per_pass + 1;  // the k-th report of its pass
    EXPECT_EQ(p.pass, i < per_pass ? CheckPass::kFit : CheckPass::kCheck) << i;
    EXPECT_EQ(p.line, k * MoveSource::kLineHookEvery) << i << ": the report comes as that line runs";
    EXPECT_EQ(p.total_bytes, text.size());
    // the bytes read end with the line reached
    ASSERT_LE(p.bytes_read, text.size());
    ASSERT_GT(p.bytes_read, 0u);
    EXPECT_EQ(text[p.bytes_read - 1], '\n') << i;
    EXPECT_EQ(static_cast<std::uint64_t>(std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(p.bytes_read), '\n')), p.line) << i;
    EXPECT_NEAR(p.fraction(), static_cast<double>(p.bytes_read) / static_cast<double>(text.size()), 1e-15);
    if (p.pass == CheckPass::kFit) {
      EXPECT_EQ(p.blocks, 0u);
    }
    if (i > per_pass) {
      EXPECT_GE(p.blocks, seen[i - 1].blocks);
    }
  }
  EXPECT_GT(seen.back().blocks, 0u);
  EXPECT_LE(seen.back().blocks, r.blocks);
  EXPECT_GT(seen.back().fraction(), 0.8);

  // an interval longer than any check: no report at all (none before the interval has passed)
  int reports = 0;
  JobOptions patient = plain;
  patient.check_progress_interval_s = 1000.0;
  patient.on_check_progress = [&](const CheckProgress&) { ++reports; };
  EXPECT_TRUE(check_program_text(text, "p.ngc", c, patient).ok);
  EXPECT_EQ(reports, 0);
}

// A handler that throws CheckInterrupted ends the check where it is: it fails with that one
// error at the line reached, makes no more blocks, and says it was interrupted.
TEST(CheckProgress, AnInterruptedCheckFailsAtTheLineReachedAndMakesNoMoreBlocks) {
  const std::string text = long_program(6000);
  const MachineConfig c = test::wide_config();
  for (const bool fit : {false, true}) {
    JobOptions o;
    o.fit = fit;
    o.check_progress_interval_s = 0.0;
    int reports = 0;
    std::uint64_t stopped_at = 0, blocks_then = 0;
    o.on_check_progress = [&](const CheckProgress& p) {
      if (++reports < 3) return;  // the third report: in the check pass without --fit, the fit pass with it
      stopped_at = p.line;
      blocks_then = p.blocks;
      throw CheckInterrupted("stopped by the test");
    };
    std::uint64_t blocks_seen = 0;
    const CheckResult r = check_program_text(text, "p.ngc", c, o, [&](const Block&) { ++blocks_seen; });
    EXPECT_FALSE(r.ok);
    EXPECT_TRUE(r.interrupted);
    EXPECT_EQ(reports, 3);
    EXPECT_EQ(stopped_at, 3 * MoveSource::kLineHookEvery);
    ASSERT_EQ(r.diagnostics.size(), 1u) << first_check_error(r);
    EXPECT_EQ(r.diagnostics[0].severity, Diagnostic::Severity::kError);
    EXPECT_EQ(r.diagnostics[0].message, "stopped by the test");
    EXPECT_EQ(static_cast<std::uint64_t>(r.diagnostics[0].line), stopped_at);
    EXPECT_EQ(blocks_seen, blocks_then) << "no block after the interruption";
    if (fit) {
      EXPECT_EQ(blocks_seen, 0u) << "interrupted in the fit pass: no block made at all";
    } else {
      EXPECT_GT(blocks_seen, 0u);
    }
  }
}

}  // namespace
}  // namespace pcnc
