// report_plots.cpp — the report's time plots as inline SVG (see report_plots.hpp).
#include "report/report_plots.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "report/svg_text.hpp"
#include "report/time_causes.hpp"

namespace pcnc {
namespace {

using namespace svg;

const char* kAxisColours[3] = {"#d1495b", "#2a9d58", "#2f6fd0"};

// The pieces of a series, [first, last) bucket index ranges: split where a bucket is not valid.
std::vector<std::pair<std::size_t, std::size_t>> pieces(std::size_t n, const std::vector<bool>& valid) {
  std::vector<std::pair<std::size_t, std::size_t>> out;
  for (std::size_t i = 0; i < n;) {
    if (!valid.empty() && !valid[i]) {
      ++i;
      continue;
    }
    std::size_t j = i + 1;
    while (j < n && (valid.empty() || valid[j])) ++j;
    out.push_back({i, j});
    i = j;
  }
  return out;
}

// The points "x,y x,y ..." of buckets [first, last) of one edge, forwards or backwards.
template <typename X, typename Y>
void append_points(std::string& out, const std::vector<double>& t, const std::vector<double>& v, std::size_t first,
                   std::size_t last, bool backwards, X x, Y y) {
  for (std::size_t k = first; k < last; ++k) {
    const std::size_t i = backwards ? last - 1 - (k - first) : k;
    if (k > first) out += ' ';
    append_xy(out, x(t[i]), y(v[i]));
  }
}

}  // namespace

std::string render_time_plot(const TimePlot& p) {
  const bool band = !p.band.empty(), lines = !p.line_lo.empty();
  constexpr double W = 1000, L = 64, R = 16, T = 14, PH = 200;
  const double B = 36 + (band ? 16 : 0) + (lines ? 22 : 0);
  const double H = T + PH + B;
  std::ostringstream o;
  o << "<svg class=\"" << p.css_class << "\" xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 " << W << " " << H
    << "\" role=\"img\" aria-label=\"" << escape(p.label) << "\">\n";
  o << "<rect width=\"" << W << "\" height=\"" << H << "\" fill=\"#ffffff\"/>\n";
  const auto& t = p.t;
  const double t_end = t.empty() ? 1.0 : std::max(t.back(), 1e-6);
  double ymin = 0.0, ymax = 0.0;
  for (const PlotSeries& s : p.series) {
    for (std::size_t i = 0; i < s.lo.size(); ++i) {
      if (!s.valid.empty() && !s.valid[i]) continue;
      ymin = std::min(ymin, s.lo[i]);
      ymax = std::max(ymax, s.hi[i]);
    }
  }
  for (double v : p.reference) ymax = std::max(ymax, v);
  if (p.symmetric) ymin = -(ymax = std::max(std::fabs(ymin), std::fabs(ymax)));
  if (ymax - ymin <= 0.0) ymax = ymin + 1.0;
  const double ystep = nice_step(ymax - ymin, 5);
  ymin = std::floor(ymin / ystep + 1e-9) * ystep;
  ymax = std::ceil(ymax / ystep - 1e-9) * ystep;
  const double pw = W - L - R;
  auto X = [&](double tv) { return L + tv / t_end * pw; };
  auto Y = [&](double v) { return T + (ymax - std::clamp(v, ymin, ymax)) / (ymax - ymin) * PH; };
  const double col = t.empty() ? 0.0 : pw / static_cast<double>(t.size());  // one bucket's width

  // marked buckets (rapids) first, under everything
  if (!p.marked.empty()) {
    o << "<g class=\"marked\" fill=\"#e3e6ee\">";
    for (std::size_t i = 0; i < t.size() && i < p.marked.size(); ++i) {
      if (p.marked[i]) o << "<rect x=\"" << f1(X(t[i]) - col / 2) << "\" y=\"" << T << "\" width=\"" << f1(col + 0.3) << "\" height=\"" << PH << "\"/>";
    }
    o << "</g>\n";
  }
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
  const double axis_y = T + PH;
  for (double tv = 0.0; tv <= t_end + tstep * 1e-6; tv += tstep) {
    o << "<line x1=\"" << f1(X(tv)) << "\" x2=\"" << f1(X(tv)) << "\" y1=\"" << T << "\" y2=\"" << axis_y << "\" stroke=\"#eef0f4\"/>";
    o << "<text x=\"" << f1(X(tv)) << "\" y=\"" << axis_y + 16 << "\" text-anchor=\"middle\">" << fixed(tv, td) << "</text>\n";
    if (lines && !t.empty()) {
      // the program line running at that time: the bucket whose middle is nearest
      const auto k = std::min(t.size() - 1, static_cast<std::size_t>(std::lround(tv / t_end * static_cast<double>(t.size()) - 0.5 < 0 ? 0 : tv / t_end * static_cast<double>(t.size()) - 0.5)));
      o << "<text class=\"line-tick\" x=\"" << f1(X(tv)) << "\" y=\"" << H - 22 << "\" text-anchor=\"middle\" fill=\"#7a8296\">"
        << p.line_lo[k] << "</text>\n";
    }
  }
  o << "<text x=\"" << W - R << "\" y=\"" << H - 4 << "\" text-anchor=\"end\">program time, s" << (lines ? "; above it the program line" : "")
    << "</text>\n";
  o << "<text x=\"14\" y=\"" << T + PH / 2 << "\" text-anchor=\"middle\" transform=\"rotate(-90 14 " << T + PH / 2 << ")\">"
    << escape(p.unit) << "</text>\n";
  o << "</g>\n";

  // envelopes: a filled band from min to max and its two edges
  for (const PlotSeries& s : p.series) {
    if (t.empty()) break;
    std::string g = "<g class=\"series\" data-name=\"" + escape(s.name) + "\">";
    for (const auto& [first, last] : pieces(t.size(), s.valid)) {
      std::string upper, lower, back;
      append_points(upper, t, s.hi, first, last, false, X, Y);
      append_points(lower, t, s.lo, first, last, false, X, Y);
      append_points(back, t, s.lo, first, last, true, X, Y);
      // the band: the upper edge forwards, the lower edge backwards
      g += "<polygon points=\"" + upper + " " + back + "\" fill=\"" + s.colour + "\" fill-opacity=\"0.22\" stroke=\"none\"/>";
      g += "<polyline points=\"" + upper + "\" fill=\"none\" stroke=\"" + s.colour + "\" stroke-width=\"1.1\"/>";
      g += "<polyline points=\"" + lower + "\" fill=\"none\" stroke=\"" + s.colour + "\" stroke-width=\"1.1\"/>";
    }
    o << g << "</g>\n";
  }
  // the reference: a dashed step line
  if (!p.reference.empty() && !t.empty()) {
    std::string d;
    bool pen = false;
    for (std::size_t i = 0; i < t.size() && i < p.reference.size(); ++i) {
      if (p.reference[i] <= 0.0) {
        pen = false;
        continue;
      }
      const double x0 = X(t[i]) - col / 2, x1 = X(t[i]) + col / 2, y = Y(p.reference[i]);
      d += pen ? " L" : " M";
      append_xy(d, x0, y);
      d += " L";
      append_xy(d, x1, y);
      pen = true;
    }
    o << "<path class=\"reference\" d=\"" << d << "\" fill=\"none\" stroke=\"#1d2330\" stroke-width=\"1\" stroke-dasharray=\"5 3\"/>\n";
  }
  // the cause band under the axis
  if (band) {
    o << "<g class=\"cause-band\">";
    const double by = axis_y + 22;
    for (std::size_t i = 0; i < t.size() && i < p.band.size(); ++i) {
      if (p.band[i].empty()) continue;
      o << "<rect x=\"" << f1(X(t[i]) - col / 2) << "\" y=\"" << by << "\" width=\"" << f1(col + 0.3) << "\" height=\"10\" fill=\""
        << p.band[i] << "\"/>";
    }
    o << "</g>\n";
  }
  // legend
  double lx = L + 12;
  auto legend = [&](const std::string& swatch, const std::string& name) {
    o << swatch << "<text x=\"" << lx + 19 << "\" y=\"" << T + 15 << "\" font-size=\"12\" fill=\"#333\">" << escape(name) << "</text>";
    lx += 34 + 7.0 * static_cast<double>(name.size());
  };
  auto box = [&](const std::string& colour) {
    return "<rect x=\"" + f1(lx) + "\" y=\"" + f1(T + 6) + "\" width=\"14\" height=\"10\" fill=\"" + colour + "\"/>";
  };
  if (p.series.size() > 1 || !p.reference.empty() || !p.marked.empty()) {
    for (const PlotSeries& s : p.series) legend(box(s.colour), s.name);
    if (!p.reference.empty()) {
      legend("<line x1=\"" + f1(lx) + "\" x2=\"" + f1(lx + 14) + "\" y1=\"" + f1(T + 11) + "\" y2=\"" + f1(T + 11) +
                 "\" stroke=\"#1d2330\" stroke-dasharray=\"5 3\"/>",
             p.reference_name);
    }
    if (!p.marked.empty()) legend(box("#e3e6ee"), p.marked_name);
    o << "\n";
  }
  if (t.empty()) {
    o << "<text x=\"" << W / 2 << "\" y=\"" << (T + PH / 2) << "\" font-size=\"14\" fill=\"#777\" text-anchor=\"middle\">no trace</text>\n";
  }
  o << "</svg>\n";
  return o.str();
}

TimePlot speed_plot(const TraceDigest& d) {
  TimePlot p;
  p.css_class = "speed-plot";
  p.label = "path speed of feed moves over time";
  p.unit = "path speed (feed moves), mm/s";
  PlotSeries feed{"feed moves", "#3b5bdb", {}, {}, {}};
  bool any_rapid = false, any_planned = false;
  for (const TraceBucket& b : d.buckets) {
    p.t.push_back((b.t0 + b.t1) / 2);
    feed.lo.push_back(b.feed_rows ? b.feed_speed_min : 0.0);
    feed.hi.push_back(b.feed_rows ? b.feed_speed_max : 0.0);
    feed.valid.push_back(b.feed_rows > 0);
    p.marked.push_back(b.rapid_rows > 0);
    any_rapid = any_rapid || b.rapid_rows > 0;
    p.reference.push_back(b.planned_max);
    any_planned = any_planned || b.planned_max > 0.0;
    p.line_lo.push_back(b.line_min);
    if (d.classified) {
      std::size_t best = 0;
      for (std::size_t c = 1; c < b.cause_rows.size(); ++c) {
        if (b.cause_rows[c] > b.cause_rows[best]) best = c;
      }
      p.band.push_back(b.rows ? time_cause_colour(static_cast<TimeCause>(best)) : "");
    }
  }
  p.series.push_back(std::move(feed));
  if (!any_rapid) p.marked.clear();
  p.marked_name = "rapid (off this scale)";
  if (!any_planned) p.reference.clear();
  p.reference_name = "planned speed (F, or what caps it)";
  return p;
}

TimePlot ferr_plot(const TraceDigest& d) {
  TimePlot p;
  p.css_class = "ferr-plot";
  p.label = "following error over time";
  p.unit = "following error, µm";
  p.symmetric = true;
  for (std::size_t i = 0; i < 3; ++i) p.series.push_back({std::string(1, static_cast<char>('X' + i)), kAxisColours[i], {}, {}, {}});
  for (const TraceBucket& b : d.buckets) {
    p.t.push_back((b.t0 + b.t1) / 2);
    for (std::size_t i = 0; i < 3; ++i) {
      p.series[i].lo.push_back(b.ferr_min[i] * 1000.0);
      p.series[i].hi.push_back(b.ferr_max[i] * 1000.0);
    }
  }
  return p;
}

TimePlot joint_ferr_plot(const JointDigest& d) {
  static const char* kJointColours[kMaxTraceJoints] = {"#e08a1e", "#8e5bd6", "#1aa6b7"};
  TimePlot p;
  p.css_class = "joint-ferr-plot";
  p.label = "rotary joints' following error over time";
  p.unit = "following error, millidegrees";
  p.symmetric = true;
  const std::size_t n = std::min(d.letters.size(), kMaxTraceJoints);
  for (std::size_t i = 0; i < n; ++i) p.series.push_back({std::string(1, d.letters[i]), kJointColours[i], {}, {}, {}});
  for (const JointBucket& b : d.buckets) {
    p.t.push_back((b.t0 + b.t1) / 2);
    for (std::size_t i = 0; i < n; ++i) {
      p.series[i].lo.push_back(b.ferr_min[i] * 1000.0);
      p.series[i].hi.push_back(b.ferr_max[i] * 1000.0);
    }
  }
  return p;
}

}  // namespace pcnc
