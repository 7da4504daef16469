// config.cpp — TOML loading for MachineConfig: strict keys, ranges checked, clear messages.
#include "config/config.hpp"

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>
#include <toml++/toml.h>

namespace pcnc {
namespace {

// A table reader that remembers which keys were consumed, so unknown keys can be reported.
class Section {
 public:
  Section(const toml::table* table, std::string path, std::string origin)
      : table_(table), path_(std::move(path)), origin_(std::move(origin)) {}

  void number(const char* key, double& out, double lo, double hi) {
    const toml::node* n = find(key);
    if (!n) return;
    std::optional<double> v = n->value<double>();
    if (!v) fail(key, "expected a number");
    if (!(*v >= lo && *v <= hi)) {
      std::ostringstream os;
      os << "value " << *v << " out of range [" << lo << ", " << hi << "]";
      fail(key, os.str());
    }
    out = *v;
  }
  void integer(const char* key, int& out, long lo, long hi) {
    const toml::node* n = find(key);
    if (!n) return;
    std::optional<int64_t> v = n->value<int64_t>();
    if (!v || !n->is_integer()) fail(key, "expected an integer");
    if (*v < lo || *v > hi) fail(key, "value out of range");
    out = static_cast<int>(*v);
  }
  void boolean(const char* key, bool& out) {
    const toml::node* n = find(key);
    if (!n) return;
    if (!n->is_boolean()) fail(key, "expected true or false");
    out = *n->value<bool>();
  }
  void string(const char* key, std::string& out) {
    const toml::node* n = find(key);
    if (!n) return;
    if (!n->is_string()) fail(key, "expected a string");
    out = *n->value<std::string>();
  }
  void vec3(const char* key, Vec3& out) {
    const toml::node* n = find(key);
    if (!n) return;
    const toml::array* a = n->as_array();
    if (!a || a->size() != 3) fail(key, "expected an array of 3 numbers [x, y, z]");
    for (size_t i = 0; i < 3; ++i) {
      std::optional<double> v = (*a)[i].value<double>();
      if (!v) fail(key, "expected an array of 3 numbers [x, y, z]");
      out[i] = *v;
    }
  }
  const toml::table* subtable(const char* key) {
    const toml::node* n = find(key);
    if (!n) return nullptr;
    if (!n->is_table()) fail(key, "expected a table");
    return n->as_table();
  }
  std::string child_path(const char* key) const { return path_.empty() ? key : path_ + "." + key; }
  const std::string& origin() const { return origin_; }

  // After reading, any key not consumed is a typo or an unsupported setting.
  void finish() const {
    if (!table_) return;
    for (auto&& [k, v] : *table_) {
      if (!used_.count(std::string(k.str()))) {
        throw ConfigError(origin_ + ": unknown key '" + child_path(std::string(k.str()).c_str()) + "'");
      }
    }
  }

  [[noreturn]] void fail(const char* key, const std::string& why) const {
    throw ConfigError(origin_ + ": key '" + child_path(key) + "': " + why);
  }

 private:
  const toml::node* find(const char* key) {
    if (!table_) return nullptr;
    used_[key] = true;
    return table_->get(key);
  }
  const toml::table* table_;
  std::string path_;
  std::string origin_;
  std::map<std::string, bool> used_;
};

void read_axis(Section& parent, const char* key, AxisConfig& a) {
  Section s(parent.subtable(key), parent.child_path(key), parent.origin());
  s.number("travel_min_mm", a.travel_min_mm, -1e4, 1e4);
  s.number("travel_max_mm", a.travel_max_mm, -1e4, 1e4);
  s.number("max_velocity_mm_s", a.max_velocity_mm_s, 1e-3, 1e5);
  s.number("max_accel_mm_s2", a.max_accel_mm_s2, 1e-3, 1e7);
  s.number("following_error_limit_mm", a.following_error_limit_mm, 1e-6, 1e3);
  s.number("home_mm", a.home_mm, -1e4, 1e4);
  s.number("moving_mass_kg", a.moving_mass_kg, 1e-4, 1e4);
  s.number("force_constant_n_per_a", a.force_constant_n_per_a, 1e-4, 1e5);
  s.number("current_limit_a", a.current_limit_a, 1e-4, 1e4);
  s.number("viscous_friction_n_s_per_m", a.viscous_friction_n_s_per_m, 0.0, 1e6);
  s.number("coulomb_friction_n", a.coulomb_friction_n, 0.0, 1e5);
  s.number("gravity_load_n", a.gravity_load_n, -1e5, 1e5);
  s.number("encoder_resolution_mm", a.encoder_resolution_mm, 0.0, 1.0);
  s.number("kp_a_per_mm", a.kp_a_per_mm, 0.0, 1e9);
  s.number("ki_a_per_mm_s", a.ki_a_per_mm_s, 0.0, 1e12);
  s.number("kd_a_s_per_mm", a.kd_a_s_per_mm, 0.0, 1e6);
  s.number("derivative_filter_hz", a.derivative_filter_hz, 1.0, 1e6);
  s.number("velocity_ff_a_s_per_mm", a.velocity_ff_a_s_per_mm, 0.0, 1e6);
  s.number("accel_ff_a_s2_per_mm", a.accel_ff_a_s2_per_mm, 0.0, 1e6);
  s.number("friction_ff_a", a.friction_ff_a, 0.0, 1e4);
  s.number("integrator_limit_a", a.integrator_limit_a, 0.0, 1e4);
  s.finish();
  if (!(a.travel_max_mm > a.travel_min_mm)) parent.fail(key, "travel_max_mm must exceed travel_min_mm");
  if (!(a.home_mm >= a.travel_min_mm && a.home_mm <= a.travel_max_mm)) {
    parent.fail(key, "home_mm must lie within [travel_min_mm, travel_max_mm]");
  }
}

// A path named in the config: relative ones are relative to the config file's directory
// (not the working directory of whichever process reads it).
std::string resolve_beside(const std::string& path, const std::string& config_origin) {
  if (path.empty() || path.front() == '/') return path;
  const std::filesystem::path dir = std::filesystem::path(config_origin).parent_path();
  return dir.empty() ? path : (dir / path).lexically_normal().string();
}

}  // namespace

MachineConfig parse_config(const std::string& toml_text, const std::string& origin) {
  toml::table root;
  try {
    root = toml::parse(toml_text, origin);
  } catch (const toml::parse_error& e) {
    std::ostringstream os;
    os << origin << ":" << e.source().begin.line << ":" << e.source().begin.column << ": " << e.description();
    throw ConfigError(os.str());
  }
  MachineConfig c;
  c.source_path = origin;
  Section top(&root, "", origin);
  top.string("name", c.name);

  {
    Section axes(top.subtable("axis"), "axis", origin);
    read_axis(axes, "x", c.axes[0]);
    read_axis(axes, "y", c.axes[1]);
    read_axis(axes, "z", c.axes[2]);
    axes.finish();
  }
  {
    Section m(top.subtable("motion"), "motion", origin);
    m.number("cycle_hz", c.motion.cycle_hz, 100.0, 100000.0);
    m.number("contouring_angle_deg", c.motion.contouring_angle_deg, 0.0, 90.0);
    m.boolean("contouring_default", c.motion.contouring_default);
    m.number("junction_velocity_step_fraction", c.motion.junction_velocity_step_fraction, 0.0, 100.0);
    m.number("corner_tolerance_mm", c.motion.corner_tolerance_mm, 0.0, 1.0);
    m.number("rapid_speed_mm_s", c.motion.rapid_speed_mm_s, 0.0, 1e5);
    m.number("jog_accel_fraction", c.motion.jog_accel_fraction, 0.01, 1.0);
    m.number("subsample_steps", c.motion.subsample_steps, 1.0, 1000.0);
    m.number("block_tolerance_mm", c.motion.block_tolerance_mm, 1e-9, 1.0);
    m.finish();
  }
  {
    Section g(top.subtable("gcode"), "gcode", origin);
    g.number("arc_radius_tolerance_mm", c.gcode.arc_radius_tolerance_mm, 0.0, 10.0);
    g.number("arc_radius_tolerance_rel", c.gcode.arc_radius_tolerance_rel, 0.0, 1.0);
    g.boolean("clamp_excess_feed", c.gcode.clamp_excess_feed);
    g.number("max_feed_mm_min", c.gcode.max_feed_mm_min, 0.0, 1e7);
    static const char* names[6] = {"g54", "g55", "g56", "g57", "g58", "g59"};
    for (int i = 0; i < 6; ++i) g.vec3(names[i], c.gcode.work_offsets[i]);
    g.integer("nurbs_knots", c.gcode.nurbs_knots, 0, 1);
    g.number("nurbs_chord_tolerance_mm", c.gcode.nurbs_chord_tolerance_mm, 1e-7, 1.0);
    g.number("max_executed_lines", c.gcode.max_executed_lines, 1.0, 1e12);
    g.string("tool_table", c.gcode.tool_table);
    g.boolean("pause_on_tool_change", c.gcode.pause_on_tool_change);
    g.finish();
    c.gcode.tool_table = resolve_beside(c.gcode.tool_table, origin);
  }
  {
    Section p(top.subtable("process"), "process", origin);
    p.string("shm_name", c.process.shm_name);
    p.string("socket_path", c.process.socket_path);
    p.integer("socket_mode", c.process.socket_mode, 0, 0777);
    p.string("socket_group", c.process.socket_group);
    p.string("state_dir", c.process.state_dir);
    p.number("host_timeout_s", c.process.host_timeout_s, 0.005, 60.0);
    p.number("rt_timeout_s", c.process.rt_timeout_s, 0.005, 60.0);
    p.number("jog_deadman_s", c.process.jog_deadman_s, 0.01, 60.0);
    p.number("client_idle_timeout_s", c.process.client_idle_timeout_s, 0.0, 86400.0);
    p.integer("rt_priority", c.process.rt_priority, 1, 99);
    p.number("rt_spin_us", c.process.rt_spin_us, 0.0, 1e6);
    std::string on_trace_failure = c.process.trace_failure_stops ? "stop" : "continue";
    p.string("on_trace_failure", on_trace_failure);
    if (on_trace_failure != "stop" && on_trace_failure != "continue") {
      p.fail("on_trace_failure", "must be \"stop\" or \"continue\"");
    }
    c.process.trace_failure_stops = on_trace_failure == "stop";
    p.finish();
    if (c.process.shm_name.empty() || c.process.shm_name[0] != '/' ||
        c.process.shm_name.find('/', 1) != std::string::npos || c.process.shm_name.size() > 200) {
      p.fail("shm_name", "must be '/name' with no further '/' (a POSIX shared-memory name)");
    }
    if (!c.process.socket_path.empty() && c.process.socket_path[0] != '/') p.fail("socket_path", "must be an absolute path");
    if (!c.process.state_dir.empty() && c.process.state_dir[0] != '/') p.fail("state_dir", "must be an absolute path");
  }
  top.finish();
  return c;
}

MachineConfig load_config(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw ConfigError("cannot read config file '" + path + "'");
  std::stringstream ss;
  ss << in.rdbuf();
  return parse_config(ss.str(), path);
}

std::string default_config_path() {
  if (const char* env = std::getenv("PCNC_CONFIG"); env && *env) return env;
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    // build/<dir>/pcnc-rt -> ../../configs, build/pcnc-rt -> ../configs, install bin -> ../share/pcnc
    for (fs::path dir = exe.parent_path(); !dir.empty() && dir != dir.root_path(); dir = dir.parent_path()) {
      fs::path candidate = dir / "configs" / "desktop-mill.toml";
      if (fs::exists(candidate, ec)) return candidate.string();
      candidate = dir / "share" / "pcnc" / "configs" / "desktop-mill.toml";
      if (fs::exists(candidate, ec)) return candidate.string();
    }
  }
  return "configs/desktop-mill.toml";
}

}  // namespace pcnc
