// scope_page.cpp — a capture's CSV and HTML plots (see scope_page.hpp).
#include "report/scope_page.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "ipc/status.hpp"
#include "report/report_html.hpp"
#include "report/svg_text.hpp"

namespace pcnc {

namespace {

std::string cell(const std::string& signal, double v) {
  char buf[64];
  if (signal == "state") {
    const int code = static_cast<int>(v);
    if (code >= 0 && code <= static_cast<int>(MachineState::kHostLost)) return to_string(static_cast<MachineState>(code));
    std::snprintf(buf, sizeof buf, "%d", code);
  } else if (signal == "line") {
    std::snprintf(buf, sizeof buf, "%.0f", v);
  } else if (signal == "speed") {
    std::snprintf(buf, sizeof buf, "%.5f", v);
  } else {
    std::snprintf(buf, sizeof buf, "%.7f", v);
  }
  return buf;
}

double nice_step(double range, int target) {
  const double raw = range / target;
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0, 10.0}) {
    if (m * mag >= raw) return m * mag;
  }
  return 10.0 * mag;
}

int decimals_for(double step) { return std::max(0, static_cast<int>(std::ceil(-std::log10(step) - 1e-9))); }

// One plot: a group of signals sharing a unit.
struct Group {
  std::string title, unit;
  double factor = 1.0;  // value in the unit = stored value * factor
  std::vector<std::size_t> cols;
};

const char* colour_of(const std::string& s) {
  if (s.size() > 2 && s.back() == 'x') return s.rfind("cmd", 0) == 0 ? "#f08a98" : "#d1495b";
  if (s.size() > 2 && s.back() == 'y') return s.rfind("cmd", 0) == 0 ? "#7fcf9f" : "#2a9d58";
  if (s.size() > 2 && s.back() == 'z') return s.rfind("cmd", 0) == 0 ? "#8fb2ea" : "#2f6fd0";
  return "#6a4c93";
}

std::string plot(const ScopeRecord& r, const Group& g) {
  constexpr double W = 1000, H = 240, L = 70, R = 16, T = 14, B = 36;
  const double pw = W - L - R, ph = H - T - B;
  const std::size_t n = r.t.size();
  const double t0 = n ? r.t[std::min(r.trigger_row, n - 1)] : 0.0;
  const double xa = n ? (r.t.front() - t0) * 1e3 : 0.0, xb = n ? std::max((r.t.back() - t0) * 1e3, xa + 1e-3) : 1.0;
  double lo = INFINITY, hi = -INFINITY;
  for (std::size_t c : g.cols) {
    for (double v : r.columns[c]) {
      lo = std::min(lo, v * g.factor);
      hi = std::max(hi, v * g.factor);
    }
  }
  if (!(lo <= hi)) lo = 0.0, hi = 1.0;
  if (hi - lo < 1e-9) lo -= 0.5, hi += 0.5;
  const double ys = nice_step(hi - lo, 5);
  lo = std::floor(lo / ys + 1e-9) * ys;
  hi = std::ceil(hi / ys - 1e-9) * ys;
  auto X = [&](double ms) { return L + (ms - xa) / (xb - xa) * pw; };
  auto Y = [&](double v) { return T + (hi - v) / (hi - lo) * ph; };
  std::ostringstream o;
  o << "<section class=\"card\"><h2>" << svg::escape(g.title) << "</h2>\n";
  o << "<svg class=\"scope\" xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 " << W << " " << H << "\" role=\"img\" aria-label=\""
    << svg::escape(g.title) << "\">\n<rect width=\"" << W << "\" height=\"" << H << "\" fill=\"#fff\"/>\n";
  if (!r.trigger.empty() && r.trigger_row > 0) {  // the pre-trigger, shaded
    o << "<rect class=\"pretrigger\" x=\"" << fixed(L, 1) << "\" y=\"" << T << "\" width=\"" << fixed(X(0.0) - L, 1) << "\" height=\""
      << ph << "\" fill=\"#f1f3f8\"/>\n";
  }
  o << "<g font-size=\"11\" fill=\"#5b6475\">\n";
  const int yd = decimals_for(ys);
  for (double v = lo; v <= hi + ys * 0.5; v += ys) {
    o << "<line x1=\"" << L << "\" x2=\"" << W - R << "\" y1=\"" << fixed(Y(v), 1) << "\" y2=\"" << fixed(Y(v), 1)
      << "\" stroke=\"#e6e9ef\"/><text x=\"" << L - 6 << "\" y=\"" << fixed(Y(v) + 4, 1) << "\" text-anchor=\"end\">" << fixed(v, yd)
      << "</text>\n";
  }
  const double xs = nice_step(xb - xa, 10);
  const int xd = decimals_for(xs);
  for (double ms = std::ceil(xa / xs - 1e-9) * xs; ms <= xb + xs * 1e-6; ms += xs) {
    o << "<line x1=\"" << fixed(X(ms), 1) << "\" x2=\"" << fixed(X(ms), 1) << "\" y1=\"" << T << "\" y2=\"" << H - B
      << "\" stroke=\"#eef0f4\"/><text x=\"" << fixed(X(ms), 1) << "\" y=\"" << H - B + 16 << "\" text-anchor=\"middle\">"
      << fixed(ms, xd) << "</text>\n";
  }
  o << "<text x=\"" << W - R << "\" y=\"" << H - 4 << "\" text-anchor=\"end\">"
    << (r.trigger.empty() ? "time from the start, ms" : "time from the trigger, ms") << "</text>\n";
  o << "<text x=\"14\" y=\"" << T + ph / 2 << "\" text-anchor=\"middle\" transform=\"rotate(-90 14 " << T + ph / 2 << ")\">"
    << svg::escape(g.unit) << "</text>\n</g>\n";
  if (!r.trigger.empty()) {
    o << "<line class=\"trigger\" x1=\"" << fixed(X(0.0), 1) << "\" x2=\"" << fixed(X(0.0), 1) << "\" y1=\"" << T << "\" y2=\"" << H - B
      << "\" stroke=\"#e07b00\" stroke-dasharray=\"4 3\"/>\n";
  }
  // each pixel column: min..max of its rows (no peak lost), drawn as a band and its edges
  const std::size_t cols = std::min<std::size_t>(n, static_cast<std::size_t>(pw));
  double lx = L + 10;
  for (std::size_t c : g.cols) {
    const std::string& name = r.signals[c];
    std::string upper, lower;
    for (std::size_t k = 0; k < cols; ++k) {
      const std::size_t a = k * n / cols, b = std::max(a + 1, (k + 1) * n / cols);
      double mn = INFINITY, mx = -INFINITY;
      for (std::size_t i = a; i < b; ++i) {
        mn = std::min(mn, r.columns[c][i] * g.factor);
        mx = std::max(mx, r.columns[c][i] * g.factor);
      }
      const double x = X((r.t[a] - t0) * 1e3);
      upper += (k ? " " : "") + fixed(x, 1) + "," + fixed(Y(mx), 1);
      lower = fixed(x, 1) + "," + fixed(Y(mn), 1) + (k ? " " : "") + lower;
    }
    o << "<g class=\"series\" data-name=\"" << svg::escape(name) << "\"><polygon points=\"" << upper << " " << lower << "\" fill=\""
      << colour_of(name) << "\" fill-opacity=\"0.25\" stroke=\"" << colour_of(name) << "\" stroke-width=\"1.1\"/></g>\n";
    o << "<rect x=\"" << lx << "\" y=\"" << T + 6 << "\" width=\"14\" height=\"10\" fill=\"" << colour_of(name) << "\"/><text x=\""
      << lx + 19 << "\" y=\"" << T + 15 << "\" font-size=\"12\" fill=\"#333\">" << svg::escape(name) << "</text>\n";
    lx += 80;
  }
  o << "</svg></section>\n";
  return o.str();
}

}  // namespace

std::string scope_csv(const ScopeRecord& r) {
  std::string out = "t";
  for (const auto& s : r.signals) out += "," + s;
  out += "\n";
  char buf[32];
  for (std::size_t i = 0; i < r.t.size(); ++i) {
    std::snprintf(buf, sizeof buf, "%.4f", r.t[i]);
    out += buf;
    for (std::size_t c = 0; c < r.signals.size(); ++c) out += "," + cell(r.signals[c], r.columns[c][i]);
    out += "\n";
  }
  return out;
}

std::string render_scope_html(const ScopeRecord& r) {
  std::vector<Group> groups = {{"Position", "mm", 1.0, {}},    {"Following error", "µm", 1000.0, {}},
                               {"Path speed", "mm/s", 1.0, {}}, {"Program line", "line", 1.0, {}},
                               {"Machine state", "state (1 IDLE, 2 RUNNING, 3 PAUSED, 4 JOGGING, 5 STOPPING, 6 FAULT, 7 ESTOP)", 1.0, {}}};
  for (std::size_t c = 0; c < r.signals.size(); ++c) {
    const std::string& s = r.signals[c];
    const std::size_t g = s.rfind("ferr", 0) == 0 ? 1 : s == "speed" ? 2 : s == "line" ? 3 : s == "state" ? 4 : 0;
    groups[g].cols.push_back(c);
  }
  std::ostringstream o;
  const double secs = static_cast<double>(r.t.size()) * r.period_s;
  o << "<!doctype html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>pcnc scope</title>\n<style>"
    << "body{margin:0;background:#f3f4f7;color:#1d2330;font:14px/1.45 system-ui,sans-serif}"
       "main{max-width:1180px;margin:0 auto;padding:22px 20px 40px}h1{font-size:22px;margin:0 0 4px}"
       "h2{font-size:15px;margin:0 0 8px;color:#2b3345}.sub{color:#5b6475;margin:0 0 16px}"
       ".card{background:#fff;border-radius:10px;box-shadow:0 1px 3px rgba(20,30,50,.12);padding:14px 16px;margin-bottom:16px}"
       "svg{display:block;width:100%;height:auto}</style></head><body><main>\n";
  o << "<h1>Scope capture</h1>\n<p class=\"sub\" id=\"summary\">" << r.t.size() << " cycles (" << fixed(secs, 3) << " s at "
    << fixed(1.0 / r.period_s, 0) << " Hz, no gaps) of " << svg::escape([&] {
         std::string l;
         for (const auto& s : r.signals) l += (l.empty() ? "" : ", ") + s;
         return l;
       }());
  if (!r.trigger.empty()) {
    o << "; trigger <code>" << svg::escape(r.trigger) << "</code> held at machine time "
      << fixed(r.t.empty() ? 0.0 : r.t[std::min(r.trigger_row, r.t.size() - 1)], 4) << " s, " << r.trigger_row
      << " cycles of pre-trigger (shaded)";
  } else if (!r.t.empty()) {
    o << "; from machine time " << fixed(r.t.front(), 4) << " s";
  }
  if (!r.source.empty()) o << "; " << svg::escape(r.source);
  o << "</p>\n";
  for (const Group& g : groups) {
    if (!g.cols.empty()) o << plot(r, g);
  }
  o << "</main></body></html>\n";
  return o.str();
}

}  // namespace pcnc
