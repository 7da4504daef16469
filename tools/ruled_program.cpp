// ruled_program.cpp — the ruled-surface G-code form and its JSON file form. See ruled_program.hpp.
#include "ruled_program.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>

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

}  // namespace pcnc
