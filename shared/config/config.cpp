// config.cpp — TOML loading for MachineConfig: every machine key required, unknown keys refused
// with their line:column, every value range-checked with its unit; all problems reported at once.
#include "config/config.hpp"

#include <unistd.h>

#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <algorithm>
#include <set>
#include <vector>
#include <sstream>
#include <toml++/toml.h>
#include "config/surface_file.hpp"

namespace pcnc {

ConfigError::ConfigError(std::vector<std::string> all)
    : std::runtime_error([&] {
        std::string joined;
        for (const auto& p : all) joined += (joined.empty() ? "" : "\n") + p;
        return joined;
      }()),
      problems(std::move(all)) {}

namespace {

enum class Need { kRequired, kOptional };

std::string position(const std::string& origin, const toml::source_region& where) {
  if (where.begin.line == 0) return origin + ": ";
  return origin + ":" + std::to_string(where.begin.line) + ":" + std::to_string(where.begin.column) + ": ";
}

std::string show(double v) {
  std::ostringstream os;
  os << v;
  return os.str();
}

const char* type_name(const toml::node& n) {
  switch (n.type()) {
    case toml::node_type::string: return "a string";
    case toml::node_type::integer: return "an integer";
    case toml::node_type::floating_point: return "a number";
    case toml::node_type::boolean: return "a boolean";
    case toml::node_type::table: return "a table";
    case toml::node_type::array: return "an array";
    default: return "a date or time";
  }
}

std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diag = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diag = up;
    }
  }
  return row[b.size()];
}

// One TOML table of the config. Each read marks its key as known; a required key that is
// absent, a value of the wrong type or out of its range is noted as a problem (reading goes
// on, so that one run of `pcnc config check` lists every problem); finish() notes the keys
// nobody read (typos) with their line:column, and a section that is missing altogether once.
class Section {
 public:
  Section(const toml::table* table, std::string name, std::string origin, std::vector<std::string>& problems)
      : table_(table), name_(std::move(name)), origin_(std::move(origin)), problems_(problems) {}

  bool number(const char* key, double& out, double lo, double hi, const char* unit, Need need = Need::kRequired) {
    const toml::node* n = find(key, unit, need);
    if (!n) return false;
    const std::optional<double> v = n->is_number() ? n->value<double>() : std::nullopt;
    if (!v) return wrong_type(*n, key, std::string("a number") + with_unit(unit));
    if (!(*v >= lo && *v <= hi)) {
      problems_.push_back(position(origin_, n->source()) + label() + " " + key + " = " + show(*v) + with_space(unit) +
                          ": out of range, must be " + show(lo) + " .. " + show(hi) + with_space(unit));
      return false;
    }
    out = *v;
    return true;
  }
  bool integer(const char* key, int& out, long lo, long hi, const char* what, Need need = Need::kRequired) {
    const toml::node* n = find(key, what, need);
    if (!n) return false;
    if (!n->is_integer()) return wrong_type(*n, key, std::string("an integer") + with_unit(what));
    const int64_t v = *n->value<int64_t>();
    if (v < lo || v > hi) {
      problems_.push_back(position(origin_, n->source()) + label() + " " + key + " = " + std::to_string(v) +
                          ": out of range, must be " + std::to_string(lo) + " .. " + std::to_string(hi) + with_unit(what));
      return false;
    }
    out = static_cast<int>(v);
    return true;
  }
  bool boolean(const char* key, bool& out, Need need = Need::kRequired) {
    const toml::node* n = find(key, "true or false", need);
    if (!n) return false;
    if (!n->is_boolean()) return wrong_type(*n, key, "true or false");
    out = *n->value<bool>();
    return true;
  }
  bool string(const char* key, std::string& out, Need need = Need::kRequired) {
    const toml::node* n = find(key, "a string", need);
    if (!n) return false;
    if (!n->is_string()) return wrong_type(*n, key, "a string");
    out = *n->value<std::string>();
    return true;
  }
  bool vec3(const char* key, Vec3& out, double lo, double hi, const char* unit, Need need = Need::kRequired) {
    std::vector<double> v;
    if (!number_list(key, v, 3, 3, lo, hi, unit, need, "[x, y, z] in mm", "an array of 3 numbers [x, y, z]")) return false;
    out = {v[0], v[1], v[2]};
    return true;
  }
  // An array of numbers, min_count .. max_count of them, each in lo .. hi.
  // `missing_as` and `what` name it in the messages (default: the unit, "an array of N numbers").
  bool number_list(const char* key, std::vector<double>& out, std::size_t min_count, std::size_t max_count, double lo,
                   double hi, const char* unit, Need need = Need::kRequired, const char* missing_as = nullptr,
                   const char* what = nullptr) {
    const toml::node* n = find(key, missing_as ? missing_as : unit, need);
    if (!n) return false;
    const toml::array* a = n->as_array();
    const std::string expected =
        (what ? std::string(what)
              : "an array of " + std::to_string(min_count) +
                    (max_count != min_count ? " to " + std::to_string(max_count) : std::string()) + " numbers") +
        with_unit(unit);
    if (!a || a->size() < min_count || a->size() > max_count) return wrong_type(*n, key, expected);
    std::vector<double> v;
    for (size_t i = 0; i < a->size(); ++i) {
      const std::optional<double> c = (*a)[i].is_number() ? (*a)[i].value<double>() : std::nullopt;
      if (!c) return wrong_type(*n, key, expected);
      if (!(*c >= lo && *c <= hi)) {
        problems_.push_back(position(origin_, (*a)[i].source()) + label() + " " + key + "[" + std::to_string(i) +
                            "] = " + show(*c) + with_space(unit) + ": out of range, must be " + show(lo) + " .. " +
                            show(hi) + with_space(unit));
        return false;
      }
      v.push_back(*c);
    }
    out = std::move(v);
    return true;
  }
  // An array of up to max_count points [x, y, z], each coordinate in lo .. hi.
  bool vec3_list(const char* key, std::vector<Vec3>& out, std::size_t max_count, double lo, double hi,
                 Need need = Need::kRequired) {
    const toml::node* n = find(key, "[[x, y, z], ...] in mm", need);
    if (!n) return false;
    const toml::array* a = n->as_array();
    const std::string expected = "an array of 1 to " + std::to_string(max_count) + " points [x, y, z] (mm)";
    if (!a || a->empty() || a->size() > max_count) return wrong_type(*n, key, expected);
    std::vector<Vec3> v;
    for (size_t i = 0; i < a->size(); ++i) {
      const toml::array* p = (*a)[i].as_array();
      if (!p || p->size() != 3) return wrong_type(*n, key, expected);
      Vec3 q{};
      for (size_t k = 0; k < 3; ++k) {
        const std::optional<double> c = (*p)[k].is_number() ? (*p)[k].value<double>() : std::nullopt;
        if (!c || !(*c >= lo && *c <= hi)) {
          problems_.push_back(position(origin_, (*p)[k].source()) + label() + " " + key + "[" + std::to_string(i) +
                              "][" + std::to_string(k) + "]: expected a number in " + show(lo) + " .. " + show(hi) +
                              " mm");
          return false;
        }
        q[k] = *c;
      }
      v.push_back(q);
    }
    out = std::move(v);
    return true;
  }
  // A key that was renamed: refused with a message naming the new one.
  void renamed(const char* old_key, const char* new_key) {
    used_.insert(old_key);
    const toml::node* n = table_ ? table_->get(old_key) : nullptr;
    if (!n) return;
    problems_.push_back(position(origin_, n->source()) + label() + " " + old_key + ": renamed to " + new_key +
                        " (the one path tolerance: merging, smoothing and the corner speed); rename the key");
  }
  // A sub-table (`[axis.x]` in `[axis]`); nullptr when absent (its own Section reports that).
  const toml::table* subtable(const char* key) {
    used_.insert(key);
    if (!table_) return nullptr;
    const toml::node* n = table_->get(key);
    if (!n) return nullptr;
    if (!n->is_table()) {
      wrong_type(*n, key, "a table [" + child(key) + "]");
      return nullptr;
    }
    return n->as_table();
  }
  std::string child(const char* key) const { return name_.empty() ? key : name_ + "." + key; }
  const std::string& origin() const { return origin_; }

  // A problem with a value that was read (a rule between keys, a name's form): at that key's
  // value, or at the section's header.
  void problem(const std::string& why, const char* at_key = nullptr) {
    const toml::node* n = table_ && at_key ? table_->get(at_key) : nullptr;
    const toml::source_region where = n ? n->source() : table_ ? table_->source() : toml::source_region{};
    problems_.push_back(position(origin_, where) + label() + ": " + why);
  }

  void finish() {
    if (!table_) {
      if (!missing_.empty()) {
        std::string keys;
        for (const auto& [k, unit] : missing_) keys += (keys.empty() ? "" : ", ") + k;
        problems_.push_back(origin_ + ": missing section " + label() + ": it must set " + std::to_string(missing_.size()) +
                            " key" + (missing_.size() == 1 ? "" : "s") + ": " + keys);
      }
      return;
    }
    for (const auto& [k, unit] : missing_) {
      // at the section's header; a top-level key has none
      const std::string where = name_.empty() ? origin_ + ": " : position(origin_, table_->source());
      problems_.push_back(where + label() + ": missing key '" + k + "'" + unit);
    }
    for (auto&& [k, v] : *table_) {
      const std::string key(k.str());
      if (used_.count(key)) continue;
      std::string msg = position(origin_, k.source()) + label() + ": unknown " +
                        (v.is_table() ? "section [" + child(key.c_str()) + "]" : "key '" + key + "'");
      std::string best;  // the nearest known key, a missing one first
      std::size_t best_d = std::min<std::size_t>(4, key.size() / 2 + 1);
      auto consider = [&](const std::string& known) {
        const std::size_t d = edit_distance(key, known);
        if (d < best_d) best_d = d, best = known;
      };
      for (const auto& [k, unit] : missing_) consider(k);
      for (const auto& k : used_) consider(k);
      if (!best.empty()) msg += " (did you mean '" + best + "'?)";
      problems_.push_back(msg);
    }
  }

 private:
  static std::string with_unit(const char* unit) { return unit && *unit ? std::string(" (") + unit + ")" : ""; }
  static std::string with_space(const char* unit) { return unit && *unit ? std::string(" ") + unit : ""; }
  std::string label() const { return name_.empty() ? "(top level)" : "[" + name_ + "]"; }

  const toml::node* find(const char* key, const char* unit, Need need) {
    used_.insert(key);
    const toml::node* n = table_ ? table_->get(key) : nullptr;
    if (!n && need == Need::kRequired) missing_.emplace_back(key, with_unit(unit));
    return n;
  }
  bool wrong_type(const toml::node& n, const char* key, const std::string& expected) {
    problems_.push_back(position(origin_, n.source()) + label() + " " + key + ": expected " + expected + ", not " +
                        type_name(n));
    return false;
  }

  const toml::table* table_;
  std::string name_;
  std::string origin_;
  std::vector<std::string>& problems_;
  std::set<std::string> used_;
  std::vector<std::pair<std::string, std::string>> missing_;  // required keys absent: name, " (unit)"
};

void read_axis(Section& parent, const char* key, AxisConfig& a, std::vector<std::string>& problems) {
  Section s(parent.subtable(key), parent.child(key), parent.origin(), problems);
  const bool min_ok = s.number("travel_min_mm", a.travel_min_mm, -1e4, 1e4, "mm");
  const bool max_ok = s.number("travel_max_mm", a.travel_max_mm, -1e4, 1e4, "mm");
  const bool home_ok = s.number("home_mm", a.home_mm, -1e4, 1e4, "mm");
  s.number("max_velocity_mm_s", a.max_velocity_mm_s, 1e-3, 1e5, "mm/s");
  s.number("max_accel_mm_s2", a.max_accel_mm_s2, 1e-3, 1e7, "mm/s^2");
  s.number("following_error_limit_mm", a.following_error_limit_mm, 1e-6, 1e3, "mm");
  s.number("moving_mass_kg", a.moving_mass_kg, 1e-4, 1e4, "kg");
  s.number("force_constant_n_per_a", a.force_constant_n_per_a, 1e-4, 1e5, "N/A");
  s.number("current_limit_a", a.current_limit_a, 1e-4, 1e4, "A");
  s.number("viscous_friction_n_s_per_m", a.viscous_friction_n_s_per_m, 0.0, 1e6, "N s/m");
  s.number("coulomb_friction_n", a.coulomb_friction_n, 0.0, 1e5, "N");
  s.number("gravity_load_n", a.gravity_load_n, -1e5, 1e5, "N");
  s.number("encoder_resolution_mm", a.encoder_resolution_mm, 0.0, 1.0, "mm");
  s.number("kp_a_per_mm", a.kp_a_per_mm, 0.0, 1e9, "A/mm");
  s.number("ki_a_per_mm_s", a.ki_a_per_mm_s, 0.0, 1e12, "A/(mm s)");
  s.number("kd_a_s_per_mm", a.kd_a_s_per_mm, 0.0, 1e6, "A s/mm");
  s.number("derivative_filter_hz", a.derivative_filter_hz, 1.0, 1e6, "Hz");
  s.number("velocity_ff_a_s_per_mm", a.velocity_ff_a_s_per_mm, 0.0, 1e6, "A s/mm");
  s.number("accel_ff_a_s2_per_mm", a.accel_ff_a_s2_per_mm, 0.0, 1e6, "A s^2/mm");
  s.number("friction_ff_a", a.friction_ff_a, 0.0, 1e4, "A");
  s.number("integrator_limit_a", a.integrator_limit_a, 0.0, 1e4, "A");
  if (min_ok && max_ok && !(a.travel_max_mm > a.travel_min_mm)) {
    s.problem("travel_max_mm (" + show(a.travel_max_mm) + " mm) must exceed travel_min_mm (" + show(a.travel_min_mm) +
              " mm)",
              "travel_max_mm");
  } else if (min_ok && max_ok && home_ok && !(a.home_mm >= a.travel_min_mm && a.home_mm <= a.travel_max_mm)) {
    s.problem("home_mm (" + show(a.home_mm) + " mm) must lie within the travel, " + show(a.travel_min_mm) + " .. " +
              show(a.travel_max_mm) + " mm",
              "home_mm");
  }
  s.finish();
}

// [axis.a], [axis.b], [axis.c]: a rotary joint, in degrees in the file and radians in `out`
// (rotary_config.hpp). Read only when the section is there (a 3-axis machine has none).
// `continuous = true` replaces the travel (its keys are then refused).
void read_rotary_axis(Section& parent, const char* key, std::optional<RotaryAxisConfig>& out,
                      std::vector<std::string>& problems) {
  const toml::table* table = parent.subtable(key);
  if (!table) return;
  Section s(table, parent.child(key), parent.origin(), problems);
  RotaryAxisConfig a;
  a.letter = static_cast<char>(key[0] - 'a' + 'A');
  double min_deg = 0.0, max_deg = 0.0, home_deg = 0.0, v = 0.0, acc = 0.0, ferr = 0.0, res = 0.0;
  double kp = 0.0, ki = 0.0, kd = 0.0, kvff = 0.0, kaff = 0.0;
  s.boolean("continuous", a.continuous, Need::kOptional);
  const Need travel = a.continuous ? Need::kOptional : Need::kRequired;
  const bool min_ok = s.number("travel_min_deg", min_deg, -1e5, 1e5, "deg", travel);
  const bool max_ok = s.number("travel_max_deg", max_deg, -1e5, 1e5, "deg", travel);
  const bool home_ok = s.number("home_deg", home_deg, -1e5, 1e5, "deg");
  s.number("max_velocity_deg_s", v, 1e-3, 1e6, "deg/s");
  s.number("max_accel_deg_s2", acc, 1e-3, 1e8, "deg/s^2");
  s.number("following_error_limit_deg", ferr, 1e-6, 360.0, "deg");
  s.number("inertia_kg_m2", a.inertia_kg_m2, 1e-9, 1e3, "kg m^2");
  s.number("torque_constant_nm_per_a", a.torque_constant_nm_per_a, 1e-4, 1e4, "N m/A");
  s.number("current_limit_a", a.current_limit_a, 1e-4, 1e4, "A");
  s.number("viscous_friction_nm_s_per_rad", a.viscous_friction_nm_s_per_rad, 0.0, 1e4, "N m s/rad");
  s.number("coulomb_friction_nm", a.coulomb_friction_nm, 0.0, 1e4, "N m");
  s.number("encoder_resolution_deg", res, 0.0, 1.0, "deg");
  s.number("kp_a_per_deg", kp, 0.0, 1e9, "A/deg");
  s.number("ki_a_per_deg_s", ki, 0.0, 1e12, "A/(deg s)");
  s.number("kd_a_s_per_deg", kd, 0.0, 1e6, "A s/deg");
  s.number("derivative_filter_hz", a.derivative_filter_hz, 1.0, 1e6, "Hz");
  s.number("velocity_ff_a_s_per_deg", kvff, 0.0, 1e6, "A s/deg");
  s.number("accel_ff_a_s2_per_deg", kaff, 0.0, 1e6, "A s^2/deg");
  s.number("friction_ff_a", a.friction_ff_a, 0.0, 1e4, "A");
  s.number("integrator_limit_a", a.integrator_limit_a, 0.0, 1e4, "A");
  if (a.continuous && (min_ok || max_ok)) {
    s.problem("a continuous axis has no travel limits; expected either continuous = true or travel_min_deg and "
              "travel_max_deg",
              min_ok ? "travel_min_deg" : "travel_max_deg");
  } else if (!a.continuous && min_ok && max_ok && !(max_deg > min_deg)) {
    s.problem("travel_max_deg (" + show(max_deg) + " deg) must exceed travel_min_deg (" + show(min_deg) + " deg)",
              "travel_max_deg");
  } else if (!a.continuous && min_ok && max_ok && home_ok && !(home_deg >= min_deg && home_deg <= max_deg)) {
    s.problem("home_deg (" + show(home_deg) + " deg) must lie within the travel, " + show(min_deg) + " .. " +
                  show(max_deg) + " deg",
              "home_deg");
  }
  s.finish();
  // degrees at the edge, radians inside; gains per degree become gains per radian
  a.travel_min_rad = min_deg * kRadPerDeg;
  a.travel_max_rad = max_deg * kRadPerDeg;
  a.home_rad = home_deg * kRadPerDeg;
  a.max_velocity_rad_s = v * kRadPerDeg;
  a.max_accel_rad_s2 = acc * kRadPerDeg;
  a.following_error_limit_rad = ferr * kRadPerDeg;
  a.encoder_resolution_rad = res * kRadPerDeg;
  a.kp_a_per_rad = kp * kDegPerRad;
  a.ki_a_per_rad_s = ki * kDegPerRad;
  a.kd_a_s_per_rad = kd * kDegPerRad;
  a.velocity_ff_a_s_per_rad = kvff * kDegPerRad;
  a.accel_ff_a_s2_per_rad = kaff * kDegPerRad;
  out = a;
}

// [kinematics], optional (absent: trivial): kind and the pivots of geometry/kinematics.hpp, and
// the rotary joints that kind needs, none more.
void read_kinematics(Section& top, MachineConfig& c, std::vector<std::string>& problems) {
  Section k(top.subtable("kinematics"), "kinematics", top.origin(), problems);
  std::string kind = "trivial";
  const bool have_kind = k.string("kind", kind, Need::kOptional);
  const bool trivial = kind == "trivial";
  const Need pivots = trivial ? Need::kOptional : Need::kRequired;
  const bool tilt = k.vec3("tilt_pivot_mm", c.kinematics.tilt_pivot, -1e4, 1e4, "mm", pivots);
  const bool rot = k.vec3("rotary_pivot_mm", c.kinematics.rotary_pivot, -1e4, 1e4, "mm", pivots);
  const char* needs = "";  // the rotary joints the kind uses: tilt, then C
  if (kind == "xyzac-trt") {
    c.kinematics.kind = KinematicsKind::kTableTable;
    needs = "ac";
  } else if (kind == "xyzbc-head-table") {
    c.kinematics.kind = KinematicsKind::kHeadTable;
    needs = "bc";
  } else if (!trivial) {
    k.problem("kind '" + kind + "' is not a kinematics pcnc has; expected \"trivial\", \"xyzac-trt\" or "
              "\"xyzbc-head-table\"",
              "kind");
  } else if (tilt || rot) {
    k.problem("the trivial kinematics has no pivots; expected no tilt_pivot_mm or rotary_pivot_mm", tilt ? "tilt_pivot_mm" : "rotary_pivot_mm");
  }
  k.finish();
  if (!trivial && !(kind == "xyzac-trt" || kind == "xyzbc-head-table")) return;
  const std::string label = have_kind ? "[kinematics] kind = \"" + kind + "\"" : std::string("the trivial kinematics (no [kinematics] kind)");
  for (int i = 0; i < kRotaryAxes; ++i) {
    const char letter = static_cast<char>('a' + i);
    const bool used = std::string(needs).find(letter) != std::string::npos;
    const bool there = c.rotary[static_cast<std::size_t>(i)].has_value();
    if (used && !there) {
      problems.push_back(top.origin() + ": missing section [axis." + letter + "]: " + label + " needs it");
    } else if (!used && there) {
      problems.push_back(top.origin() + ": [axis." + letter + "] is not a joint of " + label +
                         "; expected it removed, or a [kinematics] kind that uses it");
    }
  }
}

// A path named in the config: relative ones are relative to the config file's directory
// (not the working directory of whichever process reads it).
std::string resolve_beside(const std::string& path, const std::string& config_origin) {
  if (path.empty() || path.front() == '/') return path;
  const std::filesystem::path dir = std::filesystem::path(config_origin).parent_path();
  return dir.empty() ? path : (dir / path).lexically_normal().string();
}

// [probe] and [workpiece] (docs/probe.md): both optional sections, every key in them required
// except the bump's and the reference objects'.
void read_probe(Section& top, MachineConfig& c, std::vector<std::string>& problems) {
  {
    const toml::table* t = top.subtable("probe");
    Section p(t, "probe", top.origin(), problems);
    c.probe.present = t != nullptr;
    if (t) {
      ProbeModel& m = c.probe.model;
      const bool r_ok = p.number("ball_radius_mm", m.ball_radius_mm, 0.01, 25.0, "mm");
      const bool ax_ok = p.number("pretravel_axial_mm", m.pretravel_axial_mm, 0.0, 0.5, "mm");
      const bool lat_ok = p.number("pretravel_lateral_mm", m.pretravel_lateral_mm, 0.0, 0.5, "mm");
      const bool lobe_ok = p.number("pretravel_lobe_mm", m.pretravel_lobe_mm, 0.0, 0.5, "mm");
      p.number("repeatability_mm", m.repeatability_mm, 0.0, 0.1, "mm");
      int seed = 1;
      if (p.integer("seed", seed, 0, 2147483647L, "of the repeatability noise")) m.seed = static_cast<std::uint64_t>(seed);
      p.number("overtravel_mm", m.overtravel_mm, 0.01, 25.0, "mm");
      if (lat_ok && lobe_ok && m.pretravel_lobe_mm > m.pretravel_lateral_mm) {
        p.problem("pretravel_lobe_mm (" + show(m.pretravel_lobe_mm) + " mm) must not exceed pretravel_lateral_mm (" +
                      show(m.pretravel_lateral_mm) + " mm): the pre-travel would turn negative",
                  "pretravel_lobe_mm");
      }
      if (r_ok && ax_ok && lat_ok && lobe_ok &&
          std::max(m.pretravel_axial_mm, m.pretravel_lateral_mm + m.pretravel_lobe_mm) >= m.ball_radius_mm) {
        p.problem("the pre-travel must stay below the ball radius", "ball_radius_mm");
      }
      p.finish();
    }
  }
  const toml::table* t = top.subtable("workpiece");
  if (!t) return;
  Section w(t, "workpiece", top.origin(), problems);
  TableScene& s = c.table;
  std::string surface = "plane";
  if (w.string("surface", surface)) {
    if (surface != "plane" && surface != "bump" && surface != "bspline" && surface != "none") {
      w.problem("surface '" + surface + "' must be \"plane\", \"bump\", \"bspline\" or \"none\"", "surface");
    }
  }
  s.has_surface = surface != "none";
  const Need surf = s.has_surface && surface != "bspline" ? Need::kRequired : Need::kOptional;
  std::string surface_path;
  if (w.string("surface_file", surface_path, surface == "bspline" ? Need::kRequired : Need::kOptional)) {
    if (surface != "bspline") {
      w.problem("surface_file is read only with surface = \"bspline\"", "surface_file");
    } else {
      try {
        s.bspline = std::make_shared<const BSplineSurface>(load_surface_file(resolve_beside(surface_path, top.origin())));
      } catch (const std::exception& e) {
        w.problem(std::string("surface_file: ") + e.what(), "surface_file");
      }
    }
  }
  // the machining error (the seed's eq. 16) added to the top
  int error_seed = 0, error_cells = 8;
  double error_rms = 0.0;
  const bool has_error = w.integer("error_seed", error_seed, 0, 2147483647L, "of the Wiener error", Need::kOptional);
  const Need err = has_error ? Need::kRequired : Need::kOptional;
  w.number("error_rms_mm", error_rms, 0.0, 1.0, "mm", err);
  w.integer("error_cells", error_cells, 1, 64, "lattice cells per side", Need::kOptional);
  std::vector<double> ex{c.axes[0].travel_min_mm, c.axes[0].travel_max_mm},
      ey{c.axes[1].travel_min_mm, c.axes[1].travel_max_mm};
  w.number_list("error_x_mm", ex, 2, 2, -1e4, 1e4, "mm", Need::kOptional);
  w.number_list("error_y_mm", ey, 2, 2, -1e4, 1e4, "mm", Need::kOptional);
  if (has_error) {
    if (!(ex[1] > ex[0]) || !(ey[1] > ey[0])) {
      w.problem("error_x_mm and error_y_mm must each be [low, high] with high > low", "error_x_mm");
    } else if (error_rms > 0.0) {
      s.error = std::make_shared<const WienerSurface>(static_cast<std::uint64_t>(error_seed), error_cells, error_rms);
      s.error_x0_mm = ex[0], s.error_x1_mm = ex[1], s.error_y0_mm = ey[0], s.error_y1_mm = ey[1];
    }
  }
  std::vector<Vec3> balls;
  if (w.vec3_list("artefact_balls_mm", balls, TableScene::kMaxArtefactBalls, -1e4, 1e4, Need::kOptional)) {
    s.artefact_balls = static_cast<int>(balls.size());
    for (std::size_t i = 0; i < balls.size(); ++i) s.artefact_centres[i] = balls[i];
    w.number("artefact_ball_radius_mm", s.artefact_ball_radius_mm, 0.01, 1e3, "mm");
  } else {
    w.number("artefact_ball_radius_mm", s.artefact_ball_radius_mm, 0.01, 1e3, "mm", Need::kOptional);
  }
  w.number("z_mm", s.z_mm, -1e4, 1e4, "mm", surf);
  w.number("slope_x", s.slope_x, -10.0, 10.0, "dz/dx", Need::kOptional);
  w.number("slope_y", s.slope_y, -10.0, 10.0, "dz/dy", Need::kOptional);
  const Need bump = surface == "bump" ? Need::kRequired : Need::kOptional;
  w.number("bump_x_mm", s.bump_x_mm, -1e4, 1e4, "mm", bump);
  w.number("bump_y_mm", s.bump_y_mm, -1e4, 1e4, "mm", bump);
  w.number("bump_height_mm", s.bump_height_mm, -100.0, 100.0, "mm", bump);
  w.number("bump_sigma_mm", s.bump_sigma_mm, 0.01, 1e4, "mm", bump);
  if (surface != "bump") s.bump_height_mm = 0.0;
  w.vec3("sphere_center_mm", s.sphere_center, -1e4, 1e4, "mm", Need::kOptional);
  w.number("sphere_radius_mm", s.sphere_radius_mm, 0.0, 1e3, "mm", Need::kOptional);
  const bool lo = w.vec3("gauge_min_mm", s.gauge_min, -1e4, 1e4, "mm", Need::kOptional);
  const bool hi = w.vec3("gauge_max_mm", s.gauge_max, -1e4, 1e4, "mm", Need::kOptional);
  if (lo != hi) {
    w.problem("gauge_min_mm and gauge_max_mm go together (the gauge block's opposite corners)",
              lo ? "gauge_min_mm" : "gauge_max_mm");
  } else if (lo) {
    s.has_gauge = true;
    for (int i = 0; i < kAxes; ++i) {
      if (!(s.gauge_max[i] > s.gauge_min[i])) {
        w.problem("gauge_max_mm must exceed gauge_min_mm on every axis", "gauge_max_mm");
        break;
      }
    }
  }
  w.finish();
}

// [machine_error] (docs/measurement.md): the volumetric error the simulated encoders do not
// see; optional, every key in it optional (absent: zero).
void read_machine_error(Section& top, MachineConfig& c, std::vector<std::string>& problems) {
  const toml::table* t = top.subtable("machine_error");
  if (!t) return;
  Section m(t, "machine_error", top.origin(), problems);
  VolumetricError& e = c.machine_error;
  const char* names[kAxes][3] = {{"pitch_x_mm", "pitch_x_start_mm", "pitch_x_step_mm"},
                                 {"pitch_y_mm", "pitch_y_start_mm", "pitch_y_step_mm"},
                                 {"pitch_z_mm", "pitch_z_start_mm", "pitch_z_step_mm"}};
  for (int i = 0; i < kAxes; ++i) {
    std::vector<double> table;
    const bool has = m.number_list(names[i][0], table, 1, kMaxPitchNodes, -1.0, 1.0, "mm", Need::kOptional);
    const Need need = has ? Need::kRequired : Need::kOptional;
    PitchTable& p = e.pitch[static_cast<std::size_t>(i)];
    m.number(names[i][1], p.start_mm, -1e4, 1e4, "mm", need);
    m.number(names[i][2], p.step_mm, 1e-3, 1e4, "mm", need);
    if (has) {
      p.count = static_cast<int>(table.size());
      for (std::size_t k = 0; k < table.size(); ++k) p.error_mm[k] = table[k];
    }
  }
  m.number("squareness_xy_urad", e.squareness_xy_urad, -9999.0, 9999.0, "µrad", Need::kOptional);
  m.number("squareness_yz_urad", e.squareness_yz_urad, -9999.0, 9999.0, "µrad", Need::kOptional);
  m.number("squareness_zx_urad", e.squareness_zx_urad, -9999.0, 9999.0, "µrad", Need::kOptional);
  m.vec3("growth_per_K", e.growth_per_K, -1e-3, 1e-3, "1/K", Need::kOptional);
  m.number("temperature_offset_K", e.temperature_offset_K, -100.0, 100.0, "K", Need::kOptional);
  m.vec3("origin_drift_mm", e.origin_drift_mm, -1.0, 1.0, "mm", Need::kOptional);
  const std::string why = validate(e);
  if (!why.empty()) m.problem(why);
  c.has_machine_error = true;
  m.finish();
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
  std::vector<std::string> problems;
  Section top(&root, "", origin, problems);
  if (top.string("name", c.name) &&
      (c.name.empty() || c.name == "." || c.name == ".." || c.name.find('/') != std::string::npos)) {
    top.problem("name '" + c.name + "' must name a directory (the machine's runtime and state directories): not empty, "
                "'.' or '..', no '/'",
                "name");
  }

  {
    Section axes(top.subtable("axis"), "axis", origin, problems);
    read_axis(axes, "x", c.axes[0], problems);
    read_axis(axes, "y", c.axes[1], problems);
    read_axis(axes, "z", c.axes[2], problems);
    read_rotary_axis(axes, "a", c.rotary[0], problems);
    read_rotary_axis(axes, "b", c.rotary[1], problems);
    read_rotary_axis(axes, "c", c.rotary[2], problems);
    axes.finish();
  }
  read_kinematics(top, c, problems);
  {
    Section m(top.subtable("motion"), "motion", origin, problems);
    m.number("cycle_hz", c.motion.cycle_hz, 100.0, 100000.0, "Hz");
    m.number("contouring_angle_deg", c.motion.contouring_angle_deg, 0.0, 90.0, "deg");
    m.boolean("contouring_default", c.motion.contouring_default);
    m.number("junction_velocity_step_fraction", c.motion.junction_velocity_step_fraction, 0.0, 100.0,
             "of a_max x period");
    m.number("path_tolerance_mm", c.motion.path_tolerance_mm, 0.0, 1.0, "mm", Need::kOptional);
    m.number("smoothing_angle_deg", c.motion.smoothing_angle_deg, 0.0, 180.0, "deg", Need::kOptional);
    m.renamed("corner_tolerance_mm", "path_tolerance_mm");
    m.number("rapid_speed_mm_s", c.motion.rapid_speed_mm_s, 0.0, 1e5, "mm/s", Need::kOptional);
    m.number("jog_accel_fraction", c.motion.jog_accel_fraction, 0.01, 1.0, "of max_accel_mm_s2");
    m.number("subsample_steps", c.motion.subsample_steps, 1.0, 1000.0, "per cycle");
    m.number("block_tolerance_mm", c.motion.block_tolerance_mm, 1e-9, 1.0, "mm");
    m.finish();
  }
  {
    Section g(top.subtable("gcode"), "gcode", origin, problems);
    g.number("arc_radius_tolerance_mm", c.gcode.arc_radius_tolerance_mm, 0.0, 10.0, "mm");
    g.number("arc_radius_tolerance_rel", c.gcode.arc_radius_tolerance_rel, 0.0, 1.0, "of the radius");
    g.boolean("clamp_excess_feed", c.gcode.clamp_excess_feed);
    g.number("max_feed_mm_min", c.gcode.max_feed_mm_min, 0.0, 1e7, "mm/min", Need::kOptional);
    static const char* names[6] = {"g54", "g55", "g56", "g57", "g58", "g59"};
    for (int i = 0; i < 6; ++i) {
      g.vec3(names[i], c.gcode.work_offsets[i], -1e4, 1e4, "mm", i == 0 ? Need::kRequired : Need::kOptional);
    }
    g.integer("nurbs_knots", c.gcode.nurbs_knots, 0, 1, "0 open uniform, 1 chord length", Need::kOptional);
    g.number("nurbs_chord_tolerance_mm", c.gcode.nurbs_chord_tolerance_mm, 1e-7, 1.0, "mm", Need::kOptional);
    g.number("surface_tolerance_mm", c.gcode.surface_tolerance_mm, 1e-6, 1.0, "mm", Need::kOptional);
    g.number("max_executed_lines", c.gcode.max_executed_lines, 1.0, 1e12, "lines", Need::kOptional);
    g.string("tool_table", c.gcode.tool_table, Need::kOptional);
    g.string("surface", c.gcode.surface, Need::kOptional);
    g.boolean("pause_on_tool_change", c.gcode.pause_on_tool_change, Need::kOptional);
    g.finish();
    c.gcode.tool_table = resolve_beside(c.gcode.tool_table, origin);
    c.gcode.surface = resolve_beside(c.gcode.surface, origin);
  }
  {
    Section k(top.subtable("cutter_comp"), "cutter_comp", origin, problems);
    k.boolean("gouge_check", c.cutter_comp.gouge_check, Need::kOptional);
    k.number("fit_segment_max_mm", c.cutter_comp.fit_segment_max_mm, 1e-6, 100.0, "mm", Need::kOptional);
    k.number("fit_tolerance_mm", c.cutter_comp.fit_tolerance_mm, 1e-7, 1.0, "mm", Need::kOptional);
    k.finish();
  }
  {
    Section p(top.subtable("process"), "process", origin, problems);
    if (p.string("shm_name", c.process.shm_name) &&
        (c.process.shm_name.empty() || c.process.shm_name[0] != '/' ||
         c.process.shm_name.find('/', 1) != std::string::npos || c.process.shm_name.size() > 200)) {
      p.problem("shm_name '" + c.process.shm_name + "' must be '/name' with no further '/' (a POSIX shared-memory name)", "shm_name");
    }
    if (p.string("socket_path", c.process.socket_path, Need::kOptional) && !c.process.socket_path.empty() &&
        c.process.socket_path[0] != '/') {
      p.problem("socket_path '" + c.process.socket_path + "' must be an absolute path", "socket_path");
    }
    p.integer("socket_mode", c.process.socket_mode, 0, 0777, "file mode, e.g. 0o600", Need::kOptional);
    p.string("socket_group", c.process.socket_group, Need::kOptional);
    if (p.string("state_dir", c.process.state_dir, Need::kOptional) && !c.process.state_dir.empty() &&
        c.process.state_dir[0] != '/') {
      p.problem("state_dir '" + c.process.state_dir + "' must be an absolute path", "state_dir");
    }
    p.number("host_timeout_s", c.process.host_timeout_s, 0.005, 60.0, "s");
    p.number("rt_timeout_s", c.process.rt_timeout_s, 0.005, 60.0, "s");
    p.number("jog_deadman_s", c.process.jog_deadman_s, 0.01, 60.0, "s");
    p.number("client_idle_timeout_s", c.process.client_idle_timeout_s, 0.0, 86400.0, "s", Need::kOptional);
    p.integer("rt_priority", c.process.rt_priority, 1, 99, "SCHED_FIFO priority", Need::kOptional);
    p.number("rt_spin_us", c.process.rt_spin_us, 0.0, 1e6, "us", Need::kOptional);
    std::string on_trace_failure = c.process.trace_failure_stops ? "stop" : "continue";
    if (p.string("on_trace_failure", on_trace_failure, Need::kOptional)) {
      if (on_trace_failure != "stop" && on_trace_failure != "continue") {
        p.problem("on_trace_failure '" + on_trace_failure + "' must be \"stop\" or \"continue\"", "on_trace_failure");
      }
      c.process.trace_failure_stops = on_trace_failure != "continue";
    }
    p.finish();
  }
  read_probe(top, c, problems);
  read_machine_error(top, c, problems);
  top.finish();
  if (!problems.empty()) {
    // in the file's order: the file-wide ones (a missing section or top-level key) first
    auto line_of = [&](const std::string& p) {
      const std::size_t at = origin.size() + 1;
      if (p.compare(0, origin.size(), origin) != 0 || p.size() <= at || !std::isdigit(static_cast<unsigned char>(p[at]))) {
        return 0L;
      }
      return std::strtol(p.c_str() + at, nullptr, 10);
    };
    std::stable_sort(problems.begin(), problems.end(),
                     [&](const std::string& a, const std::string& b) { return line_of(a) < line_of(b); });
    throw ConfigError(std::move(problems));
  }
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
