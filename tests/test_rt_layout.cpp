// test_rt_layout.cpp — the rt's rooms keep their arrows pointing down (DESIGN.md "Layout"):
// rt/motion and rt/drive include nothing from rt/loop (the machine that owns them), the rt
// includes nothing from the host, and no rt source file grows past 700 lines.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "test_paths.hpp"

namespace pcnc {
namespace {

namespace fs = std::filesystem;

struct Source {
  std::string path;
  std::vector<std::string> lines;
};

std::vector<Source> sources_in(const std::string& dir) {
  std::vector<Source> out;
  for (const auto& e : fs::recursive_directory_iterator(test::source_dir() + "/" + dir)) {
    const std::string ext = e.path().extension().string();
    if (!e.is_regular_file() || (ext != ".cpp" && ext != ".hpp")) continue;
    Source s{fs::relative(e.path(), test::source_dir()).string(), {}};
    std::ifstream in(e.path());
    for (std::string line; std::getline(in, line);) s.lines.push_back(line);
    out.push_back(std::move(s));
  }
  return out;
}

bool includes_from(const Source& s, const std::string& room) {
  for (const std::string& l : s.lines) {
    if (l.rfind("#include \"" + room + "/", 0) == 0) return true;
  }
  return false;
}

TEST(RtLayout, MotionAndDriveNeverIncludeTheLoop) {
  int files = 0;
  for (const char* dir : {"rt/motion", "rt/drive"}) {
    for (const Source& s : sources_in(dir)) {
      ++files;
      EXPECT_FALSE(includes_from(s, "loop")) << s.path << " includes rt/loop: arrows point down";
    }
  }
  EXPECT_GE(files, 8);
}

TEST(RtLayout, TheRtIncludesNothingFromTheHost) {
  for (const Source& s : sources_in("rt")) {
    for (const char* room : {"gcode", "service", "report"}) {
      EXPECT_FALSE(includes_from(s, room)) << s.path << " includes host/" << room;
    }
  }
}

TEST(RtLayout, NoRtSourceFileOver700Lines) {
  for (const Source& s : sources_in("rt")) EXPECT_LE(s.lines.size(), 700u) << s.path;
}

}  // namespace
}  // namespace pcnc
