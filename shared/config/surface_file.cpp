// surface_file.cpp — the surface file's strict reader and its writer (see surface_file.hpp).
#include "config/surface_file.hpp"

#include <cmath>
#include <fstream>
#include <set>
#include <sstream>
#include <sys/stat.h>

#include <nlohmann/json.hpp>

#include "config/atomic_file.hpp"

namespace pcnc {
namespace {

using json = nlohmann::ordered_json;
constexpr const char* kSurfaceFormat = "pcnc-bspline-surface";
constexpr std::uintmax_t kMaxFileBytes = 64u << 20;

[[noreturn]] void refuse_surface(const std::string& origin, const std::string& why) {
  throw SurfaceFileError(origin + ": " + why);
}

double number(const json& v, const std::string& origin, const std::string& key) {
  if (!v.is_number()) refuse_surface(origin, "key '" + key + "': expected a number, got " + v.dump());
  const double d = v.get<double>();
  if (!std::isfinite(d)) refuse_surface(origin, "key '" + key + "': not a finite number");
  return d;
}

int integer(const json& v, const std::string& origin, const std::string& key) {
  if (!v.is_number_integer()) refuse_surface(origin, "key '" + key + "': expected an integer, got " + v.dump());
  const long long i = v.get<long long>();
  if (i < -1000000 || i > 1000000) refuse_surface(origin, "key '" + key + "': " + std::to_string(i) + " is out of range");
  return static_cast<int>(i);
}

std::vector<double> numbers(const json& v, const std::string& origin, const std::string& key) {
  if (!v.is_array()) refuse_surface(origin, "key '" + key + "': expected an array of numbers");
  std::vector<double> out;
  out.reserve(v.size());
  for (std::size_t i = 0; i < v.size(); ++i) out.push_back(number(v[i], origin, key + "[" + std::to_string(i) + "]"));
  return out;
}

}  // namespace

BSplineSurface parse_surface_json(std::string_view text, const std::string& origin) {
  json doc;
  try {
    doc = json::parse(text);
  } catch (const json::exception& e) {
    refuse_surface(origin, std::string("not valid JSON: ") + e.what());
  }
  if (!doc.is_object()) refuse_surface(origin, "expected a JSON object");
  const std::set<std::string> expected = {"format", "version", "units", "degree", "e", "knots_u", "knots_v",
                                          "control_points"};
  for (const auto& [key, value] : doc.items())
    if (!expected.count(key)) refuse_surface(origin, "unknown key '" + key + "'");
  for (const auto& key : expected)
    if (!doc.contains(key)) refuse_surface(origin, "missing key '" + key + "'");
  if (doc["format"] != kSurfaceFormat) refuse_surface(origin, std::string("key 'format' must be \"") + kSurfaceFormat + "\"");
  if (integer(doc["version"], origin, "version") != kSurfaceFileVersion)
    refuse_surface(origin, "key 'version' is " + doc["version"].dump() + "; this pcnc reads version " +
                       std::to_string(kSurfaceFileVersion));
  if (doc["units"] != "mm") refuse_surface(origin, "key 'units' must be \"mm\"");
  BSplineSurface s;
  s.degree = integer(doc["degree"], origin, "degree");
  if (s.degree < 1 || s.degree > kMaxSurfaceDegree)
    refuse_surface(origin, "key 'degree': " + std::to_string(s.degree) + " is outside 1.." + std::to_string(kMaxSurfaceDegree));
  s.e = number(doc["e"], origin, "e");
  if (s.e < 0.0 || s.e > 1.0) refuse_surface(origin, "key 'e': must lie in [0, 1]");
  s.knots_u = numbers(doc["knots_u"], origin, "knots_u");
  s.knots_v = numbers(doc["knots_v"], origin, "knots_v");
  const json& grid = doc["control_points"];
  if (!grid.is_array() || grid.empty() || !grid[0].is_array() || grid[0].empty())
    refuse_surface(origin, "key 'control_points': expected rows of [x, y, z] points");
  s.count_v = static_cast<int>(grid.size());
  s.count_u = static_cast<int>(grid[0].size());
  for (std::size_t j = 0; j < grid.size(); ++j) {
    const std::string row_key = "control_points[" + std::to_string(j) + "]";
    if (!grid[j].is_array() || grid[j].size() != static_cast<std::size_t>(s.count_u))
      refuse_surface(origin, "key '" + row_key + "': expected a row of " + std::to_string(s.count_u) + " points, as the first");
    for (std::size_t i = 0; i < grid[j].size(); ++i) {
      const std::string key = row_key + "[" + std::to_string(i) + "]";
      const json& p = grid[j][i];
      if (!p.is_array() || p.size() != 3) refuse_surface(origin, "key '" + key + "': expected [x, y, z]");
      s.points.push_back({number(p[0], origin, key), number(p[1], origin, key), number(p[2], origin, key)});
    }
  }
  if (const std::string why = validate(s); !why.empty()) {
    const auto colon = why.find(": ");  // validate() names the key first: "knots_u: ..."
    refuse_surface(origin, "key '" + why.substr(0, colon) + "': " + why.substr(colon + 2));
  }
  return s;
}

BSplineSurface load_surface_file(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) refuse_surface(path, "cannot be opened");
  if (!S_ISREG(st.st_mode)) refuse_surface(path, "is not a regular file");
  if (static_cast<std::uintmax_t>(st.st_size) > kMaxFileBytes) refuse_surface(path, "is larger than 64 MB");
  std::ifstream in(path, std::ios::binary);
  if (!in) refuse_surface(path, "cannot be opened");
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) refuse_surface(path, "cannot be read");
  return parse_surface_json(text.str(), path);
}

std::string surface_json(const BSplineSurface& s) {
  // one row of control points per line: readable, and diffs stay small
  std::ostringstream out;
  out.precision(17);
  auto list = [&](const std::vector<double>& v) {
    out << "[";
    for (std::size_t i = 0; i < v.size(); ++i) out << (i ? ", " : "") << v[i];
    out << "]";
  };
  out << "{\n  \"format\": \"" << kSurfaceFormat << "\",\n  \"version\": " << kSurfaceFileVersion
      << ",\n  \"units\": \"mm\",\n  \"degree\": " << s.degree << ",\n  \"e\": " << s.e << ",\n  \"knots_u\": ";
  list(s.knots_u);
  out << ",\n  \"knots_v\": ";
  list(s.knots_v);
  out << ",\n  \"control_points\": [\n";
  for (int j = 0; j < s.count_v; ++j) {
    out << "    [";
    for (int i = 0; i < s.count_u; ++i) {
      const Vec3& p = s.point(i, j);
      out << (i ? ", " : "") << "[" << p[0] << ", " << p[1] << ", " << p[2] << "]";
    }
    out << "]" << (j + 1 < s.count_v ? "," : "") << "\n";
  }
  out << "  ]\n}\n";
  return out.str();
}

void save_surface_file(const std::string& path, const BSplineSurface& s) {
  std::string error;
  if (!write_file_atomically(path, surface_json(s), &error)) refuse_surface(path, "cannot be written: " + error);
}

}  // namespace pcnc
