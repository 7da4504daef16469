// tool_axis_view.cpp — the tool tip and tool axis of a 5-axis run as an isometric SVG. See
// tool_axis_view.hpp.
#include "report/tool_axis_view.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "report/svg_text.hpp"

namespace pcnc {
namespace {

using svg::f1;

struct AxisViewPoint {
  double x = 0.0, y = 0.0;
};

// the tool path view's isometric projection (report_html.cpp): X to the lower right, Y to the
// upper right, Z up
AxisViewPoint axis_view_iso(const Vec3& p) {
  const double c = std::sqrt(3.0) / 2.0;
  return {(p[0] + p[1]) * c, p[2] + (p[1] - p[0]) * 0.5};
}

}  // namespace

std::string render_tool_axis_svg(const JointDigest& d) {
  constexpr double W = 760, H = 540, M = 30, kLegend = 40;
  std::ostringstream o;
  o << "<svg class=\"tool-axis-view\" id=\"tool-axis-view\" xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 " << W << " "
    << H << "\" role=\"img\" aria-label=\"tool tip and tool axis in workpiece coordinates, isometric view\">\n";
  if (!d.tool_axis || d.tip_path.empty()) {
    o << "<text x=\"" << W / 2 << "\" y=\"" << H / 2 << "\" fill=\"#c9d0de\" font-size=\"15\" text-anchor=\"middle\">"
      << (d.tool_axis ? "no motion in the trace" : "no tool axis: the machine's kinematics were not available")
      << "</text>\n</svg>\n";
    return o.str();
  }
  double minx = 1e300, maxx = -1e300, miny = 1e300, maxy = -1e300;
  auto extend = [&](const Vec3& p) {
    const AxisViewPoint q = axis_view_iso(p);
    minx = std::min(minx, q.x);
    maxx = std::max(maxx, q.x);
    miny = std::min(miny, q.y);
    maxy = std::max(maxy, q.y);
  };
  for (const Vec3& p : d.tip_path) extend(p);
  for (const ToolAxisMark& m : d.marks) extend(m.tip + d.axis_length_mm * m.axis);
  const double avail_w = W - 2 * M, avail_h = H - 2 * M - kLegend;
  const double scale = std::min(avail_w / std::max(maxx - minx, 1e-9), avail_h / std::max(maxy - miny, 1e-9));
  const double ox = M + (avail_w - (maxx - minx) * scale) / 2 - minx * scale;
  const double oy = M + (avail_h + (maxy - miny) * scale) / 2 + miny * scale;
  auto screen = [&](const Vec3& p) {
    const AxisViewPoint q = axis_view_iso(p);
    return AxisViewPoint{q.x * scale + ox, oy - q.y * scale};
  };
  o << "<polyline class=\"tip-path\" fill=\"none\" stroke=\"#7fb2ff\" stroke-width=\"1.4\" stroke-linejoin=\"round\" points=\"";
  for (std::size_t i = 0; i < d.tip_path.size(); ++i) {
    const AxisViewPoint q = screen(d.tip_path[i]);
    o << (i ? " " : "") << f1(q.x) << "," << f1(q.y);
  }
  o << "\"/>\n<g stroke=\"#f2b13a\" stroke-width=\"1.2\" stroke-opacity=\"0.9\">\n";
  for (const ToolAxisMark& m : d.marks) {
    const AxisViewPoint a = screen(m.tip), b = screen(m.tip + d.axis_length_mm * m.axis);
    o << "<line class=\"tool-axis\" x1=\"" << f1(a.x) << "\" y1=\"" << f1(a.y) << "\" x2=\"" << f1(b.x) << "\" y2=\""
      << f1(b.y) << "\"/>\n";
  }
  o << "</g>\n";
  // the workpiece frame's directions, bottom right
  const double lx = W - M - 60, ly = H - kLegend - 10;
  const char* names[3] = {"X", "Y", "Z"};
  o << "<g font-size=\"12\" fill=\"#c9d0de\" stroke-width=\"1.2\">\n";
  for (int i = 0; i < 3; ++i) {
    Vec3 e{0.0, 0.0, 0.0};
    e[static_cast<std::size_t>(i)] = 1.0;
    const AxisViewPoint q = axis_view_iso(e);
    const double ex = lx + 30 * q.x, ey = ly - 30 * q.y;
    o << "<line x1=\"" << lx << "\" y1=\"" << ly << "\" x2=\"" << f1(ex) << "\" y2=\"" << f1(ey) << "\" stroke=\"#8c96ad\"/><text x=\""
      << f1(ex + 3) << "\" y=\"" << f1(ey + 4) << "\">" << names[i] << "</text>\n";
  }
  const double gy = H - kLegend + 14;
  o << "<line x1=\"" << M << "\" y1=\"" << gy << "\" x2=\"" << M + 30 << "\" y2=\"" << gy
    << "\" stroke=\"#7fb2ff\" stroke-width=\"1.4\"/><text x=\"" << M + 36 << "\" y=\"" << gy + 4
    << "\">tool tip (commanded)</text>\n";
  o << "<line x1=\"" << M + 200 << "\" y1=\"" << gy << "\" x2=\"" << M + 230 << "\" y2=\"" << gy
    << "\" stroke=\"#f2b13a\" stroke-width=\"1.2\"/><text x=\"" << M + 236 << "\" y=\"" << gy + 4 << "\">tool axis, "
    << fixed(d.axis_length_mm, 1) << " mm long, every " << fixed(d.axis_every_mm, 2) << " mm of the tip's path</text>\n";
  o << "</g>\n<!-- " << d.marks.size() << " tool-axis marks, " << d.tip_path.size() << " tip points -->\n</svg>\n";
  return o.str();
}

}  // namespace pcnc
