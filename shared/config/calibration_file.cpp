// calibration_file.cpp — the measurement calibration file's strict reader and its writer
// (see calibration_file.hpp).
#include "config/calibration_file.hpp"

#include <cmath>
#include <fstream>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "config/atomic_file.hpp"

namespace pcnc {
namespace {

using json = nlohmann::ordered_json;
constexpr const char* kFormat = "pcnc-measure-calibration";
constexpr int kVersion = 1;

[[noreturn]] void refuse(const std::string& origin, const std::string& why) {
  throw CalibrationFileError(origin + ": " + why);
}

// A JSON object whose keys are all known; every read names its key on failure.
class Obj {
 public:
  Obj(const json& v, std::string origin, std::string path) : v_(v), origin_(std::move(origin)), path_(std::move(path)) {
    if (!v_.is_object()) refuse(origin_, where("") + "expected an object");
  }
  const json& get(const std::string& key) {
    used_.insert(key);
    if (!v_.contains(key)) refuse(origin_, where(key) + "missing");
    return v_.at(key);
  }
  double number(const std::string& key) {
    const json& v = get(key);
    if (!v.is_number() || !std::isfinite(v.get<double>())) refuse(origin_, where(key) + "expected a finite number");
    return v.get<double>();
  }
  int integer(const std::string& key, int lo, int hi) {
    const json& v = get(key);
    if (!v.is_number_integer()) refuse(origin_, where(key) + "expected an integer");
    const long long i = v.get<long long>();
    if (i < lo || i > hi) refuse(origin_, where(key) + std::to_string(i) + " is out of range " + std::to_string(lo) + ".." + std::to_string(hi));
    return static_cast<int>(i);
  }
  std::vector<double> numbers(const std::string& key, std::size_t max_count) {
    const json& v = get(key);
    if (!v.is_array() || v.size() > max_count) refuse(origin_, where(key) + "expected an array of at most " + std::to_string(max_count) + " numbers");
    std::vector<double> out;
    for (const json& e : v) {
      if (!e.is_number() || !std::isfinite(e.get<double>())) refuse(origin_, where(key) + "expected finite numbers");
      out.push_back(e.get<double>());
    }
    return out;
  }
  Vec3 vec3(const std::string& key) {
    const std::vector<double> v = numbers(key, 3);
    if (v.size() != 3) refuse(origin_, where(key) + "expected [x, y, z]");
    return {v[0], v[1], v[2]};
  }
  Obj child(const std::string& key) { return Obj(get(key), origin_, path_.empty() ? key : path_ + "." + key); }
  void finish() const {
    for (auto it = v_.begin(); it != v_.end(); ++it)
      if (!used_.count(it.key())) refuse(origin_, where(it.key()) + "unknown key");
  }

 private:
  std::string where(const std::string& key) const {
    const std::string full = path_.empty() ? key : key.empty() ? path_ : path_ + "." + key;
    return full.empty() ? "" : "key '" + full + "': ";
  }
  const json& v_;
  std::string origin_, path_;
  std::set<std::string> used_;
};

json vec(const Vec3& v) { return json::array({v[0], v[1], v[2]}); }

}  // namespace

MeasureCalibration parse_calibration_json(std::string_view text, const std::string& origin) {
  json doc = json::parse(text, nullptr, false);
  if (doc.is_discarded()) refuse(origin, "not valid JSON");
  Obj top(doc, origin, "");
  const json& format = top.get("format");
  if (!format.is_string() || format.get<std::string>() != kFormat)
    refuse(origin, std::string("key 'format': expected \"") + kFormat + "\" (not a calibration file of pcnc measure)");
  top.integer("version", kVersion, kVersion);
  MeasureCalibration c;
  {
    Obj p = top.child("probe");
    c.probe.polar_nodes = p.integer("polar_nodes", 2, kMaxPolarNodes);
    c.probe.polar_max_rad = p.number("polar_max_rad");
    c.probe.harmonics = p.integer("harmonics", 0, kMaxHarmonic);
    const json& rows = p.get("coefficients_mm");
    if (!rows.is_array() || static_cast<int>(rows.size()) != c.probe.polar_nodes)
      refuse(origin, "key 'probe.coefficients_mm': expected one array per polar node");
    for (std::size_t k = 0; k < rows.size(); ++k) {
      if (!rows[k].is_array() || static_cast<int>(rows[k].size()) != 2 * c.probe.harmonics + 1)
        refuse(origin, "key 'probe.coefficients_mm': each node has 2 * harmonics + 1 numbers (A0, A1, B1, ...)");
      for (std::size_t m = 0; m < rows[k].size(); ++m) {
        if (!rows[k][m].is_number() || !std::isfinite(rows[k][m].get<double>()))
          refuse(origin, "key 'probe.coefficients_mm': expected finite numbers");
        c.probe.coeff[k][m] = rows[k][m].get<double>();
      }
    }
    c.probe_touches = p.integer("touches", 0, 1000000);
    c.probe_rms_mm = p.number("residual_rms_mm");
    c.probe_max_mm = p.number("residual_max_mm");
    c.sphere_centre_mm = p.vec3("sphere_centre_mm");
    c.sphere_radius_mm = p.number("sphere_radius_mm");
    p.finish();
    const std::string why = validate(c.probe);
    if (!why.empty()) refuse(origin, "probe: " + why);
  }
  {
    Obj v = top.child("volumetric");
    const json& pitch = v.get("pitch");
    if (!pitch.is_array() || pitch.size() != kAxes) refuse(origin, "key 'volumetric.pitch': expected 3 tables (X, Y, Z)");
    for (int i = 0; i < kAxes; ++i) {
      Obj t(pitch[static_cast<std::size_t>(i)], origin, "volumetric.pitch[" + std::to_string(i) + "]");
      PitchTable& p = c.volumetric.pitch[static_cast<std::size_t>(i)];
      p.start_mm = t.number("start_mm");
      p.step_mm = t.number("step_mm");
      const std::vector<double> e = t.numbers("error_mm", kMaxPitchNodes);
      p.count = static_cast<int>(e.size());
      for (std::size_t k = 0; k < e.size(); ++k) p.error_mm[k] = e[k];
      t.finish();
    }
    c.volumetric.squareness_xy_urad = v.number("squareness_xy_urad");
    c.volumetric.squareness_yz_urad = v.number("squareness_yz_urad");
    c.volumetric.squareness_zx_urad = v.number("squareness_zx_urad");
    c.volumetric.growth_per_K = v.vec3("growth_per_K");
    c.volumetric.temperature_offset_K = v.number("temperature_offset_K");
    c.volumetric.origin_drift_mm = v.vec3("origin_drift_mm");
    c.artefact_lengths = v.integer("lengths", 0, 1000000);
    c.artefact_rms_before_mm = v.number("rms_before_mm");
    c.artefact_rms_after_mm = v.number("rms_after_mm");
    c.artefact_max_before_mm = v.number("max_before_mm");
    c.artefact_max_after_mm = v.number("max_after_mm");
    v.finish();
    const std::string why = validate(c.volumetric);
    if (!why.empty()) refuse(origin, "volumetric: " + why);
  }
  top.finish();
  return c;
}

MeasureCalibration load_calibration_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) refuse(path, "cannot be read");
  std::ostringstream ss;
  ss << in.rdbuf();
  return parse_calibration_json(ss.str(), path);
}

std::string calibration_json(const MeasureCalibration& c) {
  json probe = json::object();
  probe["polar_nodes"] = c.probe.polar_nodes;
  probe["polar_max_rad"] = c.probe.polar_max_rad;
  probe["harmonics"] = c.probe.harmonics;
  json rows = json::array();
  for (int k = 0; k < c.probe.polar_nodes; ++k) {
    json row = json::array();
    for (int m = 0; m < 2 * c.probe.harmonics + 1; ++m) row.push_back(c.probe.coeff[static_cast<std::size_t>(k)][static_cast<std::size_t>(m)]);
    rows.push_back(row);
  }
  probe["coefficients_mm"] = rows;
  probe["touches"] = c.probe_touches;
  probe["residual_rms_mm"] = c.probe_rms_mm;
  probe["residual_max_mm"] = c.probe_max_mm;
  probe["sphere_centre_mm"] = vec(c.sphere_centre_mm);
  probe["sphere_radius_mm"] = c.sphere_radius_mm;
  json vol = json::object();
  json pitch = json::array();
  for (const PitchTable& p : c.volumetric.pitch) {
    json e = json::array();
    for (int k = 0; k < p.count; ++k) e.push_back(p.error_mm[static_cast<std::size_t>(k)]);
    pitch.push_back(json{{"start_mm", p.start_mm}, {"step_mm", p.step_mm}, {"error_mm", e}});
  }
  vol["pitch"] = pitch;
  vol["squareness_xy_urad"] = c.volumetric.squareness_xy_urad;
  vol["squareness_yz_urad"] = c.volumetric.squareness_yz_urad;
  vol["squareness_zx_urad"] = c.volumetric.squareness_zx_urad;
  vol["growth_per_K"] = vec(c.volumetric.growth_per_K);
  vol["temperature_offset_K"] = c.volumetric.temperature_offset_K;
  vol["origin_drift_mm"] = vec(c.volumetric.origin_drift_mm);
  vol["lengths"] = c.artefact_lengths;
  vol["rms_before_mm"] = c.artefact_rms_before_mm;
  vol["rms_after_mm"] = c.artefact_rms_after_mm;
  vol["max_before_mm"] = c.artefact_max_before_mm;
  vol["max_after_mm"] = c.artefact_max_after_mm;
  json doc = json::object();
  doc["format"] = kFormat;
  doc["version"] = kVersion;
  doc["probe"] = probe;
  doc["volumetric"] = vol;
  return doc.dump(2) + "\n";
}

void save_calibration_file(const std::string& path, const MeasureCalibration& c) {
  std::string error;
  if (!write_file_atomically(path, calibration_json(c), &error)) refuse(path, "cannot be written: " + error);
}

}  // namespace pcnc
