// report_html.cpp — rendering the HTML run report: figures table, isometric tool path and
// time plots as inline SVG (see report_html.hpp).
#include "report/report_html.hpp"
#include "report/path_view_3d.hpp"
#include "report/report_plots.hpp"
#include "report/svg_text.hpp"
#include "report/tool_axis_view.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <future>
#include <iterator>
#include <sstream>
#include <stdexcept>
#include <vector>


namespace pcnc {

namespace {
using namespace svg;


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

}  // namespace

// ---- the tool path ----

namespace {
using namespace svg;

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

// The path through `project` as one <path> per class (rapid, or one of the feed-speed colour
// bins), decimated to what the pixels show: a point closer than `min_px` on screen to the last
// one drawn, in the same class, is left out (the next point far enough, or the class's end,
// still lands exactly). Returns the markup; `*feeds` counts the feed points drawn.
template <typename Project>
std::string path_strokes(const std::vector<ToolPathPoint>& path, double vmax, Project project, double width,
                         std::size_t* feeds = nullptr, double min_px = 0.75) {
  constexpr int kBins = 24;
  auto bin_of = [&](const ToolPathPoint& q) { return std::clamp(static_cast<int>(q.speed / vmax * kBins), 0, kBins - 1); };
  struct Stroke {
    std::string d;
    P2 pen{-1e300, -1e300};  // where its last piece ended
  };
  std::vector<Stroke> strokes(kBins + 1);  // [kBins]: rapids
  std::size_t n_feed = 0;
  P2 last = path.empty() ? P2{} : project(path[0].p);  // the last point drawn (screen)
  int run = -2;                                         // the class of the piece being drawn
  for (std::size_t i = 1; i < path.size(); ++i) {
    const int cls = path[i].rapid ? kBins : bin_of(path[i]);
    const P2 q = project(path[i].p);
    const bool next_same = i + 1 < path.size() && (path[i + 1].rapid ? kBins : bin_of(path[i + 1])) == cls;
    if (cls == run && next_same && std::hypot(q.x - last.x, q.y - last.y) < min_px) continue;
    Stroke& st = strokes[static_cast<std::size_t>(cls)];
    if (cls != run || st.pen.x != last.x || st.pen.y != last.y) {
      st.d += st.d.empty() ? "M" : " M";
      append_xy(st.d, last.x, last.y);
    }
    st.d += ' ';
    append_xy(st.d, q.x, q.y);
    st.pen = q;
    last = q;
    run = cls;
    if (cls != kBins) ++n_feed;
  }
  std::size_t size = 0;
  for (const Stroke& st : strokes) size += st.d.size() + 160;
  std::string o;
  o.reserve(size);
  if (!strokes[kBins].d.empty()) {
    o += "<path class=\"rapid\" stroke=\"#aab3c5\" stroke-opacity=\"0.55\" stroke-width=\"" + fixed(width * 0.6, 2) +
         "\" stroke-dasharray=\"4 3\" d=\"";
    o += strokes[kBins].d;
    o += "\"/>\n";
  }
  for (int b = 0; b < kBins; ++b) {
    if (strokes[static_cast<std::size_t>(b)].d.empty()) continue;
    o += "<path class=\"feed\" stroke=\"" + colour_at((b + 0.5) / kBins) + "\" stroke-width=\"" + fixed(width, 2) + "\" d=\"";
    o += strokes[static_cast<std::size_t>(b)].d;
    o += "\"/>\n";
  }
  if (feeds) *feeds = n_feed;
  return o;
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
    << path_strokes(path, vmax, project, 1.5, &feeds) << "</g>\n";
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
  o << "<!-- " << feeds << " feed points drawn of " << path.size() << " -->\n";
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
    << path_strokes(path, feed_speed_max(path), project, 1.3) << "</g>\n";
  if (!s.comp_contour.empty()) {  // G41/G42: the contour as programmed, over the tool path the trace shows
    o << "<g class=\"comp-contour\" clip-path=\"url(#top-clip)\" fill=\"none\" stroke=\"#ffffff\" stroke-opacity=\"0.8\" "
         "stroke-width=\"1\" stroke-dasharray=\"5 3\">\n";
    for (const std::vector<Vec3>& line : s.comp_contour) {
      if (line.size() < 2) continue;
      std::string points;
      for (const Vec3& p : line) {
        const P2 q = project(p);
        append_xy(points, q.x, q.y);
        points += ' ';
      }
      o << "<polyline points=\"" << points << "\"/>\n";
    }
    o << "</g>\n";
    o << "<text class=\"comp-legend\" x=\"" << L << "\" y=\"" << f1(H - 4) << "\" font-size=\"11\" fill=\"#c9d0de\">"
      << "dashed: programmed contour; coloured: the compensated tool centre path (tool diameter "
      << fixed(s.comp_tool_diameter_mm, 3) << " mm)</text>\n";
  }
  o << end_markers(project(s.last_point), project(s.final_status.actual), "");
  o << "</svg>\n";
  return o.str();
}

namespace {
using namespace svg;

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

// "Where the time went": seconds per cause (adding up to the machine time) and the lines
// that lost the most time against cruising at their programmed speed.
std::string render_time_causes(const ReportPage& page) {
  const RunSummary& s = page.summary;
  std::ostringstream o;
  o << "<section class=\"card\" id=\"time-causes\"><h2>Where the time went</h2>\n";
  if (s.time_by_cause.empty()) {
    o << "<p class=\"note\">No attribution: " << (page.has_trace ? "the summary holds no plan" : "no trace") << ".</p></section>\n";
    return o.str();
  }
  std::vector<std::pair<std::string, double>> rows(s.time_by_cause.begin(), s.time_by_cause.end());
  std::sort(rows.begin(), rows.end(), [](const auto& a, const auto& b) { return a.second > b.second; });
  const double total = std::max(s.final_status.program_time_s, 1e-12);
  o << "<table class=\"causes\">\n<tr><th>cause</th><th>time, s</th><th>share</th></tr>\n";
  for (const auto& [key, sec] : rows) {
    TimeCause c = TimeCause::kOther;
    parse_time_cause(key, c);
    o << "<tr><th><span style=\"display:inline-block;width:11px;height:11px;margin-right:6px;background:" << time_cause_colour(c)
      << "\"></span>" << escape(time_cause_label(c)) << "</th><td>" << num("cause-" + key, fixed(sec, 3)) << "</td><td>"
      << fixed(100.0 * sec / total, 1) << " %</td></tr>\n";
  }
  o << "</table>\n";
  if (!page.slowest.empty()) {
    o << "<h2 style=\"margin-top:14px\">Slowest stretches</h2>\n<table class=\"slowest\">\n"
      << "<tr><th>line</th><th>time, s</th><th>not at F or rapid, s</th><th>mostly</th></tr>\n";
    for (const SlowStretch& x : page.slowest) {
      o << "<tr><th>" << x.line << "</th><td>" << fixed(x.time_s, 3) << "</td><td>" << fixed(x.lost_s, 3) << "</td><td>"
        << escape(time_cause_label(x.cause)) << " (" << fixed(x.cause_s, 3) << " s)";
      if (x.angle_deg >= 0.0) o << ", turn " << fixed(x.angle_deg, 1) << "°";
      o << "</td></tr>\n";
    }
    o << "</table>\n";
  }
  o << "<p class=\"note\">Each trace row (one cycle) goes to one cause, from the plan the check recorded for its "
       "line: cruising at the block's limit (F, F clamped to the machine maximum, an axis's velocity, an arc's "
       "centripetal limit, a curve's schedule, rapid), speeding up or slowing down (to a junction stop, a corner, a start "
       "or end, or between speeds at an axis's acceleration), steady below the limit (override), dwell, pause.</p></section>\n";
  return o.str();
}

}  // namespace

std::string render_report_html(const ReportPage& page) {
  const RunSummary& s = page.summary;
  const Status& st = s.final_status;
  const bool ok = s.end == "completed";
  const std::string name = std::filesystem::path(s.program).filename().string();
  // the interactive 3D view (the path thinned, packed as a binary record, gzipped: about a third
  // of the page's time) is built on a second thread while the rest of the page is drawn; the
  // page is the same, put together in its fixed order
  std::string no_view;
  std::future<std::string> view3d;
  if (page.has_trace && page.view3d) {
    view3d = std::async(std::launch::async, [&page, &no_view] {
      return render_path_view_3d(page.trace.path, page.view3d_options, &no_view);
    });
  }

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
                     (s.path_tolerance_mm > 0.0
                          ? "; path tolerance " + num("path-tolerance", fixed(s.path_tolerance_mm * 1000.0, 1)) +
                                " µm: under M21 corners are passed at the junction-deviation speed and runs of short "
                                "G1 moves are smoothed into curves"
                          : std::string())});
    if (s.comp_entries > 0) {
      r.push_back({"cutter compensation",
                   "tool diameter " + num("comp-tool-diameter", fixed(s.comp_tool_diameter_mm, 4)) + " mm; " +
                       num("comp-moves-in", std::to_string(s.comp_moves_in)) + " moves offset (biarcs counted) → " +
                       num("comp-moves-out", std::to_string(s.comp_moves_out)) + " tool moves",
                   "G41/G42 in " + std::to_string(s.comp_entries) +
                       " entr" + (s.comp_entries == 1 ? "y" : "ies") +
                       (s.comp_biarcs > 0 ? "; " + std::to_string(s.comp_biarcs) + " biarcs replaced " +
                                                std::to_string(s.comp_moves_replaced) + " programmed moves"
                                          : std::string()) +
                       "; the top view draws the programmed contour dashed over the tool centre path"});
    }
    if (s.pauses > 0) {
      std::string lines;
      for (std::size_t i = 0; i < s.pause_lines.size(); ++i) lines += (i ? ", " : "") + std::to_string(s.pause_lines[i]);
      if (s.pauses > s.pause_lines.size()) lines += ", …";
      r.push_back({"pauses", num("pauses", std::to_string(s.pauses)) + " M0/M1 on line" + (s.pauses > 1 ? "s " : " ") + lines,
                   s.pauses_mode == "ask" ? "the machine waited at rest for the operator (pcnc run --pauses ask)"
                                          : "the machine came to rest there and went on (pcnc run --pauses continue)"});
    }
    r.push_back({"smoothing",
                 num("smoothed-moves", std::to_string(s.smoothed_moves)) + " G1 moves into " +
                     num("smoothed-blocks", std::to_string(s.smoothed_blocks)) + " blocks (" +
                     num("smoothed-curves", std::to_string(s.smoothed_curves)) + " curves)",
                 "the commanded path keeps at most " +
                     num("path-deviation", fixed(s.max_path_deviation_mm * 1000.0, 2)) +
                     " µm from the programmed moves (measured on each curve)" +
                     (s.smoothed_curves > 0 ? "; fitted to a tolerance of " +
                                                  (s.smoothing_max_tolerance_mm > s.smoothing_min_tolerance_mm
                                                       ? fixed(s.smoothing_min_tolerance_mm * 1000.0, 1) + "–"
                                                       : std::string()) +
                                                  num("smoothing-tolerance", fixed(s.smoothing_max_tolerance_mm * 1000.0, 1)) + " µm"
                                            : std::string())});
    if (s.packed_arcs > 0) {
      r.push_back({"arc packing",
                   num("packed-arcs", std::to_string(s.packed_arcs)) + " arcs into " +
                       num("packed-blocks", std::to_string(s.packed_blocks)) + " blocks (" +
                       num("packed-curves", std::to_string(s.packed_curves)) + (s.packed_curves == 1 ? " curve)" : " curves)"),
                   "chains of short arcs as exact rational curves, so the ring holds enough of them: at most " +
                       num("packed-deviation", fixed(s.packed_max_deviation_mm * 1000.0, 3)) +
                       " µm from the programmed arcs (measured on each curve)"});
    }
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
    << css() << path_view_3d_css() << "</style>\n</head>\n<body>\n<main>\n";
  o << "<header><h1>" << escape(name) << "</h1><span class=\"badge " << (ok ? "ok" : "bad") << "\" id=\"result\">"
    << escape(s.end) << "</span></header>\n";
  o << "<p class=\"sub\">pcnc run report · " << escape(s.program) << " · machine " << escape(s.machine) << " ("
    << escape(s.config_path) << ")";
  if (!s.message.empty()) o << "<br><strong>" << escape(s.message) << "</strong>";
  o << "</p>\n";

  o << "<div class=\"grid\">\n<div>\n<section class=\"card dark\"><h2>Tool path (measured)</h2>\n"
    << "<p>Machine coordinates. Feed moves coloured by commanded path speed, rapids grey.";
  if (page.has_trace) {
    o << " " << page.trace.path.size() << " points, kept " << fixed(page.trace.path_tolerance_mm * 1000.0, 0)
      << " µm apart or more.";
  }
  o << "</p>\n";
  const auto view3d_at = o.tellp();  // the 3D view goes here when its thread is done (below)
  o << "<div class=\"toolpath-static\">" << render_toolpath_svg(page) << "</div></section>\n";
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
  const TraceDigest no_trace;
  const TraceDigest& d = page.has_trace ? page.trace : no_trace;
  const TimePlot speed = speed_plot(d);
  o << "<section class=\"card\"><h2>Path speed over time</h2>\n" << render_time_plot(speed);
  o << "<p class=\"note\">Feed moves on their own scale, minimum to maximum within each of " << speed.t.size()
    << " time slices (at most one per pixel column); slices with a rapid are shaded, its speed is off this scale. The dashed line "
       "is the planned speed: the programmed F, or the limit that caps it. Under the time axis the program line running "
       "then"
    << (d.classified ? ", and a band coloured by the cause most of the slice's time went to (table below)" : "")
    << ".</p></section>\n";
  o << render_time_causes(page);
  o << "<section class=\"card\"><h2>Following error over time</h2>\n" << render_time_plot(ferr_plot(d));
  o << "<p class=\"note\">Setpoint minus encoder per axis, minimum to maximum within each time slice.</p></section>\n";
  if (!d.joints.letters.empty()) {
    // a 5-axis trace: the tool seen from the workpiece, and the rotary joints' following error
    const JointDigest& j = d.joints;
    o << "<section class=\"card dark\" id=\"tool-axis\"><h2>Tool tip and tool axis (workpiece coordinates)</h2>\n<p>"
      << "From the forward kinematics of the commanded joints with the machine's config and a tool length of "
      << fixed(page.summary.tcp_tool_length_mm, 3) << " mm (the program's under tool-centre-point control): the tool tip's path ("
      << fixed(j.tip_path_mm, 1) << " mm) and the tool axis every " << fixed(j.axis_every_mm, 2) << " mm of it ("
      << j.marks.size() << " marks), drawn from the tip towards the spindle.</p>\n"
      << render_tool_axis_svg(j) << "</section>\n";
    o << "<section class=\"card\" id=\"joint-ferr\"><h2>Rotary joints' following error over time</h2>\n"
      << render_time_plot(joint_ferr_plot(j)) << "<p class=\"note\">Setpoint minus encoder per rotary joint, in "
      << "millidegrees, minimum to maximum within each time slice. Largest:";
    for (std::size_t i = 0; i < j.letters.size() && i < kMaxTraceJoints; ++i)
      o << (i ? ", " : " ") << j.letters[i] << " " << fixed(j.ferr_abs_max[i] * 1000.0, 2) << " m°";
    o << ".</p></section>\n";
  }

  std::string view3d_text;
  if (view3d.valid()) {
    view3d_text = view3d.get();
    if (!no_view.empty()) view3d_text += "<p>No interactive view: " + escape(no_view) + ".</p>\n";
  }
  o << "<footer>Written by pcnc after both processes ended, from the host's run summary";
  if (page.has_trace) o << " and " << page.trace.rows << " trace rows (" << page.trace.program_rows << " in the program)";
  else if (!page.trace_note.empty()) o << "; no trace: " << escape(page.trace_note);
  o << ". Self-contained: one file, nothing loaded from the network"
    << (page.has_trace && page.view3d && no_view.empty() ? "; the 3D view runs three.js (Debian's libjs-three), inlined" : "")
    << ".</footer>\n";
  o << "</main>\n</body>\n</html>\n";
  std::string html = o.str();
  html.insert(static_cast<std::size_t>(view3d_at), view3d_text);
  return html;
}

}  // namespace pcnc
