// surface_page.cpp — the fit report's HTML page (see surface_page.hpp).
#include "report/surface_page.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "report/svg_text.hpp"

namespace pcnc {
namespace {

// A diverging scale: blue (low) through white (0) to red (high), symmetric about 0 when the
// values straddle it; otherwise a sequential one over [min, max].
std::string colour(double t) {  // t in [-1, 1]
  t = std::clamp(t, -1.0, 1.0);
  const double a = std::fabs(t);
  const int hi = 255, lo = static_cast<int>(255 * (1.0 - a));
  char b[16];
  if (t >= 0)
    std::snprintf(b, sizeof b, "#%02x%02x%02x", hi, lo, lo);
  else
    std::snprintf(b, sizeof b, "#%02x%02x%02x", lo, lo, hi);
  return b;
}

}  // namespace

std::string surface_page_html(const SurfacePage& p) {
  double vmin = INFINITY, vmax = -INFINITY;
  for (double v : p.values) vmin = std::min(vmin, v), vmax = std::max(vmax, v);
  if (!std::isfinite(vmin)) vmin = vmax = 0.0;
  const bool diverging = vmin < 0.0 && vmax > 0.0;
  const double span = diverging ? std::max(-vmin, vmax) : std::max(vmax - vmin, 1e-12);
  auto t_of = [&](double v) { return diverging ? v / span : 2.0 * (v - vmin) / span - 1.0; };

  const double w = 520, h_map = std::max(1.0, p.y1 - p.y0) / std::max(1e-9, p.x1 - p.x0) * w;
  const double h = std::clamp(h_map, 120.0, 800.0), m = 64;
  auto sx = [&](double x) { return m + (x - p.x0) / std::max(1e-9, p.x1 - p.x0) * w; };
  auto sy = [&](double y) { return m + h - (y - p.y0) / std::max(1e-9, p.y1 - p.y0) * h; };
  std::ostringstream s;
  s << "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>" << svg::escape(p.title)
    << "</title>\n<style>body{font-family:sans-serif;margin:2em}table{border-collapse:collapse}"
       "td{padding:2px 12px 2px 0}</style></head><body>\n<h1>Measured surface: "
    << svg::escape(p.title) << "</h1>\n<table>\n";
  for (const auto& [label, value] : p.figures)
    s << "<tr><td>" << svg::escape(label) << "</td><td>" << svg::escape(value) << "</td></tr>\n";
  s << "</table>\n<h2>" << svg::escape(p.map_label) << "</h2>\n";
  s << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << w + 2 * m + 90 << "\" height=\"" << h + 2 * m
    << "\" font-size=\"11\">\n";
  const double cw = w / std::max(1, p.nx), ch = h / std::max(1, p.ny);
  for (int j = 0; j < p.ny; ++j)
    for (int i = 0; i < p.nx; ++i)
      s << "<rect x=\"" << fixed(m + i * cw, 2) << "\" y=\"" << fixed(m + h - (j + 1) * ch, 2) << "\" width=\""
        << fixed(cw + 0.3, 2) << "\" height=\"" << fixed(ch + 0.3, 2) << "\" fill=\""
        << colour(t_of(p.values[static_cast<std::size_t>(j * p.nx + i)])) << "\"/>\n";
  s << "<rect x=\"" << m << "\" y=\"" << m << "\" width=\"" << w << "\" height=\"" << h
    << "\" fill=\"none\" stroke=\"#333\"/>\n";
  for (const Vec3& q : p.probes)
    s << "<circle cx=\"" << fixed(sx(q[0]), 2) << "\" cy=\"" << fixed(sy(q[1]), 2)
      << "\" r=\"2.5\" fill=\"#000\"><title>" << fixed(q[0], 4) << ", " << fixed(q[1], 4) << ", "
      << fixed(q[2], 4) << " mm</title></circle>\n";
  s << "<text x=\"" << m << "\" y=\"" << m + h + 16 << "\">X " << fixed(p.x0, 3) << "</text><text x=\"" << m + w
    << "\" y=\"" << m + h + 16 << "\" text-anchor=\"end\">X " << fixed(p.x1, 3) << " mm</text>\n";
  s << "<text x=\"" << m - 4 << "\" y=\"" << m + h << "\" text-anchor=\"end\">Y " << fixed(p.y0, 3)
    << "</text><text x=\"" << m - 4 << "\" y=\"" << m + 10 << "\" text-anchor=\"end\">" << fixed(p.y1, 3)
    << "</text>\n";
  // the colour bar
  const double bx = m + w + 20, bh = h;
  for (int k = 0; k < 50; ++k) {
    const double t = 1.0 - 2.0 * (k + 0.5) / 50.0;
    s << "<rect x=\"" << bx << "\" y=\"" << fixed(m + k * bh / 50, 2) << "\" width=\"16\" height=\""
      << fixed(bh / 50 + 0.3, 2) << "\" fill=\"" << colour(t) << "\"/>\n";
  }
  const double top = diverging ? span : vmax, bottom = diverging ? -span : vmin;
  s << "<text x=\"" << bx + 20 << "\" y=\"" << m + 10 << "\">" << fixed(top, 2) << " µm</text>\n";
  s << "<text x=\"" << bx + 20 << "\" y=\"" << m + bh << "\">" << fixed(bottom, 2) << " µm</text>\n";
  s << "</svg>\n<p>Dots: the measured points (hover for their coordinates). The map is sampled on "
    << p.nx << " × " << p.ny << " cells.</p>\n</body></html>\n";
  return s.str();
}

}  // namespace pcnc
