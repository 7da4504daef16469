// report_html.cpp — rendering the HTML run report: figures table, isometric tool path and
// time plots as inline SVG (see report_html.hpp).
#include "report/report_html.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <stdexcept>
#include <vector>


namespace pcnc {

std::string fixed(double v, int decimals) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  std::string s(buf);
  if (s.size() > 1 && s[0] == '-' && s.find_first_not_of("-0.") == std::string::npos) s.erase(0, 1);
  return s;
}

namespace {

std::string escape(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

// A number in a span with a stable id: what scripts and the tests read.
std::string num(const std::string& id, const std::string& text) {
  return "<span class=\"n\" id=\"" + id + "\">" + text + "</span>";
}

std::string hms(double s) {
  if (!(s >= 0.0)) s = 0.0;
  const auto whole = static_cast<long long>(s);
  char buf[64];
  if (whole >= 3600) {
    std::snprintf(buf, sizeof buf, "%lld h %02lld min %02lld s", whole / 3600, (whole / 60) % 60, whole % 60);
  } else if (whole >= 60) {
    std::snprintf(buf, sizeof buf, "%lld min %04.1f s", whole / 60, s - 60.0 * static_cast<double>(whole / 60));
  } else {
    return "";
  }
  return buf;
}

// ---- colours ----

// Viridis, sampled: slow = dark violet, fast = yellow.
const double kViridis[][3] = {{68, 1, 84},    {72, 40, 120},  {62, 73, 137},  {49, 104, 142}, {38, 130, 142},
                              {31, 158, 137}, {53, 183, 121}, {110, 206, 88}, {181, 222, 43}, {253, 231, 37}};
constexpr int kViridisStops = 10;

std::string colour_at(double f) {
  f = std::clamp(f, 0.0, 1.0) * (kViridisStops - 1);
  const int i = std::min(static_cast<int>(f), kViridisStops - 2);
  const double w = f - i;
  char buf[16];
  std::snprintf(buf, sizeof buf, "#%02x%02x%02x", static_cast<int>(std::lround(kViridis[i][0] * (1 - w) + kViridis[i + 1][0] * w)),
                static_cast<int>(std::lround(kViridis[i][1] * (1 - w) + kViridis[i + 1][1] * w)),
                static_cast<int>(std::lround(kViridis[i][2] * (1 - w) + kViridis[i + 1][2] * w)));
  return buf;
}

const char* kAxisColour[3] = {"#d1495b", "#2a9d58", "#2f6fd0"};

// ---- axis ticks ----

double nice_step(double range, int target) {
  if (!(range > 0.0)) return 1.0;
  const double raw = range / std::max(target, 1);
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  const double r = raw / mag;
  return (r < 1.5 ? 1.0 : r < 3.5 ? 2.0 : r < 7.5 ? 5.0 : 10.0) * mag;
}

int decimals_for(double step) { return std::max(0, static_cast<int>(std::ceil(-std::log10(step) - 1e-9))); }

std::string f1(double v) { return fixed(v, 1); }

// ---- isometric projection: X to the lower right, Y to the upper right, Z up ----

struct P2 {
  double x = 0.0, y = 0.0;
};
P2 iso(const Vec3& p) {
  const double c = std::sqrt(3.0) / 2.0;
  return {(p[0] + p[1]) * c, p[2] + (p[1] - p[0]) * 0.5};  // y up
}

struct Frame2 {
  double scale = 1.0, ox = 0.0, oy = 0.0;  // screen = (x*scale + ox, oy - y*scale)
  P2 to_screen(const Vec3& p) const {
    const P2 q = iso(p);
    return {q.x * scale + ox, oy - q.y * scale};
  }
};

std::string pt(const P2& p) { return f1(p.x) + "," + f1(p.y); }

}  // namespace

// ---- the tool path ----

namespace {

// The part's box: the program's extents and the final tool position (machine coordinates).
// The approach from the home position may leave it; the views clip there.
void part_box(const RunSummary& s, Vec3& lo, Vec3& hi) {
  lo = s.min_point;
  hi = s.max_point;
  for (std::size_t i = 0; i < 3; ++i) {
    lo[i] = std::min(lo[i], s.final_status.actual[i]);
    hi[i] = std::max(hi[i], s.final_status.actual[i]);
    const double pad = std::max(0.02 * (hi[i] - lo[i]), 1e-3);  // a flat part still gets a visible box
    lo[i] -= pad;
    hi[i] += pad;
  }
}

// The feed-speed colour scale: rapids excluded (they would squash it).
double feed_speed_max(const std::vector<ToolPathPoint>& path) {
  double v = 0.0;
  for (const ToolPathPoint& q : path) {
    if (!q.rapid) v = std::max(v, q.speed);
  }
  return v > 0.0 ? v : 1.0;
}

// Polylines of the path through `project`: runs of segments with the same kind and colour.
template <typename Project>
std::string path_polylines(const std::vector<ToolPathPoint>& path, double vmax, Project project, double width,
                           std::size_t* feeds = nullptr) {
  constexpr int kBins = 32;
  auto bin_of = [&](const ToolPathPoint& q) { return std::clamp(static_cast<int>(q.speed / vmax * kBins), 0, kBins - 1); };
  std::ostringstream o;
  std::size_t n_feed = 0;
  std::size_t i = 1;
  while (i < path.size()) {
    const bool rapid = path[i].rapid;
    const int bin = rapid ? -1 : bin_of(path[i]);
    std::string pts = pt(project(path[i - 1].p));
    std::size_t j = i;
    while (j < path.size() && path[j].rapid == rapid && (rapid || bin_of(path[j]) == bin)) {
      pts += " " + pt(project(path[j].p));
      ++j;
    }
    if (rapid) {
      o << "<polyline class=\"rapid\" stroke=\"#aab3c5\" stroke-opacity=\"0.55\" stroke-width=\"" << fixed(width * 0.6, 2)
        << "\" stroke-dasharray=\"4 3\" points=\"" << pts << "\"/>\n";
    } else {
      ++n_feed;
      o << "<polyline class=\"feed\" stroke=\"" << colour_at((bin + 0.5) / kBins) << "\" stroke-width=\"" << fixed(width, 2)
        << "\" points=\"" << pts << "\"/>\n";
    }
    i = j;
  }
  if (feeds) *feeds = n_feed;
  return o.str();
}

std::string end_markers(const P2& last, const P2& tool, const std::string& id) {
  return "<circle cx=\"" + f1(last.x) + "\" cy=\"" + f1(last.y) +
         "\" r=\"8\" fill=\"none\" stroke=\"#ffffff\" stroke-opacity=\"0.75\" stroke-width=\"1.2\"/>\n"
         "<circle class=\"final-tool\"" + (id.empty() ? std::string() : " id=\"" + id + "\"") + " cx=\"" + f1(tool.x) + "\" cy=\"" + f1(tool.y) +
         "\" r=\"5\" fill=\"#ff2d2d\" stroke=\"#ffffff\" stroke-width=\"1.5\"/>\n";
}

}  // namespace

std::string render_toolpath_svg(const ReportPage& page) {
  const RunSummary& s = page.summary;
  constexpr double W = 760, H = 540, M = 30, kLegend = 50;
  std::ostringstream o;
  o << "<svg class=\"toolpath\" xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 " << W << " " << H
    << "\" role=\"img\" aria-label=\"tool path, isometric view\">\n";
  o << "<defs><clipPath id=\"iso-clip\"><rect x=\"4\" y=\"4\" width=\"" << W - 8 << "\" height=\"" << H - kLegend - 8
    << "\"/></clipPath></defs>\n";

  const std::vector<ToolPathPoint> empty;
  const std::vector<ToolPathPoint>& path = page.has_trace ? page.trace.path : empty;
  Vec3 lo, hi;
  part_box(s, lo, hi);
  std::vector<Vec3> corners;
  for (int k = 0; k < 8; ++k) corners.push_back({(k & 1) ? hi[0] : lo[0], (k & 2) ? hi[1] : lo[1], (k & 4) ? hi[2] : lo[2]});
  double minx = 1e300, maxx = -1e300, miny = 1e300, maxy = -1e300;
  for (const Vec3& c : corners) {
    const P2 q = iso(c);
    minx = std::min(minx, q.x);
    maxx = std::max(maxx, q.x);
    miny = std::min(miny, q.y);
    maxy = std::max(maxy, q.y);
  }
  Frame2 fr;
  const double avail_w = W - 2 * M, avail_h = H - 2 * M - kLegend;
  fr.scale = std::min(avail_w / std::max(maxx - minx, 1e-9), avail_h / std::max(maxy - miny, 1e-9));
  fr.ox = M + (avail_w - (maxx - minx) * fr.scale) / 2 - minx * fr.scale;
  fr.oy = M + (avail_h + (maxy - miny) * fr.scale) / 2 + miny * fr.scale;
  auto project = [&](const Vec3& p) { return fr.to_screen(p); };

  // the box's twelve edges
  o << "<g stroke=\"#3b4358\" stroke-width=\"1\" fill=\"none\">\n";
  for (int a = 0; a < 8; ++a) {
    for (int b = a + 1; b < 8; ++b) {
      const int diff = a ^ b;
      if (diff != 1 && diff != 2 && diff != 4) continue;
      const P2 p = project(corners[a]), q = project(corners[b]);
      o << "<line x1=\"" << f1(p.x) << "\" y1=\"" << f1(p.y) << "\" x2=\"" << f1(q.x) << "\" y2=\"" << f1(q.y) << "\"/>\n";
    }
  }
  o << "</g>\n";
  // the box's size along the three edges from its corner nearest the viewer's left
  const char* names[3] = {"X", "Y", "Z"};
  for (int i = 0; i < 3; ++i) {
    Vec3 mid = i == 1 ? Vec3{hi[0], lo[1], lo[2]} : lo;
    mid[static_cast<std::size_t>(i)] = (lo[static_cast<std::size_t>(i)] + hi[static_cast<std::size_t>(i)]) / 2;
    const P2 q = project(mid);
    const double dx = i == 0 ? -8 : 8, dy = i == 2 ? 4 : 16;
    o << "<text x=\"" << f1(q.x + dx) << "\" y=\"" << f1(q.y + dy) << "\" fill=\"#8c96ad\" font-size=\"12\" text-anchor=\""
      << (i == 0 ? "end" : "start") << "\">" << names[i] << " " << fixed(hi[static_cast<std::size_t>(i)] - lo[static_cast<std::size_t>(i)], 2)
      << " mm</text>\n";
  }

  const double vmax = feed_speed_max(path);
  std::size_t feeds = 0;
  o << "<g clip-path=\"url(#iso-clip)\" fill=\"none\" stroke-linejoin=\"round\" stroke-linecap=\"round\">\n"
    << path_polylines(path, vmax, project, 1.5, &feeds) << "</g>\n";
  o << end_markers(project(s.last_point), project(s.final_status.actual), "final-tool");

  // legend: colour bar for the feed speed, the rapid dash, the dots
  const double ly = H - kLegend + 10, lx = M;
  constexpr int kSteps = 48;
  const double bw = 200.0 / kSteps;
  o << "<g font-size=\"12\" fill=\"#c9d0de\">\n";
  for (int k = 0; k < kSteps; ++k) {
    o << "<rect x=\"" << f1(lx + k * bw) << "\" y=\"" << ly << "\" width=\"" << f1(bw + 0.6) << "\" height=\"10\" fill=\""
      << colour_at((k + 0.5) / kSteps) << "\"/>\n";
  }
  o << "<text x=\"" << lx << "\" y=\"" << ly + 26 << "\">0</text>\n";
  o << "<text x=\"" << lx + 200 << "\" y=\"" << ly + 26 << "\" text-anchor=\"end\">" << fixed(vmax, 1) << " mm/s ("
    << fixed(vmax * 60.0, 0) << " mm/min)</text>\n";
  const double rx = lx + 240;
  o << "<line x1=\"" << rx << "\" y1=\"" << ly + 5 << "\" x2=\"" << rx + 30 << "\" y2=\"" << ly + 5
    << "\" stroke=\"#aab3c5\" stroke-dasharray=\"4 3\"/><text x=\"" << rx + 36 << "\" y=\"" << ly + 9 << "\">rapid</text>\n";
  o << "<circle cx=\"" << rx + 100 << "\" cy=\"" << ly + 5 << "\" r=\"5\" fill=\"#ff2d2d\" stroke=\"#fff\" stroke-width=\"1.5\"/><text x=\""
    << rx + 110 << "\" y=\"" << ly + 9 << "\">tool at the end</text>\n";
  o << "<circle cx=\"" << rx + 230 << "\" cy=\"" << ly + 5
    << "\" r=\"7\" fill=\"none\" stroke=\"#fff\" stroke-opacity=\"0.75\" stroke-width=\"1.2\"/><text x=\"" << rx + 242 << "\" y=\""
    << ly + 9 << "\">last programmed point</text>\n";
  o << "</g>\n";
  if (path.empty()) {
    o << "<text x=\"" << W / 2 << "\" y=\"" << H / 2 << "\" fill=\"#c9d0de\" font-size=\"15\" text-anchor=\"middle\">no trace: "
      << escape(page.trace_note.empty() ? "the tool path is not available" : page.trace_note) << "</text>\n";
  }
  o << "<!-- " << feeds << " feed polylines, " << path.size() << " points -->\n";
  o << "</svg>\n";
  return o.str();
}

std::string render_top_view_svg(const ReportPage& page) {
  const RunSummary& s = page.summary;
  const std::vector<ToolPathPoint> empty;
  const std::vector<ToolPathPoint>& path = page.has_trace ? page.trace.path : empty;
  Vec3 lo, hi;
  part_box(s, lo, hi);
  constexpr double W = 760, L = 52, R = 16, T = 14, B = 34;
  const double sx = hi[0] - lo[0], sy = hi[1] - lo[1];
  const double scale = (W - L - R) / sx;
  const double H = std::clamp(sy * scale, 160.0, 520.0) + T + B;
  const double k = std::min(scale, (H - T - B) / sy);  // equal scale on X and Y
  const double ox = L + ((W - L - R) - sx * k) / 2, oy = T + ((H - T - B) + sy * k) / 2;
  auto project = [&](const Vec3& p) { return P2{ox + (p[0] - lo[0]) * k, oy - (p[1] - lo[1]) * k}; };
  std::ostringstream o;
  o << "<svg class=\"topview\" xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 " << W << " " << f1(H)
    << "\" role=\"img\" aria-label=\"tool path, top view\">\n";
  o << "<defs><clipPath id=\"top-clip\"><rect x=\"" << f1(ox) << "\" y=\"" << f1(oy - sy * k) << "\" width=\"" << f1(sx * k)
    << "\" height=\"" << f1(sy * k) << "\"/></clipPath></defs>\n";
  // grid in machine millimetres
  const double step = nice_step(std::max(sx, sy), 8);
  const int d = decimals_for(step);
  o << "<g font-size=\"11\" fill=\"#8c96ad\" stroke-width=\"1\">\n";
  for (double x = std::ceil(lo[0] / step) * step; x <= hi[0] + 1e-9; x += step) {
    const P2 a = project({x, lo[1], 0}), b = project({x, hi[1], 0});
    o << "<line x1=\"" << f1(a.x) << "\" y1=\"" << f1(a.y) << "\" x2=\"" << f1(b.x) << "\" y2=\"" << f1(b.y)
      << "\" stroke=\"#262c3b\"/><text x=\"" << f1(a.x) << "\" y=\"" << f1(a.y + 15) << "\" text-anchor=\"middle\">" << fixed(x, d)
      << "</text>\n";
  }
  for (double y = std::ceil(lo[1] / step) * step; y <= hi[1] + 1e-9; y += step) {
    const P2 a = project({lo[0], y, 0}), b = project({hi[0], y, 0});
    o << "<line x1=\"" << f1(a.x) << "\" y1=\"" << f1(a.y) << "\" x2=\"" << f1(b.x) << "\" y2=\"" << f1(b.y)
      << "\" stroke=\"#262c3b\"/><text x=\"" << f1(a.x - 6) << "\" y=\"" << f1(a.y + 4) << "\" text-anchor=\"end\">" << fixed(y, d)
      << "</text>\n";
  }
  o << "<text x=\"" << W - R << "\" y=\"" << f1(H - 4) << "\" text-anchor=\"end\">X, mm</text>"
    << "<text x=\"12\" y=\"" << T + 8 << "\">Y, mm</text>\n</g>\n";
  o << "<g clip-path=\"url(#top-clip)\" fill=\"none\" stroke-linejoin=\"round\" stroke-linecap=\"round\">\n"
    << path_polylines(path, feed_speed_max(path), project, 1.3) << "</g>\n";
  o << end_markers(project(s.last_point), project(s.final_status.actual), "");
  o << "</svg>\n";
  return o.str();
}

namespace {

// ---- time plots ----

struct Series {
  std::string name, colour;
  std::vector<double> lo, hi;  // per bucket
};

std::string render_time_plot(const std::string& css_class, const std::string& label, const std::string& unit,
                             const std::vector<double>& t, const std::vector<Series>& series, bool symmetric) {
  constexpr double W = 1000, H = 250, L = 64, R = 16, T = 14, B = 36;
  std::ostringstream o;
  o << "<svg class=\"" << css_class << "\" xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 " << W << " " << H
    << "\" role=\"img\" aria-label=\"" << escape(label) << "\">\n";
  o << "<rect width=\"" << W << "\" height=\"" << H << "\" fill=\"#ffffff\"/>\n";
  const double t_end = t.empty() ? 1.0 : std::max(t.back(), 1e-6);
  double ymin = 0.0, ymax = 0.0;
  for (const Series& s : series) {
    for (double v : s.lo) ymin = std::min(ymin, v);
    for (double v : s.hi) ymax = std::max(ymax, v);
  }
  if (symmetric) {
    const double m = std::max(std::fabs(ymin), std::fabs(ymax));
    ymin = -m;
    ymax = m;
  }
  if (ymax - ymin <= 0.0) ymax = ymin + 1.0;
  const double ystep = nice_step(ymax - ymin, 5);
  ymin = std::floor(ymin / ystep + 1e-9) * ystep;
  ymax = std::ceil(ymax / ystep - 1e-9) * ystep;
  const double pw = W - L - R, ph = H - T - B;
  auto X = [&](double tv) { return L + tv / t_end * pw; };
  auto Y = [&](double v) { return T + (ymax - v) / (ymax - ymin) * ph; };

  // grid and ticks
  o << "<g font-size=\"11\" fill=\"#5b6475\">\n";
  const int yd = decimals_for(ystep);
  for (double v = ymin; v <= ymax + ystep * 0.5; v += ystep) {
    o << "<line x1=\"" << L << "\" x2=\"" << W - R << "\" y1=\"" << f1(Y(v)) << "\" y2=\"" << f1(Y(v)) << "\" stroke=\""
      << (std::fabs(v) < ystep * 1e-6 ? "#9aa2b1" : "#e6e9ef") << "\"/>";
    o << "<text x=\"" << L - 6 << "\" y=\"" << f1(Y(v) + 4) << "\" text-anchor=\"end\">" << fixed(v, yd) << "</text>\n";
  }
  const double tstep = nice_step(t_end, 10);
  const int td = decimals_for(tstep);
  for (double tv = 0.0; tv <= t_end + tstep * 1e-6; tv += tstep) {
    o << "<line x1=\"" << f1(X(tv)) << "\" x2=\"" << f1(X(tv)) << "\" y1=\"" << T << "\" y2=\"" << H - B << "\" stroke=\"#eef0f4\"/>";
    o << "<text x=\"" << f1(X(tv)) << "\" y=\"" << H - B + 16 << "\" text-anchor=\"middle\">" << fixed(tv, td) << "</text>\n";
  }
  o << "<text x=\"" << W - R << "\" y=\"" << H - 4 << "\" text-anchor=\"end\">program time, s</text>\n";
  o << "<text x=\"14\" y=\"" << T + ph / 2 << "\" text-anchor=\"middle\" transform=\"rotate(-90 14 " << T + ph / 2 << ")\">"
    << escape(unit) << "</text>\n";
  o << "</g>\n";

  // envelopes: a filled band from min to max and its two edges
  for (const Series& s : series) {
    if (t.empty()) break;
    std::string upper, lower, band;
    for (std::size_t i = 0; i < t.size(); ++i) upper += (i ? " " : "") + f1(X(t[i])) + "," + f1(Y(s.hi[i]));
    for (std::size_t i = 0; i < t.size(); ++i) lower += (i ? " " : "") + f1(X(t[i])) + "," + f1(Y(s.lo[i]));
    band = upper;
    for (std::size_t i = t.size(); i-- > 0;) band += " " + f1(X(t[i])) + "," + f1(Y(s.lo[i]));
    o << "<g class=\"series\" data-name=\"" << escape(s.name) << "\">";
    o << "<polygon points=\"" << band << "\" fill=\"" << s.colour << "\" fill-opacity=\"0.22\" stroke=\"none\"/>";
    o << "<polyline points=\"" << upper << "\" fill=\"none\" stroke=\"" << s.colour << "\" stroke-width=\"1.1\"/>";
    o << "<polyline points=\"" << lower << "\" fill=\"none\" stroke=\"" << s.colour << "\" stroke-width=\"1.1\"/>";
    o << "</g>\n";
  }
  // legend
  if (series.size() > 1) {
    double lx = L + 12;
    for (const Series& s : series) {
      o << "<rect x=\"" << lx << "\" y=\"" << T + 6 << "\" width=\"14\" height=\"10\" fill=\"" << s.colour << "\"/><text x=\""
        << lx + 19 << "\" y=\"" << T + 15 << "\" font-size=\"12\" fill=\"#333\">" << escape(s.name) << "</text>";
      lx += 70;
    }
    o << "\n";
  }
  if (t.empty()) {
    o << "<text x=\"" << W / 2 << "\" y=\"" << H / 2 << "\" font-size=\"14\" fill=\"#777\" text-anchor=\"middle\">no trace</text>\n";
  }
  o << "</svg>\n";
  return o.str();
}

struct Row {
  std::string label, value, note;
};

std::string css() {
  return R"(body{margin:0;background:#f3f4f7;color:#1d2330;font:14px/1.45 system-ui,-apple-system,"Segoe UI",Roboto,"DejaVu Sans",sans-serif}
main{max-width:1180px;margin:0 auto;padding:22px 20px 40px}
header{display:flex;align-items:baseline;gap:14px;flex-wrap:wrap;margin-bottom:4px}
h1{font-size:22px;margin:0;font-weight:650;word-break:break-all}
h2{font-size:15px;margin:0 0 8px;font-weight:650;color:#2b3345}
.sub{color:#5b6475;margin:0 0 16px}
.badge{display:inline-block;padding:2px 10px;border-radius:11px;font-weight:600;font-size:13px}
.ok{background:#d9f2e1;color:#14602f}.bad{background:#fbdcdc;color:#8c1d1d}
.grid{display:grid;grid-template-columns:minmax(0,1.45fr) minmax(0,1fr);gap:16px;align-items:start}
.card{background:#fff;border-radius:10px;box-shadow:0 1px 3px rgba(20,30,50,.12);padding:14px 16px;margin-bottom:16px}
.card.dark{background:#161a24;padding:8px}
.card.dark h2{color:#d7dcea;margin:6px 8px 2px}
.card.dark p{color:#8c96ad;margin:0 8px 6px;font-size:12.5px}
svg{display:block;width:100%;height:auto}
table{border-collapse:collapse;width:100%}
th{text-align:left;font-weight:500;color:#4a5266;padding:5px 8px 5px 0;vertical-align:top;white-space:nowrap}
td{padding:5px 0;vertical-align:top}
tr+tr th,tr+tr td{border-top:1px solid #eceef3}
tr.group th{padding-top:12px;color:#1d2330;font-weight:650;border-top:none}
.n{font-variant-numeric:tabular-nums;font-weight:600}
.note{color:#6b7385;font-size:12.5px}
.ax{display:inline-block;min-width:1.1em;font-weight:650}
.fx{color:#d1495b}.fy{color:#2a9d58}.fz{color:#2f6fd0}
footer{color:#6b7385;font-size:12.5px;margin-top:8px}
@media (max-width:900px){.grid{grid-template-columns:1fr}}
)";
}

std::string axes3(const std::string& id, const Vec3& v_mm, double factor, int decimals, const std::string& unit) {
  std::string s;
  const char* cls[3] = {"fx", "fy", "fz"};
  for (int i = 0; i < 3; ++i) {
    if (i) s += " &nbsp; ";
    s += std::string("<span class=\"ax ") + cls[i] + "\">" + axis_name(i) + "</span> " +
         num(id + "-" + static_cast<char>('x' + i), fixed(v_mm[static_cast<std::size_t>(i)] * factor, decimals));
  }
  return s + " " + unit;
}

std::string xyz(const std::string& id, const Vec3& v) {
  return "X " + num(id + "-x", fixed(v[0], 4)) + " &nbsp;Y " + num(id + "-y", fixed(v[1], 4)) + " &nbsp;Z " +
         num(id + "-z", fixed(v[2], 4)) + " mm";
}

}  // namespace

std::string render_report_html(const ReportPage& page) {
  const RunSummary& s = page.summary;
  const Status& st = s.final_status;
  const bool ok = s.end == "completed";
  const std::string name = std::filesystem::path(s.program).filename().string();

  std::vector<std::pair<std::string, std::vector<Row>>> groups;
  // time
  {
    std::vector<Row> r;
    const std::string m = hms(st.program_time_s);
    r.push_back({"machine time", num("machine-time", fixed(st.program_time_s, 3)) + " s" + (m.empty() ? "" : " (" + m + ")"),
                 "program start to end on the machine's own clock"});
    r.push_back({"feed time L/F", num("feed-time", fixed(s.feed_length_time_s, 3)) + " s",
                 "each feed move's length over its programmed feed, summed: no acceleration, no rapids"});
    if (s.feed_length_time_s > 0.0) {
      r.push_back({"machine / feed time", num("time-ratio", fixed(st.program_time_s / s.feed_length_time_s, 3)), ""});
    }
    std::string wall = num("wall-time", fixed(s.wall_time_s, 3)) + " s, " + escape(s.clock) + " clock";
    if (s.clock == "virtual" && s.wall_time_s > 0.0) {
      wall += " (" + num("replay-speed", fixed(st.program_time_s / s.wall_time_s, 0)) + "× real time)";
    }
    r.push_back({"wall time", wall, "what the replay took on this computer"});
    groups.push_back({"Time", r});
  }
  // program
  {
    std::vector<Row> r;
    r.push_back({"lines / moves", num("lines", std::to_string(s.lines)) + " lines, " + num("moves", std::to_string(s.moves)) + " moves",
                 s.warnings ? std::to_string(s.warnings) + " warning(s) from the check" : ""});
    r.push_back({"blocks", num("blocks-sent", std::to_string(s.blocks_sent)) + " sent, " +
                               num("blocks-done", std::to_string(st.blocks_done)) + " done",
                 ""});
    r.push_back({"junctions", num("junction-flows", std::to_string(st.junction_flows)) + " passed without stopping, " +
                                  num("junction-stops", std::to_string(st.junction_stops)) + " stops",
                 std::string("contouring ") + (s.contouring_at_start ? "on (M21)" : "off (M22)") + " at start, angle " +
                     fixed(s.contouring_angle_deg, 1) + "°; M21/M22 in the program override" +
                     (s.corner_tolerance_mm > 0.0
                          ? "; corner tolerance " + num("corner-tolerance", fixed(s.corner_tolerance_mm * 1000.0, 1)) +
                                " µm: under M21 corners are passed at the junction-deviation speed and runs of collinear "
                                "G1 moves are merged into one block"
                          : std::string())});
    groups.push_back({"Program", r});
  }
  // accuracy
  {
    std::vector<Row> r;
    r.push_back({"max following error", axes3("ferr-max", st.max_following_error, 1000.0, 2, "µm"), "setpoint − encoder"});
    r.push_back({"RMS following error", axes3("ferr-rms", rms_following_error(st), 1000.0, 2, "µm"),
                 "over " + std::to_string(st.program_cycles) + " cycles"});
    r.push_back({"contour error", "max " + num("contour-max", fixed(st.max_contour_error * 1000.0, 2)) + " µm, RMS " +
                                      num("contour-rms", fixed(rms_contour_error(st) * 1000.0, 2)) + " µm",
                 "distance of the measured position from the programmed path (feed moves)"});
    groups.push_back({"Accuracy", r});
  }
  // real time
  {
    std::vector<Row> r;
    r.push_back({"ring underruns", num("underruns", std::to_string(st.underruns)),
                 "cycles that wanted a block and found the 4-slot ring empty"});
    r.push_back({"rt compute", "p99 " + num("rt-compute-p99", fixed(st.timing.compute_p99_us, 2)) + " µs, max " +
                                   num("rt-compute-max", fixed(st.timing.compute_max_us, 2)) + " µs",
                 "of the " + fixed(1e6 / std::max(s.cycle_hz, 1.0), 0) + " µs cycle"});
    r.push_back({"rt wake-up", "p99 " + num("rt-wake-p99", fixed(st.timing.wake_p99_us, 1)) + " µs, max " +
                                   num("rt-wake-max", fixed(st.timing.wake_max_us, 1)) + " µs, " +
                                   num("rt-overruns", std::to_string(st.timing.overruns)) + " overruns",
                 s.clock == "virtual" ? "virtual clock: the loop does not sleep, so there is no wake-up latency" : ""});
    r.push_back({"host slot refill", "p50 " + num("refill-p50", fixed(s.refill_p50_us, 1)) + " µs, p99 " +
                                         num("refill-p99", fixed(s.refill_p99_us, 1)) + " µs, max " +
                                         num("refill-max", fixed(s.refill_max_us, 1)) + " µs",
                 "from the rt freeing a slot to the host filling it, " + std::to_string(s.refill_count) + " refills"});
    groups.push_back({"Real time", r});
  }
  // geometry
  {
    std::vector<Row> r;
    r.push_back({"transform", "machine = " + num("scale", fixed(s.transform.scale, 6)) + " · program + (" +
                                  num("offset-x", fixed(s.transform.offset[0], 4)) + ", " +
                                  num("offset-y", fixed(s.transform.offset[1], 4)) + ", " +
                                  num("offset-z", fixed(s.transform.offset[2], 4)) + ") mm",
                 s.transform.scale < 1.0 ? "scaled down by --fit to the travel" : "work offset"});
    r.push_back({"final tool position", xyz("final", st.actual), "measured (encoder), machine coordinates"});
    r.push_back({"last programmed point", xyz("last-point", s.last_point), "after offset and scale"});
    r.push_back({"distance at the end", num("final-deviation", fixed(norm(st.actual - s.last_point) * 1000.0, 2)) + " µm", ""});
    groups.push_back({"Geometry", r});
  }

  std::ostringstream o;
  o << "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
    << "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n"
    << "<title>pcnc run report: " << escape(name) << "</title>\n<style>\n"
    << css() << "</style>\n</head>\n<body>\n<main>\n";
  o << "<header><h1>" << escape(name) << "</h1><span class=\"badge " << (ok ? "ok" : "bad") << "\" id=\"result\">"
    << escape(s.end) << "</span></header>\n";
  o << "<p class=\"sub\">pcnc run report · " << escape(s.program) << " · machine " << escape(s.machine) << " ("
    << escape(s.config_path) << ")";
  if (!s.message.empty()) o << "<br><strong>" << escape(s.message) << "</strong>";
  o << "</p>\n";

  o << "<div class=\"grid\">\n<div>\n<section class=\"card dark\"><h2>Tool path (measured), isometric</h2>\n"
    << "<p>Machine coordinates. Feed moves coloured by commanded path speed, rapids dashed.";
  if (page.has_trace) {
    o << " " << page.trace.path.size() << " points, kept " << fixed(page.trace.path_tolerance_mm * 1000.0, 0)
      << " µm apart or more.";
  }
  o << "</p>\n" << render_toolpath_svg(page) << "</section>\n";
  o << "<section class=\"card dark\"><h2>Top view (X–Y)</h2>\n<p>Looking down Z, same colours; grid in machine millimetres.</p>\n"
    << render_top_view_svg(page) << "</section>\n</div>\n";

  o << "<section class=\"card\"><h2>Figures</h2>\n<table>\n";
  for (const auto& [title, rows] : groups) {
    o << "<tr class=\"group\"><th colspan=\"2\">" << title << "</th></tr>\n";
    for (const Row& r : rows) {
      o << "<tr><th>" << r.label << "</th><td>" << r.value;
      if (!r.note.empty()) o << "<br><span class=\"note\">" << r.note << "</span>";
      o << "</td></tr>\n";
    }
  }
  o << "</table>\n</section>\n</div>\n";

  // time plots
  std::vector<double> t;
  Series speed{"speed", "#3b5bdb", {}, {}};
  Series fe[3] = {{"X", kAxisColour[0], {}, {}}, {"Y", kAxisColour[1], {}, {}}, {"Z", kAxisColour[2], {}, {}}};
  if (page.has_trace) {
    for (const TraceBucket& b : page.trace.buckets) {
      t.push_back((b.t0 + b.t1) / 2);
      speed.lo.push_back(b.speed_min);
      speed.hi.push_back(b.speed_max);
      for (std::size_t i = 0; i < 3; ++i) {
        fe[i].lo.push_back(b.ferr_min[i] * 1000.0);
        fe[i].hi.push_back(b.ferr_max[i] * 1000.0);
      }
    }
  }
  o << "<section class=\"card\"><h2>Path speed over time</h2>\n"
    << render_time_plot("speed-plot", "path speed over time", "commanded path speed, mm/s", t, {speed}, false);
  o << "<p class=\"note\">Band: minimum to maximum within each of " << t.size()
    << " time slices; the line dips where the path stops or slows at a junction.</p></section>\n";
  o << "<section class=\"card\"><h2>Following error over time</h2>\n"
    << render_time_plot("ferr-plot", "following error over time", "following error, µm", t, {fe[0], fe[1], fe[2]}, true);
  o << "<p class=\"note\">Setpoint minus encoder per axis, minimum to maximum within each time slice.</p></section>\n";

  o << "<footer>Written by pcnc after both processes ended, from the host's run summary";
  if (page.has_trace) o << " and " << page.trace.rows << " trace rows (" << page.trace.program_rows << " in the program)";
  else if (!page.trace_note.empty()) o << "; no trace: " << escape(page.trace_note);
  o << ". Self-contained: no scripts, nothing loaded from the network.</footer>\n";
  o << "</main>\n</body>\n</html>\n";
  return o.str();
}

void build_report_file(const std::string& summary_path, const std::string& trace_path, const std::string& html_path) {
  ReportPage page;
  page.summary = read_run_summary(summary_path);
  if (!trace_path.empty()) {
    // which source lines hold rapids: recorded from the blocks the run's check made (the
    // blocks that were sent), so the report runs no front end of its own
    const std::vector<LineRange>& rapid = page.summary.rapid_lines;
    DigestOptions d;
    const Vec3 size = page.summary.max_point - page.summary.min_point;
    d.path_tolerance_mm = std::max(1e-4, std::max({size[0], size[1], size[2]}) / 2000.0);
    d.is_rapid_line = [&rapid](std::uint32_t line) {
      const auto it = std::upper_bound(rapid.begin(), rapid.end(), line,
                                       [](std::uint32_t l, const LineRange& r) { return l < r.first; });
      return it != rapid.begin() && line <= std::prev(it)->last;
    };
    page.trace = digest_trace(trace_path, d);
    page.has_trace = true;
  } else {
    page.trace_note = "the run was made without a trace";
  }
  const std::string html = render_report_html(page);
  std::ofstream f(html_path);
  if (!f) throw std::runtime_error("cannot write the report '" + html_path + "'");
  f << html;
  if (!f.flush()) throw std::runtime_error("cannot write the report '" + html_path + "'");
}

}  // namespace pcnc
