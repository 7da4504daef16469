// biarc_polyline.cpp — biarcs through a smooth run of short G1 moves: tangents from a local
// least-squares quadratic, greedy spans checked exactly at every programmed point.
// See fit_biarcs_polyline in biarc.hpp.
#include <algorithm>
#include <cmath>

#include "geometry/biarc.hpp"

namespace pcnc {
namespace {

constexpr int kMaxHalfWindow = 4;  // points each side of the tangent estimate, at most

// Unit tangent at points[i]: slope at x = 0 of y = a + b x + c x^2 fitted by least squares to
// the neighbouring points in a frame along the neighbours' chord. The widest window (up to
// kMaxHalfWindow points each side) whose fit leaves no point further than `max_residual`
// wins: wide where the curve is smooth (the 0.5 um rounding of CAM output averages out),
// narrow where its curvature changes fast (a parabola no longer fits).
Vec2 local_tangent(const std::vector<Vec2>& p, std::size_t i, double max_residual) {
  const std::size_t n = p.size();
  const Vec2 d = normalized(p[std::min(i + 1, n - 1)] - p[i > 0 ? i - 1 : 0]);
  const Vec2 nrm = perp(d);
  for (int h = kMaxHalfWindow; h >= 1; --h) {
    const std::size_t lo = i >= static_cast<std::size_t>(h) ? i - h : 0;
    const std::size_t hi = std::min(n - 1, i + h);
    if (hi - lo < 2) return d;
    double s[5] = {0, 0, 0, 0, 0}, t[3] = {0, 0, 0};  // normal equations of the 3-parameter fit
    for (std::size_t k = lo; k <= hi; ++k) {
      const double x = dot(p[k] - p[i], d), y = dot(p[k] - p[i], nrm);
      double xp = 1.0;
      for (int e = 0; e < 5; ++e) {
        s[e] += xp;
        if (e < 3) t[e] += xp * y;
        xp *= x;
      }
    }
    const double m[3][3] = {{s[0], s[1], s[2]}, {s[1], s[2], s[3]}, {s[2], s[3], s[4]}};
    auto det3 = [](const double a[3][3]) {
      return a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
             a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
    };
    const double det = det3(m);
    if (!(std::abs(det) > 1e-30)) continue;
    double coef[3];
    for (int col = 0; col < 3; ++col) {  // Cramer's rule
      double mc[3][3];
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) mc[r][c] = c == col ? t[r] : m[r][c];
      coef[col] = det3(mc) / det;
    }
    if (!std::isfinite(coef[1])) continue;
    double worst = 0.0;
    for (std::size_t k = lo; k <= hi; ++k) {
      const double x = dot(p[k] - p[i], d), y = dot(p[k] - p[i], nrm);
      worst = std::max(worst, std::abs(y - (coef[0] + coef[1] * x + coef[2] * x * x)));
    }
    if (worst <= max_residual || hi - lo == 2) return normalized(d + coef[1] * nrm);
  }
  return d;
}

// Distance from q to the segment a-b.
double segment_distance(Vec2 q, Vec2 a, Vec2 b) {
  const Vec2 ab = b - a;
  const double L = dot(ab, ab);
  const double f = L > 0.0 ? std::clamp(dot(q - a, ab) / L, 0.0, 1.0) : 0.0;
  return distance(q, a + f * ab);
}

struct PolyFitter {
  const std::vector<Vec2>& p;
  std::vector<Vec2> t;
  std::vector<double> sag;  // per segment: the sagitta of the smooth curve over the chord
  double tol;

  struct Measure {
    bool ok = false;
    double point_dev = 0.0, segment_dev = 0.0, allowance = 0.0;
    std::vector<Arc2> arcs;
  };

  Measure span(std::size_t i, std::size_t j) const {
    Measure m;
    if (const auto bi = make_biarc(p[i], t[i], p[j], t[j])) m.arcs = {bi->first, bi->second};
    else m.arcs = {make_segment(p[i], p[j])};
    for (std::size_t k = i + 1; k < j; ++k) m.point_dev = std::max(m.point_dev, nearest_on_arcs(m.arcs, p[k]));
    for (std::size_t k = i; k < j; ++k) m.allowance = std::max(m.allowance, sag[k]);
    // arcs -> programmed segments: samples along each arc, nearest segment of the span
    const int samples = 4 * static_cast<int>(j - i) + 4;
    for (const Arc2& a : m.arcs)
      for (int s = 0; s <= samples; ++s) {
        const Vec2 q = arc_point(a, static_cast<double>(s) / samples);
        double best = 1e300;
        for (std::size_t k = i; k < j; ++k) best = std::min(best, segment_distance(q, p[k], p[k + 1]));
        m.segment_dev = std::max(m.segment_dev, best);
      }
    m.ok = m.point_dev <= tol && m.segment_dev <= tol + m.allowance;
    return m;
  }
};

}  // namespace

PolylineFit fit_biarcs_polyline(const std::vector<Vec2>& input, const BiarcOptions& options) {
  PolylineFit out;
  // repeated points (zero-length moves) carry no direction
  std::vector<Vec2> p;
  for (const Vec2& q : input)
    if (p.empty() || distance(p.back(), q) > 1e-12) p.push_back(q);
  if (!input.empty() && !p.empty()) p.back() = input.back();
  if (p.size() < 2) return out;
  PolyFitter f{p, {}, {}, options.tolerance_mm};
  for (std::size_t i = 0; i < p.size(); ++i) f.t.push_back(local_tangent(p, i, 0.5 * options.tolerance_mm));
  for (std::size_t k = 0; k + 1 < p.size(); ++k) {
    const double phi = std::abs(std::atan2(cross(f.t[k], f.t[k + 1]), dot(f.t[k], f.t[k + 1])));
    f.sag.push_back(0.5 * distance(p[k], p[k + 1]) * std::tan(std::min(phi, 3.0) / 4.0));
  }
  // greedy: from i the longest span that passes (doubling, then bisection on the end index)
  std::size_t i = 0;
  const std::size_t last = p.size() - 1;
  while (i < last) {
    PolyFitter::Measure best = f.span(i, i + 1);  // no point between; the biarc may still leave
    if (!best.ok) {                                // the chord (poor tangents): keep the move
      best.arcs = {make_segment(p[i], p[i + 1])};
      best.segment_dev = 0.0;
      best.ok = true;
    }
    std::size_t good = i + 1, bad = last + 1;
    for (std::size_t step = 2; i + step <= last; step *= 2) {
      PolyFitter::Measure m = f.span(i, i + step);
      if (!m.ok) {
        bad = i + step;
        break;
      }
      good = i + step, best = std::move(m);
    }
    if (bad == last + 1 && good < last) {  // every doubling passed: try the end itself
      PolyFitter::Measure m = f.span(i, last);
      if (m.ok) good = last, best = std::move(m);
      else bad = last;
    }
    while (bad - good > 1 && bad <= last) {
      const std::size_t mid = good + (bad - good) / 2;
      PolyFitter::Measure m = f.span(i, mid);
      if (m.ok) good = mid, best = std::move(m);
      else bad = mid;
    }
    append_biarc(out.arcs, best.arcs);
    ++out.biarcs;
    out.max_point_deviation_mm = std::max(out.max_point_deviation_mm, best.point_dev);
    out.max_segment_deviation_mm = std::max(out.max_segment_deviation_mm, best.segment_dev);
    out.max_sagitta_mm = std::max(out.max_sagitta_mm, best.allowance);
    if (!best.ok) out.within_tolerance = false;
    i = good;
  }
  out.max_deviation_mm = out.max_point_deviation_mm;
  return out;
}

}  // namespace pcnc
