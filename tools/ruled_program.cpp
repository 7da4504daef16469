// ruled_program.cpp — the ruled-surface G-code form and its JSON file form. See ruled_program.hpp.
#include "ruled_program.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <initializer_list>

namespace pcnc {
namespace {

std::string num(const char* f, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, v == 0.0 ? 0.0 : v);  // no "-0"
  std::string s = buf;
  if (s.find_first_not_of("-0.") == std::string::npos) s = s[0] == '-' ? s.substr(1) : s;  // "-0.00000" -> "0.00000"
  return s;
}

}  // namespace

std::string ruled_point_line(const Vec3& p, const Vec3& a) {
  return "X" + num("%.5f", p[0]) + " Y" + num("%.5f", p[1]) + " Z" + num("%.5f", p[2]) + " I" + num("%.7f", a[0]) +
         " J" + num("%.7f", a[1]) + " K" + num("%.7f", a[2]);
}

std::vector<std::string> ruled_program_lines(const std::vector<RuledPiece>& pieces, const RuledProgramOptions& o) {
  std::vector<std::string> out;
  for (std::string h : o.header) {
    std::replace(h.begin(), h.end(), '(', '[');  // no nested comments (LinuxCNC refuses them)
    std::replace(h.begin(), h.end(), ')', ']');
    out.push_back("(" + h + ")");
  }
  out.push_back("G21 G90 G17 G94");
  if (!o.turn_joints.empty()) out.push_back("G0 " + o.turn_joints + " (the tool axis of the first set point, TCP off)");
  out.push_back("M428 (tool-centre-point control on)");
  out.push_back("G0 Z" + num("%.5f", o.clearance_z));
  if (!pieces.empty() && !pieces.front().points.empty())
    out.push_back("G0 X" + num("%.5f", pieces.front().points.front()[0]) + " Y" +
                  num("%.5f", pieces.front().points.front()[1]));
  for (const RuledPiece& piece : pieces) {
    out.push_back("G5.4 F" + num("%.3f", o.feed_mm_min) + (piece.comment.empty() ? "" : " (" + piece.comment + ")"));
    for (std::size_t i = 0; i < piece.points.size() && i < piece.axes.size(); ++i)
      out.push_back(ruled_point_line(piece.points[i], normalized(piece.axes[i])));
    out.push_back("G5.5");
  }
  out.push_back("G0 Z" + num("%.5f", o.clearance_z));
  out.push_back("M429 (tool-centre-point control off)");
  if (!o.turn_back.empty()) out.push_back("G0 " + o.turn_back);
  out.push_back("M2");
  return out;
}

std::string ruled_program_json(const std::vector<RuledPiece>& pieces, double feed_mm_min) {
  nlohmann::json j;
  j["format"] = "pcnc-ruled-program";
  j["version"] = 1;
  j["units"] = "mm";
  j["feed_mm_min"] = feed_mm_min;
  nlohmann::json arr = nlohmann::json::array();
  for (const RuledPiece& piece : pieces) {
    nlohmann::json pts = nlohmann::json::array(), axs = nlohmann::json::array();
    for (const Vec3& p : piece.points) pts.push_back({p[0], p[1], p[2]});
    for (const Vec3& a : piece.axes) {
      const Vec3 u = normalized(a);
      axs.push_back({u[0], u[1], u[2]});
    }
    arr.push_back({{"points", pts}, {"axes", axs}});
  }
  j["pieces"] = arr;
  return j.dump(1) + "\n";
}

namespace {

struct JsonRefusal {
  std::string why;
};

[[noreturn]] void refuse(const std::string& why) { throw JsonRefusal{why}; }

void only_keys(const nlohmann::json& j, std::initializer_list<const char*> keys, const std::string& where) {
  if (!j.is_object()) refuse(where + ": expected an object");
  for (auto it = j.begin(); it != j.end(); ++it) {
    bool known = false;
    for (const char* k : keys) known = known || it.key() == k;
    if (!known) refuse(where + ": unknown key '" + it.key() + "'");
  }
  for (const char* k : keys)
    if (!j.contains(k)) refuse(where + ": missing key '" + k + "'");
}

Vec3 triple(const nlohmann::json& v, const std::string& where) {
  if (!v.is_array() || v.size() != 3) refuse(where + ": expected three numbers, got " + v.dump());
  Vec3 out{};
  for (std::size_t k = 0; k < 3; ++k) {
    if (!v[k].is_number() || !std::isfinite(v[k].get<double>())) refuse(where + ": expected three finite numbers, got " + v.dump());
    out[k] = v[k].get<double>();
  }
  return out;
}

}  // namespace

RuledJsonProgram read_ruled_program_json(const std::string& text, const std::string& origin) {
  RuledJsonProgram out;
  try {
    nlohmann::json j;
    try {
      j = nlohmann::json::parse(text);
    } catch (const nlohmann::json::exception& e) {
      refuse(std::string("not JSON: ") + e.what());
    }
    only_keys(j, {"format", "version", "units", "feed_mm_min", "pieces"}, "the file");
    if (j["format"] != "pcnc-ruled-program") refuse("format " + j["format"].dump() + ": expected \"pcnc-ruled-program\"");
    if (j["version"] != 1) refuse("version " + j["version"].dump() + ": expected 1");
    if (j["units"] != "mm") refuse("units " + j["units"].dump() + ": expected \"mm\"");
    const nlohmann::json& f = j["feed_mm_min"];
    if (!f.is_number() || !(f.get<double>() > 0.0) || !std::isfinite(f.get<double>()))
      refuse("feed_mm_min " + f.dump() + ": expected a number > 0");
    out.feed_mm_min = f.get<double>();
    const nlohmann::json& ps = j["pieces"];
    if (!ps.is_array() || ps.empty()) refuse("pieces: expected a non-empty array");
    for (std::size_t p = 0; p < ps.size(); ++p) {
      const std::string where = "piece " + std::to_string(p + 1);
      only_keys(ps[p], {"points", "axes"}, where);
      const nlohmann::json& pts = ps[p]["points"];
      const nlohmann::json& axs = ps[p]["axes"];
      if (!pts.is_array() || !axs.is_array() || pts.size() != axs.size())
        refuse(where + ": expected arrays 'points' and 'axes' of the same length");
      if (pts.size() < 2) refuse(where + ": expected at least 2 set points");
      RuledPiece piece;
      for (std::size_t i = 0; i < pts.size(); ++i) {
        const std::string at = where + ", set point " + std::to_string(i + 1);
        const Vec3 q = triple(pts[i], at);
        const Vec3 a = triple(axs[i], at + " axis");
        if (std::abs(norm(a) - 1.0) > 1e-3) refuse(at + ": tool vector of length " + num("%.6g", norm(a)) + ": expected a unit vector");
        if (i > 0 && norm(q - piece.points.back()) < 1e-6) refuse(at + ": less than 1e-6 mm from the set point before");
        piece.points.push_back(q);
        piece.axes.push_back(normalized(a));
      }
      if (!out.pieces.empty()) {
        const RuledPiece& b = out.pieces.back();
        if (norm(piece.points.front() - b.points.back()) > 1e-9 || norm(piece.axes.front() - b.axes.back()) > 1e-9)
          refuse(where + ": does not start where piece " + std::to_string(p) + " ended (point and axis)");
      }
      out.pieces.push_back(std::move(piece));
    }
  } catch (const JsonRefusal& r) {
    out.pieces.clear();
    out.feed_mm_min = 0.0;
    out.error = origin + ": " + r.why;
  }
  return out;
}

}  // namespace pcnc
