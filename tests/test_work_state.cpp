// test_work_state.cpp — the work-coordinate state file (config/work_state.hpp): defaults from
// the config, the round trip through the file, what a missing, corrupt, out-of-range or
// symlinked file does, the file's mode and directory; and the config's tool-table keys.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <sstream>

#include "config/config.hpp"
#include "config/runtime_paths.hpp"
#include "config/work_state.hpp"
#include "test_paths.hpp"

namespace pcnc {
namespace {

namespace fs = std::filesystem;

// A fresh private directory per test, removed at the end.
struct TempDir {
  std::string path;
  TempDir() {
    std::string t = (fs::temp_directory_path() / "pcnc-ws-XXXXXX").string();
    path = ::mkdtemp(t.data());
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
};

void write(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

std::string read(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const WorkStateError& e) {
    return e.what();
  }
  return "";
}

MachineConfig machine() { return load_config(test::default_config()); }

WorkState sample() {
  WorkState s;
  for (int i = 0; i < kWorkSystems; ++i) s.g5x[static_cast<std::size_t>(i)] = Vec3{i + 0.5, -i - 0.25, 10.0 * i};
  s.active = 7;
  s.g92 = {1.0, -2.0, 3.125};
  s.g92_applied = true;
  s.g28 = {0.0, 25.0, 25.0};
  s.g30 = {-1e6, 1e6, 0.001};
  s.tool = 12;
  s.tool_offset_applied = true;
  s.tool_offset = {0.0, 0.0, 41.25};
  return s;
}

TEST(WorkState, NamesOfTheNineSystems) {
  const char* names[] = {"G54", "G55", "G56", "G57", "G58", "G59", "G59.1", "G59.2", "G59.3"};
  for (int i = 0; i < kWorkSystems; ++i) {
    EXPECT_EQ(work_system_name(i), names[i]);
    EXPECT_EQ(parse_work_system_name(names[i]), i);
  }
  EXPECT_EQ(parse_work_system_name("g59.2"), 7);
  for (const char* bad : {"G53", "G60", "G59.4", "G59.", "G5", "", "G54 ", "59"}) EXPECT_EQ(parse_work_system_name(bad), -1) << bad;
}

TEST(WorkState, DefaultComesFromTheConfig) {
  const MachineConfig c = machine();
  const WorkState s = default_work_state(c);
  for (std::size_t i = 0; i < 6; ++i) EXPECT_EQ(s.g5x[i], c.gcode.work_offsets[i]) << i;
  EXPECT_EQ(s.g5x[0], (Vec3{12.5, 12.5, 25.0})) << "the shipped config's G54";
  for (std::size_t i = 6; i < 9; ++i) EXPECT_EQ(s.g5x[i], (Vec3{0, 0, 0})) << i;
  EXPECT_EQ(s.active, 0);
  EXPECT_EQ(s.g92, (Vec3{0, 0, 0}));
  EXPECT_FALSE(s.g92_applied);
  for (std::size_t a = 0; a < 3; ++a) {
    EXPECT_EQ(s.g28[a], c.axes[a].home_mm);
    EXPECT_EQ(s.g30[a], c.axes[a].home_mm);
  }
}

TEST(WorkState, PathIsInTheStateDirectory) {
  MachineConfig c = machine();
  c.process.state_dir = "/var/tmp/pcnc-x";
  EXPECT_EQ(work_state_path(c), "/var/tmp/pcnc-x/work_state.json");
  EXPECT_EQ(work_state_path(c), state_dir(c) + "/work_state.json");
}

TEST(WorkState, MissingFileGivesTheDefault) {
  TempDir d;
  const MachineConfig c = machine();
  EXPECT_EQ(load_work_state(c, d.path + "/work_state.json"), default_work_state(c));
  EXPECT_FALSE(fs::exists(d.path + "/work_state.json")) << "loading does not create it";
}

TEST(WorkState, RoundTripThroughThePrivateFile) {
  TempDir d;
  const std::string dir = d.path + "/state";
  const std::string path = dir + "/work_state.json";
  save_work_state(path, sample());
  EXPECT_EQ(load_work_state(machine(), path), sample());
  struct stat st {};
  ASSERT_EQ(::stat(path.c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 07777, 0600u);
  ASSERT_EQ(::stat(dir.c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 07777, 0700u) << "the directory is created private";
  EXPECT_FALSE(fs::exists(path + ".tmp"));

  // A person can read it: named keys, one system per key.
  const std::string text = read(path);
  for (const char* key : {"\"version\": 1", "\"active\": \"G59.2\"", "\"G54\"", "\"G59.3\"", "\"G92_applied\": true", "\"G28\"", "\"G30\""}) {
    EXPECT_NE(text.find(key), std::string::npos) << key << " in\n" << text;
  }

  // Saving again replaces it.
  WorkState s = sample();
  s.g5x[1] = {7, 8, 9};
  save_work_state(path, s);
  EXPECT_EQ(load_work_state(machine(), path).g5x[1], (Vec3{7, 8, 9}));
}

TEST(WorkState, CorruptFileIsRefusedNamingTheFile) {
  TempDir d;
  const std::string path = d.path + "/work_state.json";
  const MachineConfig c = machine();
  const std::string good = format_work_state(sample());
  auto refused_for = [&](const std::string& text, const std::string& why) {
    write(path, text);
    const std::string e = error_of([&] { load_work_state(c, path); });
    EXPECT_NE(e.find(path), std::string::npos) << "names the file: " << e;
    EXPECT_NE(e.find(why), std::string::npos) << "says '" << why << "': " << e;
  };
  auto replaced = [&](const std::string& from, const std::string& to) {
    std::string t = good;
    const auto at = t.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return t.replace(at, from.size(), to);
  };
  refused_for("", "not valid JSON");
  refused_for(good.substr(0, good.size() / 2), "not valid JSON");
  refused_for("[1, 2, 3]", "expected a JSON object");
  refused_for(replaced("\"G55\"", "\"G5x\""), "unknown key 'G5x'");
  refused_for(replaced("\"version\": 1", "\"version\": 2"), "key 'version'");
  refused_for(replaced("\"active\": \"G59.2\"", "\"active\": \"G60\""), "key 'active'");
  refused_for(replaced("\"active\": \"G59.2\"", "\"active\": 3"), "key 'active'");
  refused_for(replaced("\"G92_applied\": true", "\"G92_applied\": 1"), "G92_applied");
  refused_for(replaced("\"x\": 0.5", "\"x\": \"0.5\""), "key 'G54'");
  refused_for(replaced("\"x\": 0.5", "\"x\": 2e6"), "key 'G54.x'");
  refused_for(replaced("\"x\": 0.5", "\"x\": 1e999"), "work-coordinate state");  // JSON overflow
  refused_for(replaced("\"x\": 0.5,", ""), "key 'G54'");
  // A key left out is refused, not read as zero.
  nlohmann::json j = nlohmann::json::parse(good);
  j.erase("G30");
  refused_for(j.dump(), "missing key 'G30'");
  // The tool: its three keys, each checked.
  j = nlohmann::json::parse(good);
  j["tool"]["number"] = -1;
  refused_for(j.dump(), "tool.number");
  j = nlohmann::json::parse(good);
  j["tool"].erase("offset_applied");
  refused_for(j.dump(), "missing key 'tool.offset_applied'");
  j = nlohmann::json::parse(good);
  j["tool"]["length"] = 3;
  refused_for(j.dump(), "unknown key 'tool.length'");
}

TEST(WorkState, AFileWithoutTheToolHasNoToolAndNoOffset) {
  // Files written before the tool was kept: no tool in the spindle, no length offset.
  nlohmann::json j = nlohmann::json::parse(format_work_state(sample()));
  ASSERT_TRUE(j.contains("tool"));
  EXPECT_EQ(j["tool"]["number"], 12);
  EXPECT_EQ(j["tool"]["offset"]["z"], 41.25);
  j.erase("tool");
  const WorkState w = parse_work_state(j.dump(), "old.json");
  EXPECT_EQ(w.tool, 0);
  EXPECT_FALSE(w.tool_offset_applied);
  EXPECT_EQ(w.tool_offset, Vec3{});
  EXPECT_EQ(w.g5x, sample().g5x);
}

TEST(WorkState, SymlinkAndNonRegularFilesAreRefused) {
  TempDir d;
  const std::string target = d.path + "/elsewhere.json";
  save_work_state(target, sample());
  const std::string path = d.path + "/work_state.json";
  ASSERT_EQ(::symlink(target.c_str(), path.c_str()), 0);
  std::string e = error_of([&] { load_work_state(machine(), path); });
  EXPECT_NE(e.find(path), std::string::npos) << e;
  EXPECT_NE(e.find("symbolic link"), std::string::npos) << e;

  // A dangling link is refused too (not taken for a missing file).
  ::unlink(path.c_str());
  ASSERT_EQ(::symlink((d.path + "/nothing").c_str(), path.c_str()), 0);
  EXPECT_NE(error_of([&] { load_work_state(machine(), path); }).find("symbolic link"), std::string::npos);

  // Saving replaces the link itself; the link's target is not written through.
  const std::string before = read(target);
  ::unlink(path.c_str());
  ASSERT_EQ(::symlink(target.c_str(), path.c_str()), 0);
  WorkState s = sample();
  s.active = 0;
  save_work_state(path, s);
  EXPECT_EQ(read(target), before);
  EXPECT_FALSE(fs::is_symlink(path));
  EXPECT_EQ(load_work_state(machine(), path), s);

  const std::string dir = d.path + "/a-directory";
  fs::create_directory(dir);
  EXPECT_NE(error_of([&] { load_work_state(machine(), dir); }).find("not a regular file"), std::string::npos);
}

TEST(WorkState, SaveIntoAnUnusableDirectoryThrowsNamingTheFile) {
  TempDir d;
  write(d.path + "/file", "x");
  const std::string e = error_of([&] { save_work_state(d.path + "/file/work_state.json", sample()); });
  EXPECT_NE(e.find("cannot save the work-coordinate state"), std::string::npos) << e;
  EXPECT_NE(e.find(d.path + "/file/work_state.json"), std::string::npos) << e;
  // A relative path is refused: its directory (the working one) is not made private.
  EXPECT_NE(error_of([&] { save_work_state("work_state.json", sample()); }).find("must be absolute"), std::string::npos);
  EXPECT_FALSE(fs::exists("work_state.json"));
}

// ---- the config's keys for the tool table and M6

TEST(Config, ToolTableIsRelativeToTheConfigFile) {
  // The shipped config with its tool keys changed (a config must be whole: issue 20).
  const std::string shipped = read(test::source_dir() + "/configs/desktop-mill.toml");
  const auto with = [&](const std::string& table_line, const std::string& pause_line = "pause_on_tool_change = false") {
    std::string text;
    std::istringstream in(shipped);
    std::string line;
    while (std::getline(in, line)) {
      if (line.rfind("tool_table", 0) == 0) line = table_line;
      if (line.rfind("pause_on_tool_change", 0) == 0) line = pause_line;
      text += line + "\n";
    }
    return text;
  };
  EXPECT_EQ(parse_config(with("tool_table = \"\""), "t").gcode.tool_table, "");
  EXPECT_FALSE(parse_config(with("tool_table = \"\""), "t").gcode.pause_on_tool_change);
  EXPECT_EQ(parse_config(with("tool_table = \"tools.tbl\""), "/etc/pcnc/mill.toml").gcode.tool_table, "/etc/pcnc/tools.tbl");
  EXPECT_EQ(parse_config(with("tool_table = \"../t/a.tbl\""), "/etc/pcnc/mill.toml").gcode.tool_table, "/etc/t/a.tbl");
  EXPECT_EQ(parse_config(with("tool_table = \"/abs/a.tbl\""), "/etc/pcnc/mill.toml").gcode.tool_table, "/abs/a.tbl");
  EXPECT_EQ(parse_config(with("tool_table = \"a.tbl\""), "mill.toml").gcode.tool_table, "a.tbl");
  EXPECT_TRUE(parse_config(with("tool_table = \"\"", "pause_on_tool_change = true"), "t").gcode.pause_on_tool_change);
  EXPECT_THROW(parse_config(with("tool_table = \"\"", "pause_on_tool_change = 1"), "t"), ConfigError);
  EXPECT_THROW(parse_config(with("tool_table = 3"), "t"), ConfigError);
  EXPECT_THROW(parse_config(with("tool_tabel = \"a.tbl\""), "t"), ConfigError) << "unknown keys stay refused";
}

TEST(Config, ShippedConfigsSetTheToolKeys) {
  for (const char* name : {"desktop-mill.toml", "bench-peers.toml"}) {
    const std::string path = test::source_dir() + "/configs/" + name;
    EXPECT_NE(read(path).find("\ntool_table = "), std::string::npos) << name;
    EXPECT_NE(read(path).find("\npause_on_tool_change = false"), std::string::npos) << name;
    const MachineConfig c = load_config(path);
    EXPECT_EQ(c.gcode.tool_table, "") << name;
    EXPECT_FALSE(c.gcode.pause_on_tool_change) << name;
  }
}

}  // namespace
}  // namespace pcnc
