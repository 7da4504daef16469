// test_pipeline.cpp — the one front-end pipeline (host/gcode/pipeline.hpp): `check` and the
// streamed path (BlockStream) make the same blocks for every program of ../shared/gcode, and
// check refuses a block the rt's block check would refuse, at the block's source line.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstddef>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "check.hpp"
#include "gcode_test_util.hpp"

namespace pcnc {
namespace {

namespace fs = std::filesystem;

std::string gcode_dir() { return test::shared_dir() + "/gcode"; }

std::vector<std::string> corpus_programs() {
  std::vector<std::string> out;
  for (const auto& e : fs::recursive_directory_iterator(gcode_dir())) {
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

std::string first_error(const CheckResult& r) {
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
    if (same_blocks_from_check_and_stream(gcode_dir() + "/" + rel, c, o)) ++accepted;
  }
  EXPECT_GE(accepted, 3);
}

// regress/bad-block-z.ngc: a block the rt refuses ("bad block on axis Z") used to pass check.
JobOptions bad_block_z_options() {
  JobOptions o;
  o.offset = Vec3{-42.4053, -61.7220, 2.9312};
  o.contouring = true;
  return o;
}

TEST(Pipeline, CheckRefusesTheBlockTheRtRefuses) {
  const MachineConfig c = load_config(test::source_dir() + "/configs/bench-peers.toml");
  const std::string path = gcode_dir() + "/regress/bad-block-z.ngc";
  const CheckResult r = check_program(path, c, bad_block_z_options());
  EXPECT_FALSE(r.ok);
  const std::string e = first_error(r);
  EXPECT_NE(e.find("bad-block-z.ngc:"), std::string::npos) << e;
  EXPECT_NE(e.find("refused by the rt's block check"), std::string::npos) << e;
  EXPECT_NE(e.find("axis Z"), std::string::npos) << e;
}

TEST(Pipeline, CheckCommandRefusesTheBlockTheRtRefuses) {
  CheckCommandOptions o;
  o.file = gcode_dir() + "/regress/bad-block-z.ngc";
  o.config_path = test::source_dir() + "/configs/bench-peers.toml";
  o.offset = "-42.4053,-61.7220,2.9312";
  o.contouring = "on";
  std::ostringstream out, err;
  EXPECT_NE(run_check_command(o, out, err), 0);
  EXPECT_NE(out.str().find("FAILED"), std::string::npos) << out.str();
  EXPECT_NE(err.str().find("refused by the rt's block check"), std::string::npos) << err.str();
}

// A block check refusal stops the blocks but not the diagnostics: a later front-end error
// in the same program is still reported.
TEST(Pipeline, ARefusedBlockDoesNotHideLaterErrors) {
  const MachineConfig c = load_config(test::source_dir() + "/configs/bench-peers.toml");
  std::string text;
  {
    std::ifstream in(gcode_dir() + "/regress/bad-block-z.ngc");
    std::stringstream ss;
    ss << in.rdbuf();
    text = ss.str();
  }
  text.replace(text.rfind("M30"), 3, "G1 X1 Q7\nM30");
  const CheckResult r = check_program_text(text, "bad.ngc", c, bad_block_z_options());
  EXPECT_FALSE(r.ok);
  int errors = 0;
  for (const Diagnostic& d : r.diagnostics) errors += d.severity == Diagnostic::Severity::kError;
  EXPECT_GE(errors, 2) << first_error(r);
}

// The run's check records which lines hold rapids (the report draws them dashed from this).
TEST(Pipeline, CheckRecordsTheLinesOfRapidBlocks) {
  const std::string text = "G21 G90\nG0 X1\nG0 Y1\nG1 X2 F600\nG0 Z-1\nG1 X3\nM30\n";
  const CheckResult r = check_program_text(text, "r.ngc", test::wide_config(), JobOptions{});
  ASSERT_TRUE(r.ok) << first_error(r);
  ASSERT_EQ(r.rapid_lines.size(), 2u);
  EXPECT_EQ(r.rapid_lines[0].first, 2u);
  EXPECT_EQ(r.rapid_lines[0].last, 3u);
  EXPECT_EQ(r.rapid_lines[1].first, 5u);
  EXPECT_EQ(r.rapid_lines[1].last, 5u);
  EXPECT_EQ(r.blocks, 6u);  // five moves and the End block
}

}  // namespace
}  // namespace pcnc
