// work_state.cpp — the work-coordinate state file: defaults, JSON form, load and save (see
// work_state.hpp).
#include "config/work_state.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "config/atomic_file.hpp"
#include "config/runtime_paths.hpp"

namespace pcnc {

using json = nlohmann::ordered_json;

namespace {

constexpr std::size_t kMaxWorkStateFileBytes = 64 * 1024;  // the file is well under 2 KiB
const char* const kAxisKeys[3] = {"x", "y", "z"};

json vec_json(const Vec3& v) { return json{{"x", v[0]}, {"y", v[1]}, {"z", v[2]}}; }

[[noreturn]] void refuse_state(const std::string& origin, const std::string& why) {
  throw WorkStateError("work-coordinate state " + origin + ": " + why);
}

Vec3 read_vec(const json& doc, const std::string& key, const std::string& origin) {
  const json& v = doc.at(key);
  if (!v.is_object() || v.size() != 3) refuse_state(origin, "key '" + key + "' must be an object {\"x\": mm, \"y\": mm, \"z\": mm}");
  Vec3 out{};
  for (std::size_t i = 0; i < 3; ++i) {
    const auto it = v.find(kAxisKeys[i]);
    if (it == v.end() || !it->is_number()) {
      refuse_state(origin, "key '" + key + "' must be an object {\"x\": mm, \"y\": mm, \"z\": mm}");
    }
    const double d = it->get<double>();
    if (!std::isfinite(d) || std::fabs(d) > kWorkStateLimitMm) {
      std::ostringstream os;
      os << "key '" << key << "." << kAxisKeys[i] << "': value " << d << " is not within ±" << kWorkStateLimitMm << " mm";
      refuse_state(origin, os.str());
    }
    out[i] = d;
  }
  return out;
}

}  // namespace

std::string work_system_name(int index) {
  if (index >= 0 && index < 6) return "G5" + std::to_string(4 + index);
  if (index >= 6 && index < kWorkSystems) return "G59." + std::to_string(index - 5);
  return "G5?";
}

int parse_work_system_name(std::string_view name) {
  for (int i = 0; i < kWorkSystems; ++i) {
    const std::string n = work_system_name(i);
    if (name.size() != n.size()) continue;
    bool same = true;
    for (std::size_t k = 0; k < n.size() && same; ++k) same = std::toupper(static_cast<unsigned char>(name[k])) == n[k];
    if (same) return i;
  }
  return -1;
}

WorkState default_work_state(const MachineConfig& config) {
  WorkState s;
  for (std::size_t i = 0; i < config.gcode.work_offsets.size(); ++i) s.g5x[i] = config.gcode.work_offsets[i];
  for (std::size_t a = 0; a < 3; ++a) s.g28[a] = s.g30[a] = config.axes[a].home_mm;
  return s;
}

std::string work_state_path(const MachineConfig& config) { return state_dir(config) + "/work_state.json"; }

std::string format_work_state(const WorkState& s) {
  json doc = {{"version", kWorkStateVersion}, {"units", "mm"}, {"active", work_system_name(s.active)}};
  for (int i = 0; i < kWorkSystems; ++i) doc[work_system_name(i)] = vec_json(s.g5x[static_cast<std::size_t>(i)]);
  doc["G92"] = vec_json(s.g92);
  doc["G92_applied"] = s.g92_applied;
  doc["G28"] = vec_json(s.g28);
  doc["G30"] = vec_json(s.g30);
  doc["tool"] = {{"number", s.tool}, {"offset_applied", s.tool_offset_applied}, {"offset", vec_json(s.tool_offset)}};
  return doc.dump(2) + "\n";
}

namespace {

// "tool": {"number": N, "offset_applied": bool, "offset": {x, y, z}}, all three keys required.
void read_tool(const json& t, const std::string& origin, WorkState& s) {
  if (!t.is_object()) refuse_state(origin, "key 'tool' must be an object with number, offset_applied and offset");
  for (const auto& [key, value] : t.items()) {
    if (key != "number" && key != "offset_applied" && key != "offset") refuse_state(origin, "unknown key 'tool." + key + "'");
  }
  for (const char* key : {"number", "offset_applied", "offset"}) {
    if (!t.contains(key)) refuse_state(origin, std::string("missing key 'tool.") + key + "'");
  }
  const json& n = t["number"];
  if (!n.is_number_integer() || n.get<long long>() < 0 || n.get<long long>() > 99999) {
    refuse_state(origin, "key 'tool.number' must be a tool number 0..99999, got " + n.dump());
  }
  s.tool = static_cast<int>(n.get<long long>());
  if (!t["offset_applied"].is_boolean()) refuse_state(origin, "key 'tool.offset_applied' must be true or false");
  s.tool_offset_applied = t["offset_applied"].get<bool>();
  s.tool_offset = read_vec(t, "offset", origin);
}

}  // namespace

WorkState parse_work_state(const std::string& text, const std::string& origin) {
  json doc;
  try {
    doc = json::parse(text);
  } catch (const json::exception& e) {
    refuse_state(origin, std::string("not valid JSON: ") + e.what());
  }
  if (!doc.is_object()) refuse_state(origin, "expected a JSON object");
  std::set<std::string> expected = {"version", "units", "active", "G92", "G92_applied", "G28", "G30"};
  for (int i = 0; i < kWorkSystems; ++i) expected.insert(work_system_name(i));
  for (const auto& [key, value] : doc.items()) {
    if (!expected.count(key) && key != "tool") refuse_state(origin, "unknown key '" + key + "'");
  }
  for (const auto& key : expected) {
    if (!doc.contains(key)) refuse_state(origin, "missing key '" + key + "'");
  }
  const json& v = doc["version"];
  if (!v.is_number_integer() || v.get<long long>() != kWorkStateVersion) {
    refuse_state(origin, "key 'version' is " + v.dump() + "; this pcnc reads version " + std::to_string(kWorkStateVersion));
  }
  if (doc["units"] != "mm") refuse_state(origin, "key 'units' must be \"mm\"");
  WorkState s;
  const json& active = doc["active"];
  s.active = active.is_string() ? parse_work_system_name(active.get<std::string>()) : -1;
  if (s.active < 0) refuse_state(origin, "key 'active' must name a system G54..G59.3, got " + active.dump());
  for (int i = 0; i < kWorkSystems; ++i) s.g5x[static_cast<std::size_t>(i)] = read_vec(doc, work_system_name(i), origin);
  s.g92 = read_vec(doc, "G92", origin);
  if (!doc["G92_applied"].is_boolean()) refuse_state(origin, "key 'G92_applied' must be true or false");
  s.g92_applied = doc["G92_applied"].get<bool>();
  s.g28 = read_vec(doc, "G28", origin);
  s.g30 = read_vec(doc, "G30", origin);
  if (doc.contains("tool")) read_tool(doc["tool"], origin, s);
  return s;
}

WorkState load_work_state(const MachineConfig& config, const std::string& path) {
  // O_NOFOLLOW: a symlink planted at the file's name is refused, not read through;
  // O_NONBLOCK: a FIFO there does not hang the service (it is refused below).
  const int fd = ::open(path.c_str(), O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) {
    if (errno == ENOENT) return default_work_state(config);
    if (errno == ELOOP) refuse_state(path, "is a symbolic link; refused (remove it, or replace it with the file itself)");
    refuse_state(path, std::string("cannot be opened: ") + std::strerror(errno));
  }
  struct stat st {};
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    ::close(fd);
    refuse_state(path, "is not a regular file");
  }
  if (static_cast<std::size_t>(st.st_size) > kMaxWorkStateFileBytes) {
    ::close(fd);
    refuse_state(path, "is " + std::to_string(st.st_size) + " bytes, more than a work-coordinate state can be");
  }
  std::string text;
  char buf[4096];
  for (;;) {
    const ssize_t n = ::read(fd, buf, sizeof buf);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      const int e = errno;
      ::close(fd);
      refuse_state(path, std::string("cannot be read: ") + std::strerror(e));
    }
    if (n == 0) break;
    text.append(buf, static_cast<std::size_t>(n));
    if (text.size() > kMaxWorkStateFileBytes) break;
  }
  ::close(fd);
  return parse_work_state(text, path);
}

void save_work_state(const std::string& path, const WorkState& state) {
  // Absolute only: its directory is made private (0700), which must never be the working one.
  if (path.empty() || path.front() != '/') {
    throw WorkStateError("cannot save the work-coordinate state '" + path + "': the path must be absolute");
  }
  const auto slash = path.find_last_of('/');
  const std::string dir = slash == 0 ? "/" : path.substr(0, slash);
  try {
    ensure_private_dir(dir, 0700);
  } catch (const RuntimePathError& e) {
    throw WorkStateError(std::string("cannot save the work-coordinate state ") + path + ": " + e.what());
  }
  std::string error;
  if (!write_file_atomically(path, format_work_state(state), &error)) {
    throw WorkStateError("cannot save the work-coordinate state " + path + ": " + error);
  }
}

}  // namespace pcnc
