// spline_fit.cpp — least-squares cubic B-spline within a tolerance of a polyline (see
// spline_fit.hpp for the method).
#include "geometry/spline_fit.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace pcnc {

namespace {

constexpr int kDegree = 3;
constexpr double kFirstSpanMm = 2.0;    // knot spacing of the first fit
constexpr double kMinSpanMm = 1e-3;     // a span this short is not halved again
constexpr double kTarget = 0.9;         // spans above this share of the tolerance are refined
constexpr double kSmoothing = 1e-3;     // weight of the control polygon's second differences
constexpr int kMaxRounds = 14;
constexpr int kBand = kDegree;          // half-bandwidth of the normal equations

std::vector<double> chord_params(const std::vector<Vec3>& points) {
  std::vector<double> t(points.size(), 0.0);
  for (std::size_t i = 1; i < points.size(); ++i) t[i] = t[i - 1] + norm(points[i] - points[i - 1]);
  return t;
}

// The span i of a clamped cubic knot vector with knots[i] <= u < knots[i+1] (the last
// non-empty span at the end of the domain).
int span_of(const std::vector<double>& knots, int count, double u) {
  if (u >= knots[static_cast<std::size_t>(count)]) {
    int i = count - 1;
    while (i > kDegree && knots[static_cast<std::size_t>(i)] >= knots[static_cast<std::size_t>(i) + 1]) --i;
    return i;
  }
  const auto it = std::upper_bound(knots.begin() + kDegree, knots.begin() + count, u);
  return std::max(kDegree, static_cast<int>(it - knots.begin()) - 1);
}

// The four cubic basis functions that do not vanish at u in `span` (The NURBS Book, A2.2).
std::array<double, 4> cubic_basis(const std::vector<double>& knots, int span, double u) {
  std::array<double, 4> n{1.0, 0.0, 0.0, 0.0};
  double left[4] = {}, right[4] = {};
  for (int j = 1; j <= kDegree; ++j) {
    left[j] = u - knots[static_cast<std::size_t>(span + 1 - j)];
    right[j] = knots[static_cast<std::size_t>(span + j)] - u;
    double saved = 0.0;
    for (int r = 0; r < j; ++r) {
      const double den = right[r + 1] + left[j - r];
      const double tmp = den != 0.0 ? n[static_cast<std::size_t>(r)] / den : 0.0;
      n[static_cast<std::size_t>(r)] = saved + right[r + 1] * tmp;
      saved = left[j - r] * tmp;
    }
    n[static_cast<std::size_t>(j)] = saved;
  }
  return n;
}

// A symmetric positive definite band matrix (entries (i, i+d), d <= kBand) and its solve.
struct BandSystem {
  std::vector<std::array<double, kBand + 1>> a;
  std::vector<Vec3> rhs;
  explicit BandSystem(std::size_t n) : a(n, std::array<double, kBand + 1>{}), rhs(n, Vec3{}) {}
  void add(std::size_t i, std::size_t j, double v) {
    if (i > j) std::swap(i, j);
    a[i][j - i] += v;
  }
  // Cholesky L·Lᵀ in band storage, then the two triangular solves for the three columns.
  std::vector<Vec3> solve() const {
    const std::size_t n = a.size();
    std::vector<std::array<double, kBand + 1>> l(n, std::array<double, kBand + 1>{});  // l[i][i-k] = L(i,k)
    auto L = [&](std::size_t i, std::size_t k) { return l[i][i - k]; };
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t k0 = i >= kBand ? i - kBand : 0;
      for (std::size_t j = k0; j <= i; ++j) {
        double sum = a[j][i - j];
        for (std::size_t k = std::max(k0, j >= kBand ? j - kBand : 0); k < j; ++k) sum -= L(i, k) * L(j, k);
        if (i == j) {
          l[i][0] = std::sqrt(std::max(sum, 1e-300));
        } else {
          l[i][i - j] = sum / l[j][0];
        }
      }
    }
    std::vector<Vec3> y(n);
    for (std::size_t i = 0; i < n; ++i) {
      Vec3 s = rhs[i];
      for (std::size_t k = i >= kBand ? i - kBand : 0; k < i; ++k) s = s - L(i, k) * y[k];
      y[i] = (1.0 / l[i][0]) * s;
    }
    std::vector<Vec3> x(n);
    for (std::size_t ii = n; ii-- > 0;) {
      Vec3 s = y[ii];
      for (std::size_t k = ii + 1; k < n && k <= ii + kBand; ++k) s = s - L(k, ii) * x[k];
      x[ii] = (1.0 / l[ii][0]) * s;
    }
    return x;
  }
};

// The least-squares curve on `knots` (clamped cubic) through the data, ends fixed.
NurbsCurve solve_fit(const std::vector<double>& knots, const std::vector<double>& du, const std::vector<Vec3>& dp,
                     const Vec3& first, const Vec3& last) {
  const int count = static_cast<int>(knots.size()) - kDegree - 1;
  NurbsCurve c;
  c.degree = kDegree;
  c.knots = knots;
  c.points.assign(static_cast<std::size_t>(count), Vec3{});
  c.weights.assign(static_cast<std::size_t>(count), 1.0);
  c.points.front() = first;
  c.points.back() = last;
  const int free = count - 2;  // unknowns: control points 1 .. count-2
  if (free <= 0) return c;
  BandSystem sys(static_cast<std::size_t>(free));
  auto fixed = [&](int j) { return j == 0 || j == count - 1; };
  auto value = [&](int j) { return j == 0 ? first : last; };
  for (std::size_t k = 0; k < du.size(); ++k) {
    const int s = span_of(knots, count, du[k]);
    const std::array<double, 4> n = cubic_basis(knots, s, du[k]);
    Vec3 r = dp[k];
    for (int a = 0; a < 4; ++a) {
      const int ja = s - kDegree + a;
      if (fixed(ja)) r = r - n[static_cast<std::size_t>(a)] * value(ja);
    }
    for (int a = 0; a < 4; ++a) {
      const int ja = s - kDegree + a;
      if (fixed(ja)) continue;
      const double na = n[static_cast<std::size_t>(a)];
      sys.rhs[static_cast<std::size_t>(ja - 1)] = sys.rhs[static_cast<std::size_t>(ja - 1)] + na * r;
      for (int b = a; b < 4; ++b) {
        const int jb = s - kDegree + b;
        if (!fixed(jb)) sys.add(static_cast<std::size_t>(ja - 1), static_cast<std::size_t>(jb - 1), na * n[static_cast<std::size_t>(b)]);
      }
    }
  }
  // λ Σ |Q(i-1) − 2Q(i) + Q(i+1)|²: straightens spans without data, hardly moves the others.
  const double coef[3] = {1.0, -2.0, 1.0};
  for (int i = 1; i + 1 < count; ++i) {
    for (int a = 0; a < 3; ++a) {
      const int ja = i - 1 + a;
      if (fixed(ja)) continue;
      for (int b = 0; b < 3; ++b) {
        const int jb = i - 1 + b;
        if (fixed(jb)) {
          sys.rhs[static_cast<std::size_t>(ja - 1)] =
              sys.rhs[static_cast<std::size_t>(ja - 1)] - (kSmoothing * coef[a] * coef[b]) * value(jb);
        } else if (jb >= ja) {
          sys.add(static_cast<std::size_t>(ja - 1), static_cast<std::size_t>(jb - 1), kSmoothing * coef[a] * coef[b]);
        }
      }
    }
  }
  const std::vector<Vec3> q = sys.solve();
  for (int j = 1; j + 1 < count; ++j) c.points[static_cast<std::size_t>(j)] = q[static_cast<std::size_t>(j - 1)];
  return c;
}

// One measured deviation at curve parameter u.
struct Deviation {
  double u;
  double d;
};

// A polyline prepared for many distance queries: each segment's start, direction vector and
// squared length (point_segment_distance's operations, done once), and a ball around it (its
// midpoint and half length) that bounds the distance from below.
struct SegmentChain {
  std::vector<Vec3> a, ab, mid;
  std::vector<double> len2, half;
  explicit SegmentChain(const std::vector<Vec3>& pts) {
    const std::size_t n = pts.size() > 0 ? pts.size() - 1 : 0;
    a.resize(n);
    ab.resize(n);
    mid.resize(n);
    len2.resize(n);
    half.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      a[i] = pts[i];
      ab[i] = pts[i + 1] - pts[i];
      len2[i] = dot(ab[i], ab[i]);
      mid[i] = pts[i] + 0.5 * ab[i];
      half[i] = 0.5 * std::sqrt(len2[i]);
    }
    make_chunks(pts);
  }
  // Balls around kChunk consecutive segments (centre, radius): a whole chunk is skipped at once.
  static constexpr std::size_t kChunk = 8;
  std::vector<Vec3> chunk_mid;
  std::vector<double> chunk_radius;
  void make_chunks(const std::vector<Vec3>& pts) {
    const std::size_t n = a.size();
    for (std::size_t c = 0; c * kChunk < n; ++c) {
      const std::size_t first = c * kChunk, last = std::min(n, first + kChunk);  // points first..last
      const Vec3 centre = 0.5 * (pts[first] + pts[last]);
      double r2 = 0.0;
      for (std::size_t i = first; i <= last; ++i) r2 = std::max(r2, dot(pts[i] - centre, pts[i] - centre));
      chunk_mid.push_back(centre);
      chunk_radius.push_back(std::sqrt(r2));
    }
  }
  // The square of point_segment_distance(p, pts[i], pts[i + 1]), the same operations.
  double dist2(const Vec3& p, std::size_t i) const {
    const double s = len2[i] > 0.0 ? std::clamp(dot(p - a[i], ab[i]) / len2[i], 0.0, 1.0) : 0.0;
    const Vec3 d = a[i] + s * ab[i] - p;
    return dot(d, d);
  }
};

// A segment is skipped when its ball is farther than the best distance so far plus this
// (mm): far above the rounding of the coordinates, so that a skipped segment is never the
// nearest and the result is the full scan's, bit for bit.
constexpr double kSkipMarginMm = 1e-9;

// Distance from p to the polyline pts[lo..hi] (segments lo..hi-1 of `chain`), starting with
// segment `near` (the one at p's parameter, usually the nearest); the others are skipped when
// their ball is farther than the best so far. sqrt is monotonic, so the smallest of the
// squares gives the smallest distance exactly.
double to_polyline(const Vec3& p, const std::vector<Vec3>& pts, const SegmentChain& chain, std::size_t lo, std::size_t hi,
                   std::size_t near) {
  const Vec3 d0 = p - pts[lo];
  double best2 = dot(d0, d0);
  near = std::clamp(near, lo, hi > lo ? hi - 1 : lo);
  if (near < hi) best2 = std::min(best2, chain.dist2(p, near));
  double best = std::sqrt(best2);
  // chunk by chunk (also the partial ones at the window's ends: a far ball is far for each of
  // its segments inside the window as well), then segment by segment
  for (std::size_t c = lo / SegmentChain::kChunk; c * SegmentChain::kChunk < hi; ++c) {
    const std::size_t start = c * SegmentChain::kChunk;
    if (!(near >= start && near < start + SegmentChain::kChunk)) {
      const Vec3 m = chain.chunk_mid[c] - p;
      const double reach = best + chain.chunk_radius[c] + kSkipMarginMm;
      if (dot(m, m) > reach * reach) continue;
    }
    const std::size_t end = std::min(hi, start + SegmentChain::kChunk);
    for (std::size_t i = std::max(lo, start); i < end; ++i) {
      if (i == near) continue;
      const Vec3 m = chain.mid[i] - p;
      const double reach = best + chain.half[i] + kSkipMarginMm;
      if (dot(m, m) > reach * reach) continue;
      const double d2 = chain.dist2(p, i);
      if (d2 < best2) {
        best2 = d2;
        best = std::sqrt(best2);
      }
    }
  }
  return best;
}

// std::upper_bound(v.begin(), v.end(), x) - v.begin(), the same index, trying `hint` and
// hint + 1 before the binary search: the deviation queries mostly go forward.
std::size_t upper_index(const std::vector<double>& v, double x, std::size_t hint) {
  const std::size_t n = v.size();
  auto is_it = [&](std::size_t s) { return s <= n && (s == 0 || v[s - 1] <= x) && (s == n || x < v[s]); };
  if (is_it(hint)) return hint;
  if (is_it(hint + 1)) return hint + 1;
  return static_cast<std::size_t>(std::upper_bound(v.begin(), v.end(), x) - v.begin());
}

// Window [lo, hi] of indices of the sorted `t` around parameter u: at least `min_count`
// entries and `min_width` of parameter on each side. `at` receives the index j with
// t[j] <= u < t[j + 1] (0 before the first); it comes in as the last query's (a hint).
std::pair<std::size_t, std::size_t> window(const std::vector<double>& t, double u, std::size_t min_count, double min_width,
                                           std::size_t& at) {
  const std::size_t n = t.size();
  std::size_t j = upper_index(t, u, at + 1);
  j = j > 0 ? j - 1 : 0;
  at = j;
  // first the count (one step), then the width one index at a time
  std::size_t lo = j >= min_count ? j - min_count : 0;
  std::size_t hi = std::min(std::max(j + 1, j + min_count), n - 1);
  while (lo > 0 && u - t[lo] < min_width) --lo;
  while (hi + 1 < n && t[hi] - u < min_width) ++hi;
  return {lo, hi};
}

std::vector<Deviation> measure(const NurbsCurve& curve, const std::vector<Vec3>& pts, const SegmentChain& programmed,
                               const std::vector<double>& t, int samples_per_span) {
  const NurbsView v = curve.view();
  std::vector<double> su;
  std::vector<Vec3> sp;
  for (int i = curve.degree; i < v.count; ++i) {
    const double a = v.knots[i], b = v.knots[i + 1];
    if (!(b > a)) continue;
    for (int j = 0; j < samples_per_span; ++j) su.push_back(a + (b - a) * j / samples_per_span);
  }
  su.push_back(v.u_max());
  sp.resize(su.size());
  int hint = curve.degree;  // two samples at a time (nurbs_point_pair), in order
  for (std::size_t k = 0; k < su.size(); k += 2) {
    if (k + 1 < su.size()) {
      nurbs_point_pair(v, su[k], su[k + 1], hint, sp[k], sp[k + 1]);
    } else {
      sp[k] = nurbs_point(v, su[k]);
    }
  }
  const double span = t.back() / static_cast<double>(std::max<std::size_t>(1, su.size() - 1)) * samples_per_span;
  const double width = 0.05 + 2.0 * span / samples_per_span;
  const SegmentChain sampled(sp);
  std::vector<Deviation> out;
  out.reserve(su.size() + 4 * pts.size());
  // the curve against the programmed segments
  std::size_t at = 0;
  for (std::size_t k = 0; k < su.size(); ++k) {
    const auto [lo, hi] = window(t, su[k], 4, width, at);
    out.push_back({su[k], to_polyline(sp[k], pts, programmed, lo, hi, at)});
  }
  // the programmed points and segments (quarter points) against the sampled curve
  at = 0;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    for (int q = 0; q < (i + 1 < pts.size() ? 4 : 1); ++q) {
      const double f = q / 4.0;
      const Vec3 p = q == 0 ? pts[i] : pts[i] + f * (pts[i + 1] - pts[i]);
      const double u = q == 0 ? t[i] : t[i] + f * (t[i + 1] - t[i]);
      const auto [lo, hi] = window(su, u, static_cast<std::size_t>(2 * samples_per_span), width, at);
      out.push_back({u, to_polyline(p, sp, sampled, lo, hi, at)});
    }
  }
  return out;
}

// The data of a round: every programmed point, and each segment sampled at least twice per
// knot span it lies in (the span at its middle), so that where the knots are dense the curve
// follows the segments, not only their ends (a C2 curve through the points alone overshoots
// a sharp turn between them).
void sample_polyline(const std::vector<Vec3>& points, const std::vector<double>& t, const std::vector<double>& interior,
                     std::vector<double>& du, std::vector<Vec3>& dp) {
  du.clear();
  dp.clear();
  const double length = t.back();
  std::size_t s = 0;
  for (std::size_t i = 0; i + 1 < points.size(); ++i) {
    const double mid = 0.5 * (t[i] + t[i + 1]);
    s = upper_index(interior, mid, s);
    const double h = (s < interior.size() ? interior[s] : length) - (s > 0 ? interior[s - 1] : 0.0);
    const int n = std::clamp(static_cast<int>(std::ceil(2.0 * (t[i + 1] - t[i]) / std::max(h, kMinSpanMm))), 2, 64);
    for (int j = 0; j < n; ++j) {
      const double f = static_cast<double>(j) / n;
      du.push_back(t[i] + f * (t[i + 1] - t[i]));
      dp.push_back(points[i] + f * (points[i + 1] - points[i]));
    }
  }
  du.push_back(length);
  dp.push_back(points.back());
}

}  // namespace

double point_segment_distance(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double len2 = dot(ab, ab);
  const double s = len2 > 0.0 ? std::clamp(dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
  return norm(a + s * ab - p);
}

double polyline_deviation(const NurbsCurve& curve, const std::vector<Vec3>& points, int samples_per_span,
                          std::vector<double>* per_point) {
  const std::vector<double> t = chord_params(points);
  const std::vector<Deviation> devs = measure(curve, points, SegmentChain(points), t, samples_per_span);
  double worst = 0.0;
  if (per_point) per_point->assign(points.size(), 0.0);
  for (const Deviation& d : devs) {
    worst = std::max(worst, d.d);
    if (per_point) {
      std::size_t j = static_cast<std::size_t>(std::lower_bound(t.begin(), t.end(), d.u) - t.begin());
      if (j >= t.size() || (j > 0 && d.u - t[j - 1] < t[j] - d.u)) j = j > 0 ? j - 1 : 0;
      (*per_point)[j] = std::max((*per_point)[j], d.d);
    }
  }
  return worst;
}

SplineFit fit_polyline(const std::vector<Vec3>& points, double tolerance) {
  SplineFit r;
  if (points.size() < 2) return r;
  const std::vector<double> t = chord_params(points);
  const double length = t.back();
  std::vector<double> du;
  std::vector<Vec3> dp;
  std::vector<double> interior;
  // Knots kFirstSpanMm apart, but no more than the refinement below may reach (about two per
  // programmed point): a few very long moves must not cost thousands of spans.
  const double max_spans = 2.0 * static_cast<double>(points.size()) + 8.0;
  const int first_spans = static_cast<int>(std::clamp(std::ceil(length / kFirstSpanMm), 1.0, max_spans));
  for (int i = 1; i < first_spans; ++i) interior.push_back(length * i / first_spans);
  std::vector<double> knots;
  std::vector<Deviation> devs;
  const SegmentChain programmed(points);  // the same in every round
  for (int round = 0;; ++round) {
    knots.assign(kDegree + 1, 0.0);
    knots.insert(knots.end(), interior.begin(), interior.end());
    knots.insert(knots.end(), kDegree + 1, length);
    sample_polyline(points, t, interior, du, dp);
    r.curve = solve_fit(knots, du, dp, points.front(), points.back());
    devs = measure(r.curve, points, programmed, t, 16);
    // the largest deviation in each span [knots_s, knots_s+1] (interior index s - kDegree)
    std::vector<double> span_dev(interior.size() + 1, 0.0);
    std::size_t in = 0;  // the span of d.u
    for (const Deviation& d : devs) {
      in = upper_index(interior, d.u, in);
      span_dev[in] = std::max(span_dev[in], d.d);
      if (in > 0 && d.u == interior[in - 1]) span_dev[in - 1] = std::max(span_dev[in - 1], d.d);
    }
    std::vector<double> refined;
    bool split = false, stuck = false;
    for (std::size_t s = 0; s < span_dev.size(); ++s) {
      const double a = s == 0 ? 0.0 : interior[s - 1];
      const double b = s < interior.size() ? interior[s] : length;
      if (s > 0) refined.push_back(a);
      if (span_dev[s] > kTarget * tolerance) {
        if (b - a > 2.0 * kMinSpanMm) {
          refined.push_back(0.5 * (a + b));
          split = true;
        } else if (span_dev[s] > tolerance) {
          stuck = true;
        }
      }
    }
    // More knots than about two per programmed point cannot bring a cubic closer to the
    // points and segments (a corner the angle did not see): give up here, the caller cuts the
    // run at the worst point. This also bounds the work per fit on any input.
    if (refined.size() > 2 * points.size() + 8) stuck = true;
    if (!split || stuck || round + 1 >= kMaxRounds) break;
    interior = std::move(refined);
  }
  double worst_u = 0.0;
  r.deviation = 0.0;
  for (const Deviation& d : devs) {
    if (d.d > r.deviation) r.deviation = d.d, worst_u = d.u;
  }
  r.ok = r.deviation <= tolerance;
  std::size_t j = static_cast<std::size_t>(std::lower_bound(t.begin(), t.end(), worst_u) - t.begin());
  if (j >= t.size() || (j > 0 && worst_u - t[j - 1] < t[j] - worst_u)) j = j > 0 ? j - 1 : 0;
  r.worst_point = static_cast<int>(j);
  return r;
}

}  // namespace pcnc
