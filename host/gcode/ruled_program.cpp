// ruled_program.cpp — the ruled-surface G-code form and its JSON file form. See ruled_program.hpp.
#include "gcode/ruled_program.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <initializer_list>
#include <string_view>

#include "gcode/json_places.hpp"

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
  if (!pieces.empty() && !pieces.front().points.empty()) {
    const Vec3& first = pieces.front().points.front();
    out.push_back("G0 X" + num("%.5f", first[0]) + " Y" + num("%.5f", first[1]));
    if (o.rapid_to_first_z && num("%.5f", first[2]) != num("%.5f", o.clearance_z)) out.push_back("G0 Z" + num("%.5f", first[2]));
  }
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

// A refusal at a place of the text (an offset, kNoJsonPlace: the top of the file).
struct JsonRefusal {
  std::string path;
  std::size_t offset;
  std::string why;
};

[[noreturn]] void refuse(const std::string& path, std::size_t offset, const std::string& why) {
  throw JsonRefusal{path, offset, why};
}

// The places of one container's members, found as they are needed.
struct Here {
  std::string_view text;
  std::string path;
  std::size_t offset;
  Here member(const char* key) const {
    const std::size_t at = json_member(text, offset, key);
    return {text, (path.empty() ? "" : path + ".") + key, at == kNoJsonPlace ? offset : at};
  }
  std::string name() const { return path.empty() ? "the file" : path; }
  [[noreturn]] void refuse(const std::string& why) const { pcnc::refuse(name(), offset, why); }
};

void only_keys(const nlohmann::json& j, std::initializer_list<const char*> keys, const Here& here) {
  if (!j.is_object()) here.refuse("expected an object");
  for (auto it = j.begin(); it != j.end(); ++it) {
    bool known = false;
    for (const char* k : keys) known = known || it.key() == k;
    if (!known) here.refuse("unknown key '" + it.key() + "'");
  }
  for (const char* k : keys)
    if (!j.contains(k)) here.refuse("missing key '" + std::string(k) + "'");
}

Vec3 triple(const nlohmann::json& v, const Here& here) {
  if (!v.is_array() || v.size() != 3) here.refuse("expected three numbers, got " + v.dump());
  Vec3 out{};
  for (std::size_t k = 0; k < 3; ++k) {
    if (!v[k].is_number() || !std::isfinite(v[k].get<double>())) here.refuse("expected three finite numbers, got " + v.dump());
    out[k] = v[k].get<double>();
  }
  return out;
}

std::string indexed(const std::string& path, std::size_t i) { return path + "[" + std::to_string(i) + "]"; }

// Element i of the array at `arr` (the array itself when it has no such element).
Here element(const Here& arr, const std::vector<std::size_t>& offsets, std::size_t i) {
  return {arr.text, indexed(arr.path, i), i < offsets.size() ? offsets[i] : arr.offset};
}

}  // namespace

RuledJsonProgram read_ruled_program_json(const std::string& text, const std::string& origin) {
  RuledJsonProgram out;
  const TextLines lines(text);
  out.text_lines = lines.count();
  auto place = [&](const Here& h) { return JsonPlace{h.name(), lines.line(h.offset), lines.column(h.offset)}; };
  try {
    nlohmann::json j;
    try {
      j = nlohmann::json::parse(text);
    } catch (const nlohmann::json::parse_error& e) {
      std::string what = e.what();  // "[json.exception.parse_error.101] parse error at line 1, column 2: ..."
      if (const std::size_t colon = what.find(": "); colon != std::string::npos) what = what.substr(colon + 2);
      refuse("the file", e.byte > 0 ? std::min<std::size_t>(e.byte - 1, text.size()) : 0, "not JSON: " + what);
    } catch (const nlohmann::json::exception& e) {
      refuse("the file", 0, std::string("not JSON: ") + e.what());
    }
    const Here root{text, "", json_root(text) == kNoJsonPlace ? 0 : json_root(text)};
    only_keys(j, {"format", "version", "units", "feed_mm_min", "pieces"}, root);
    if (j["format"] != "pcnc-ruled-program") root.member("format").refuse(j["format"].dump() + ": expected \"pcnc-ruled-program\"");
    if (j["version"] != 1) root.member("version").refuse(j["version"].dump() + ": expected 1");
    if (j["units"] != "mm") root.member("units").refuse(j["units"].dump() + ": expected \"mm\"");
    const nlohmann::json& f = j["feed_mm_min"];
    if (!f.is_number() || !(f.get<double>() > 0.0) || !std::isfinite(f.get<double>()))
      root.member("feed_mm_min").refuse(f.dump() + ": expected a number > 0");
    out.feed_mm_min = f.get<double>();
    const nlohmann::json& ps = j["pieces"];
    const Here pieces = root.member("pieces");
    if (!ps.is_array() || ps.empty()) pieces.refuse("expected a non-empty array");
    const std::vector<std::size_t> piece_at = json_elements(text, pieces.offset);
    for (std::size_t p = 0; p < ps.size(); ++p) {
      const Here here = element(pieces, piece_at, p);
      only_keys(ps[p], {"points", "axes"}, here);
      const nlohmann::json& pts = ps[p]["points"];
      const nlohmann::json& axs = ps[p]["axes"];
      const Here pts_here = here.member("points"), axs_here = here.member("axes");
      if (!pts.is_array()) pts_here.refuse("expected an array of set points");
      if (!axs.is_array()) axs_here.refuse("expected an array of tool vectors");
      if (pts.size() != axs.size())
        here.refuse("expected arrays 'points' and 'axes' of the same length (" + std::to_string(pts.size()) + " and " +
                    std::to_string(axs.size()) + ")");
      if (pts.size() < 2) pts_here.refuse("expected at least 2 set points");
      const std::vector<std::size_t> pt_at = json_elements(text, pts_here.offset);
      const std::vector<std::size_t> ax_at = json_elements(text, axs_here.offset);
      RuledPiece piece;
      RuledJsonProgram::PiecePlaces places;
      places.piece = place(here);
      for (std::size_t i = 0; i < pts.size(); ++i) {
        const Here pt = element(pts_here, pt_at, i), ax = element(axs_here, ax_at, i);
        const Vec3 q = triple(pts[i], pt);
        const Vec3 a = triple(axs[i], ax);
        if (std::abs(norm(a) - 1.0) > 1e-3) ax.refuse("tool vector of length " + num("%.6g", norm(a)) + ": expected a unit vector");
        if (i > 0 && norm(q - piece.points.back()) < 1e-6) pt.refuse("less than 1e-6 mm from the set point before");
        piece.points.push_back(q);
        piece.axes.push_back(normalized(a));
        places.points.push_back(place(pt));
        if (i == 0) places.first_axis = place(ax);
      }
      if (!out.pieces.empty()) {
        const RuledPiece& b = out.pieces.back();
        if (norm(piece.points.front() - b.points.back()) > 1e-9 || norm(piece.axes.front() - b.axes.back()) > 1e-9)
          here.refuse("does not start where " + indexed("pieces", p - 1) + " ended (point and axis)");
      }
      out.pieces.push_back(std::move(piece));
      out.places.push_back(std::move(places));
    }
  } catch (const JsonRefusal& r) {
    out.pieces.clear();
    out.places.clear();
    out.feed_mm_min = 0.0;
    const std::size_t at = r.offset == kNoJsonPlace ? 0 : std::min(r.offset, text.size());
    out.refusal.file = origin;
    out.refusal.line = text.empty() ? 0 : lines.line(at);
    out.refusal.column = text.empty() ? 0 : lines.column(at);
    out.refusal.message = r.path + ": " + r.why;
    out.error = format_diagnostic(out.refusal);
  }
  return out;
}

}  // namespace pcnc
