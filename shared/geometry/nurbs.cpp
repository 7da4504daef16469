// nurbs.cpp — NURBS evaluation, knot vectors, validation, knot insertion and splitting.
// See nurbs.hpp. The evaluation path (find_span, basis functions, nurbs_eval) uses only
// fixed-size local arrays so the rt can call it every cycle.
#include "geometry/nurbs.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace pcnc {
namespace {

constexpr int kOrderMax = kMaxNurbsDegree + 1;

// Full unrolling of the short basis loops once the degree is a constant (eval_in_span): GCC's
// -O2 does not unroll loops that grow the code.
#if defined(__clang__)
#define PCNC_UNROLL _Pragma("unroll")
#elif defined(__GNUC__)
#define PCNC_UNROLL _Pragma("GCC unroll 8")
#else
#define PCNC_UNROLL
#endif

// Two parameters evaluated at once on two SIMD lanes (GCC/Clang vector extension; SSE2 on
// x86-64): each lane's operations are IEEE operations in the scalar order, so each lane's value
// is the scalar one bit for bit. The knot differences (divisors, zero tests) are the same for
// both lanes of one span, so the branches stay scalar.
typedef double Pair __attribute__((vector_size(16)));

// a / b with the B-spline convention 0/0 = 0 (a zero-length knot interval contributes nothing).
// T: double, or Pair (both lanes divided by the one knot difference).
template <class T>
inline T safe_div(T a, double b) {
  return b != 0.0 ? a / b : T{} + 0.0;
}

// Non-zero basis functions of every degree 0..p at u in span `span`:
// table[d][j] = N_{span-d+j, d}(u), j = 0..d (Cox–de Boor recurrence).
template <class T>
using BasisTableOf = std::array<std::array<T, kOrderMax>, kOrderMax>;
using BasisTable = BasisTableOf<double>;

template <int p, class T>
inline void basis_table(const double* t, int span, T u, BasisTableOf<T>& table) {
  table[0][0] = T{} + 1.0;
  PCNC_UNROLL
  for (int d = 1; d <= p; ++d) {
    PCNC_UNROLL
    for (int j = 0; j <= d; ++j) {
      const int i = span - d + j;
      T value = T{} + 0.0;
      if (j >= 1) value += safe_div<T>(u - t[i], t[i + d] - t[i]) * table[d - 1][j - 1];
      if (j <= d - 1) value += safe_div<T>(t[i + d + 1] - u, t[i + d + 1] - t[i + 1]) * table[d - 1][j];
      table[d][j] = value;
    }
  }
}

// Derivative of the degree-d basis functions from the degree-(d-1) values `lower`
// (lower[j] = N_{span-d+1+j, d-1} or its derivative): out[j] for N_{span-d+j, d}.
template <int d, class T>
inline void derive(const double* t, int span, const T* lower, T* out) {
  PCNC_UNROLL
  for (int j = 0; j <= d; ++j) {
    const int i = span - d + j;
    T value = T{} + 0.0;
    if (j >= 1) value += safe_div<T>(lower[j - 1], t[i + d] - t[i]);
    if (j <= d - 1) value -= safe_div<T>(lower[j], t[i + d + 1] - t[i + 1]);
    out[j] = static_cast<double>(d) * value;
  }
}

// C(u) in the knot span `span` for the degree P known at compile time (basis_table's
// operations, unrolled: the same value bit for bit).
template <int P, class T>
void point_in_span_of(const NurbsView& c, int span, T u, T (&out)[3]) {
  BasisTableOf<T> table;
  basis_table<P, T>(c.knots, span, u, table);
  T a[3] = {};
  T w = T{} + 0.0;
  for (int j = 0; j <= P; ++j) {
    const int i = span - P + j;
    const T nw = table[P][j] * c.weights[i];
    for (int k = 0; k < 3; ++k) a[k] = a[k] + nw * c.points[i][static_cast<std::size_t>(k)];
    w += nw;
  }
  const T inv = 1.0 / w;
  for (int k = 0; k < 3; ++k) out[k] = inv * a[k];
}

template <int P>
Vec3 point_in_span(const NurbsView& c, int span, double u) {
  double p[3];
  point_in_span_of<P, double>(c, span, u, p);
  return {p[0], p[1], p[2]};
}

template <int P>
void point_pair_in_span(const NurbsView& c, int span, double ua, double ub, Vec3& pa, Vec3& pb) {
  Pair p[3];
  point_in_span_of<P, Pair>(c, span, Pair{ua, ub}, p);
  pa = {p[0][0], p[1][0], p[2][0]};
  pb = {p[0][1], p[1][1], p[2][1]};
}

int multiplicity(const std::vector<double>& knots, double u) {
  return static_cast<int>(std::count(knots.begin(), knots.end(), u));
}

}  // namespace

// ---- knot vectors -----------------------------------------------------------------------

std::vector<double> open_uniform_knots(int count, int degree) {
  const int k = degree + 1;
  const int n = count - 1;
  std::vector<double> knots;
  if (count < 1 || degree < 0) return knots;
  knots.reserve(static_cast<std::size_t>(n + k + 1));
  for (int i = 0; i <= n + k; ++i) {
    if (i < k) {
      knots.push_back(0.0);
    } else if (i <= n) {
      knots.push_back(static_cast<double>(i - k + 1));
    } else {
      knots.push_back(static_cast<double>(n - k + 2));
    }
  }
  return knots;
}

std::vector<double> chord_length_knots(const std::vector<Vec3>& points, int degree) {
  const int count = static_cast<int>(points.size());
  const int k = degree + 1;
  const int n = count - 1;
  if (count < k || degree < 1) return open_uniform_knots(count, degree);
  std::vector<double> chord(static_cast<std::size_t>(n));
  double total = 0.0;
  for (int j = 0; j < n; ++j) {
    chord[static_cast<std::size_t>(j)] = norm(points[static_cast<std::size_t>(j + 1)] - points[static_cast<std::size_t>(j)]);
    total += chord[static_cast<std::size_t>(j)];
  }
  if (!(total > 0.0)) return open_uniform_knots(count, degree);
  const double m = static_cast<double>(n - k + 2);  // domain end, as for the open uniform vector
  std::vector<double> knots(static_cast<std::size_t>(n + k + 1), 0.0);
  // Seed eq. (4), 1-based: x_{i+k} = ((i/m) c_{i+1} + sum_{j<=i} c_j) / sum c * m, i = 1..n-k+1.
  double prefix = 0.0;
  for (int i = 1; i <= n - k + 1; ++i) {
    prefix += chord[static_cast<std::size_t>(i - 1)];
    const double x = ((i / m) * chord[static_cast<std::size_t>(i)] + prefix) / total * m;
    knots[static_cast<std::size_t>(i + k - 1)] = x;
  }
  for (int idx = n + 1; idx <= n + k; ++idx) knots[static_cast<std::size_t>(idx)] = m;
  return knots;
}

NurbsCurve make_nurbs(std::vector<Vec3> points, std::vector<double> weights, int order, KnotRule rule) {
  NurbsCurve c;
  c.degree = order - 1;
  c.points = std::move(points);
  c.weights = std::move(weights);
  c.knots = rule == KnotRule::kChordLength ? chord_length_knots(c.points, c.degree)
                                           : open_uniform_knots(static_cast<int>(c.points.size()), c.degree);
  return c;
}

// ---- validation -------------------------------------------------------------------------

std::string validate(const NurbsView& c) {
  char buf[200];
  const int p = c.degree;
  if (p < kMinNurbsDegree || p > kMaxNurbsDegree) {
    std::snprintf(buf, sizeof buf, "NURBS order %d out of range: the order must be %d to %d (degree %d to %d)",
                  p + 1, kMinNurbsOrder, kMaxNurbsOrder, kMinNurbsDegree, kMaxNurbsDegree);
    return buf;
  }
  if (c.count < p + 1) {
    std::snprintf(buf, sizeof buf, "NURBS of order %d needs at least %d control points, got %d", p + 1, p + 1,
                  c.count);
    return buf;
  }
  for (int i = 0; i < c.count; ++i) {
    const Vec3& q = c.points[i];
    if (!std::isfinite(q[0]) || !std::isfinite(q[1]) || !std::isfinite(q[2])) {
      std::snprintf(buf, sizeof buf, "NURBS control point %d is not a finite number", i + 1);
      return buf;
    }
    if (!(c.weights[i] > 0.0) || !std::isfinite(c.weights[i])) {
      std::snprintf(buf, sizeof buf, "NURBS weight of control point %d is %g: weights must be > 0", i + 1,
                    c.weights[i]);
      return buf;
    }
  }
  const int knot_count = c.count + p + 1;
  for (int i = 0; i < knot_count; ++i) {
    if (!std::isfinite(c.knots[i])) {
      std::snprintf(buf, sizeof buf, "NURBS knot %d is not a finite number", i + 1);
      return buf;
    }
    if (i > 0 && c.knots[i] < c.knots[i - 1]) {
      std::snprintf(buf, sizeof buf, "NURBS knots must not decrease: knot %d (%g) < knot %d (%g)", i + 1, c.knots[i],
                    i, c.knots[i - 1]);
      return buf;
    }
  }
  if (!(c.knots[p] < c.knots[c.count])) {
    return "NURBS knot vector gives an empty parameter range (all active knots equal)";
  }
  if (c.knots[0] != c.knots[p] || c.knots[c.count] != c.knots[c.count + p]) {
    std::snprintf(buf, sizeof buf,
                  "NURBS knot vector must be clamped: its first %d and last %d knots must be equal", p + 1, p + 1);
    return buf;
  }
  // Interior multiplicity above the degree would break the curve apart.
  for (int i = p + 1; i < c.count;) {
    int j = i;
    while (j + 1 < c.count && c.knots[j + 1] == c.knots[i]) ++j;
    const int mult = j - i + 1;
    if (mult > p && c.knots[i] > c.knots[p] && c.knots[i] < c.knots[c.count]) {
      std::snprintf(buf, sizeof buf,
                    "NURBS interior knot %g repeats %d times: at most the degree (%d) keeps the curve connected",
                    c.knots[i], mult, p);
      return buf;
    }
    i = j + 1;
  }
  return {};
}

std::string validate(const NurbsCurve& curve) {
  char buf[160];
  if (curve.degree < kMinNurbsDegree || curve.degree > kMaxNurbsDegree) {
    std::snprintf(buf, sizeof buf, "NURBS order %d out of range: the order must be %d to %d (degree %d to %d)",
                  curve.degree + 1, kMinNurbsOrder, kMaxNurbsOrder, kMinNurbsDegree, kMaxNurbsDegree);
    return buf;
  }
  if (curve.points.size() < static_cast<std::size_t>(curve.degree + 1)) {
    std::snprintf(buf, sizeof buf, "NURBS of order %d needs at least %d control points, got %zu", curve.degree + 1,
                  curve.degree + 1, curve.points.size());
    return buf;
  }
  if (curve.weights.size() != curve.points.size()) {
    std::snprintf(buf, sizeof buf, "NURBS has %zu weights for %zu control points", curve.weights.size(),
                  curve.points.size());
    return buf;
  }
  const std::size_t want = curve.points.size() + static_cast<std::size_t>(curve.degree) + 1;
  if (curve.knots.size() != want) {
    std::snprintf(buf, sizeof buf,
                  "NURBS of order %d with %zu control points needs %zu knots (points + order), got %zu",
                  curve.degree + 1, curve.points.size(), want, curve.knots.size());
    return buf;
  }
  return validate(curve.view());
}

// ---- evaluation -------------------------------------------------------------------------

int find_span(const NurbsView& c, double u) {
  const double* t = c.knots;
  const int p = c.degree;
  const int n = c.count - 1;
  if (u >= t[n + 1]) {
    int i = n;
    while (i > p && !(t[i] < t[i + 1])) --i;
    return i;
  }
  if (u <= t[p]) {
    int i = p;
    while (i < n && !(t[i] < t[i + 1])) ++i;
    return i;
  }
  int lo = p;
  int hi = n + 1;  // invariant: t[lo] <= u < t[hi]
  while (hi - lo > 1) {
    const int mid = (lo + hi) / 2;
    if (u < t[mid]) {
      hi = mid;
    } else {
      lo = mid;
    }
  }
  return lo;
}

void nurbs_point_pair(const NurbsView& c, double ua, double ub, int& span_hint, Vec3& pa, Vec3& pb) {
  ua = std::clamp(ua, c.u_min(), c.u_max());
  ub = std::clamp(ub, c.u_min(), c.u_max());
  const int sa = find_span(c, ua, span_hint);
  span_hint = find_span(c, ub, sa);
  if (sa != span_hint) {
    pa = nurbs_point(c, ua);
    pb = nurbs_point(c, ub);
    return;
  }
  switch (c.degree) {
    case 1: return point_pair_in_span<1>(c, sa, ua, ub, pa, pb);
    case 2: return point_pair_in_span<2>(c, sa, ua, ub, pa, pb);
    case 3: return point_pair_in_span<3>(c, sa, ua, ub, pa, pb);
    case 4: return point_pair_in_span<4>(c, sa, ua, ub, pa, pb);
    default: return point_pair_in_span<5>(c, sa, ua, ub, pa, pb);
  }
}

Vec3 nurbs_point(const NurbsView& c, double u) {
  u = std::clamp(u, c.u_min(), c.u_max());
  const int span = find_span(c, u);
  switch (c.degree) {
    case 1: return point_in_span<1>(c, span, u);
    case 2: return point_in_span<2>(c, span, u);
    case 3: return point_in_span<3>(c, span, u);
    case 4: return point_in_span<4>(c, span, u);
    default: return point_in_span<5>(c, span, u);
  }
}

namespace {

// The evaluation proper, in the knot span `span` of u (find_span's answer), for the degree P
// known at compile time (basis_table and derive unroll: the same operations in the same order,
// the same values bit for bit, about twice as fast). `Second`: C'' too. T: double, or Pair
// (two parameters of one span; out[k]: component k, each lane one parameter's).
template <int P, bool Second, class T>
void eval_in_span_of(const NurbsView& c, int span, T u, T (&p)[3], T (&d1)[3], T (&d2)[3]) {
  const double* t = c.knots;
  BasisTableOf<T> table;
  basis_table<P, T>(t, span, u, table);
  std::array<T, kOrderMax> b1{};
  std::array<T, kOrderMax> b2{};
  derive<P, T>(t, span, table[P - 1].data(), b1.data());
  if constexpr (Second && P >= 2) {
    std::array<T, kOrderMax> lower_d1{};
    derive<P - 1, T>(t, span, table[P - 2].data(), lower_d1.data());
    derive<P, T>(t, span, lower_d1.data(), b2.data());
  }
  T a0[3] = {}, a1[3] = {}, a2[3] = {};
  T w0 = T{} + 0.0, w1 = T{} + 0.0, w2 = T{} + 0.0;
  PCNC_UNROLL
  for (int j = 0; j <= P; ++j) {
    const int i = span - P + j;
    const double w = c.weights[i];
    const Vec3 wp = w * c.points[i];
    PCNC_UNROLL
    for (int k = 0; k < 3; ++k) {
      a0[k] = a0[k] + table[P][j] * wp[static_cast<std::size_t>(k)];
      a1[k] = a1[k] + b1[j] * wp[static_cast<std::size_t>(k)];
      if constexpr (Second) a2[k] = a2[k] + b2[j] * wp[static_cast<std::size_t>(k)];
    }
    w0 += table[P][j] * w;
    w1 += b1[j] * w;
    if constexpr (Second) w2 += b2[j] * w;
  }
  const T inv = 1.0 / w0;
  PCNC_UNROLL
  for (int k = 0; k < 3; ++k) {
    p[k] = inv * a0[k];
    d1[k] = inv * (a1[k] - w1 * p[k]);
    if constexpr (Second) d2[k] = inv * (a2[k] - 2.0 * w1 * d1[k] - w2 * p[k]);
  }
}

template <int P, bool Second>
NurbsEval eval_in_span(const NurbsView& c, int span, double u) {
  double p[3], d1[3], d2[3] = {0.0, 0.0, 0.0};
  eval_in_span_of<P, Second, double>(c, span, u, p, d1, d2);
  NurbsEval e;
  e.p = {p[0], p[1], p[2]};
  e.d1 = {d1[0], d1[1], d1[2]};
  if constexpr (Second) e.d2 = {d2[0], d2[1], d2[2]};
  return e;
}

// Two parameters of the knot span `span` at once.
template <int P, bool Second>
void eval_pair_in_span(const NurbsView& c, int span, double ua, double ub, NurbsEval& ea, NurbsEval& eb) {
  Pair p[3], d1[3], d2[3] = {};
  eval_in_span_of<P, Second, Pair>(c, span, Pair{ua, ub}, p, d1, d2);
  ea.p = {p[0][0], p[1][0], p[2][0]};
  eb.p = {p[0][1], p[1][1], p[2][1]};
  ea.d1 = {d1[0][0], d1[1][0], d1[2][0]};
  eb.d1 = {d1[0][1], d1[1][1], d1[2][1]};
  if constexpr (Second) {
    ea.d2 = {d2[0][0], d2[1][0], d2[2][0]};
    eb.d2 = {d2[0][1], d2[1][1], d2[2][1]};
  } else {
    ea.d2 = eb.d2 = Vec3{};
  }
}

// eval_in_span for the curve's degree (1..kMaxNurbsDegree; the callers evaluate valid curves).
template <bool Second>
NurbsEval eval_dispatch(const NurbsView& c, int span, double u) {
  switch (c.degree) {
    case 1: return eval_in_span<1, Second>(c, span, u);
    case 2: return eval_in_span<2, Second>(c, span, u);
    case 3: return eval_in_span<3, Second>(c, span, u);
    case 4: return eval_in_span<4, Second>(c, span, u);
    default: return eval_in_span<5, Second>(c, span, u);
  }
}
static_assert(kMaxNurbsDegree == 5, "eval_dispatch covers degrees 1..5");

template <bool Second>
void eval_pair_dispatch(const NurbsView& c, int span, double ua, double ub, NurbsEval& ea, NurbsEval& eb) {
  switch (c.degree) {
    case 1: return eval_pair_in_span<1, Second>(c, span, ua, ub, ea, eb);
    case 2: return eval_pair_in_span<2, Second>(c, span, ua, ub, ea, eb);
    case 3: return eval_pair_in_span<3, Second>(c, span, ua, ub, ea, eb);
    case 4: return eval_pair_in_span<4, Second>(c, span, ua, ub, ea, eb);
    default: return eval_pair_in_span<5, Second>(c, span, ua, ub, ea, eb);
  }
}

// nurbs_eval (Second) or nurbs_derivative at ua and ub: as a pair when both lie in one span.
template <bool Second>
void eval_pair(const NurbsView& c, double ua, double ub, int& span_hint, NurbsEval& ea, NurbsEval& eb) {
  ua = std::clamp(ua, c.u_min(), c.u_max());
  ub = std::clamp(ub, c.u_min(), c.u_max());
  const int sa = find_span(c, ua, span_hint);
  span_hint = find_span(c, ub, sa);
  if (sa == span_hint) {
    eval_pair_dispatch<Second>(c, sa, ua, ub, ea, eb);
  } else {
    ea = eval_dispatch<Second>(c, sa, ua);
    eb = eval_dispatch<Second>(c, span_hint, ub);
  }
}

}  // namespace

int find_span(const NurbsView& c, double u, int hint) {
  const double* t = c.knots;
  if (hint >= c.degree && hint < c.count && t[hint] <= u && u < t[hint + 1]) return hint;
  return find_span(c, u);
}

NurbsEval nurbs_eval(const NurbsView& c, double u) {
  u = std::clamp(u, c.u_min(), c.u_max());
  return eval_dispatch<true>(c, find_span(c, u), u);
}

NurbsEval nurbs_eval(const NurbsView& c, double u, int& span_hint) {
  u = std::clamp(u, c.u_min(), c.u_max());
  span_hint = find_span(c, u, span_hint);
  return eval_dispatch<true>(c, span_hint, u);
}

Vec3 nurbs_derivative(const NurbsView& c, double u) {
  u = std::clamp(u, c.u_min(), c.u_max());
  return eval_dispatch<false>(c, find_span(c, u), u).d1;
}

Vec3 nurbs_derivative(const NurbsView& c, double u, int& span_hint) {
  u = std::clamp(u, c.u_min(), c.u_max());
  span_hint = find_span(c, u, span_hint);
  return eval_dispatch<false>(c, span_hint, u).d1;
}

void nurbs_eval_pair(const NurbsView& c, double ua, double ub, int& span_hint, NurbsEval& ea, NurbsEval& eb,
                     bool second) {
  if (second) {
    eval_pair<true>(c, ua, ub, span_hint, ea, eb);
  } else {
    eval_pair<false>(c, ua, ub, span_hint, ea, eb);
  }
}

void nurbs_derivative_pair(const NurbsView& c, double ua, double ub, int& span_hint, Vec3& da, Vec3& db) {
  NurbsEval ea, eb;
  eval_pair<false>(c, ua, ub, span_hint, ea, eb);
  da = ea.d1;
  db = eb.d1;
}

Vec3 nurbs_tangent(const NurbsView& c, double u, bool toward_end) {
  const NurbsEval e = nurbs_eval(c, u);
  const double speed = norm(e.d1);
  const double scale = norm(e.d2) * (c.u_max() - c.u_min());
  if (speed > 1e-9 * std::max(scale, 1e-300) && speed > 0.0) return (1.0 / speed) * e.d1;
  // C'(u) = 0: near u, C(u+h) - C(u) ~ C''(u) h^2 / 2, pointing along C'' on both sides;
  // the direction of travel is +C'' after u and -C'' before u.
  const Vec3 dir = normalized(e.d2);
  return toward_end ? dir : -1.0 * dir;
}

double nurbs_curvature(const NurbsEval& e) {
  const double s = norm(e.d1);
  if (!(s > 0.0)) return 0.0;
  return norm(cross(e.d1, e.d2)) / (s * s * s);
}

namespace {

// 8-point Gauss–Legendre on [a, b] of the parametric speed |C'(u)|; [a, b] lies in the knot
// span `span` (tried first for each point).
double gauss8_speed(const NurbsView& c, double a, double b, int span) {
  static constexpr double kX[4] = {0.18343464249564981, 0.52553240991632899, 0.79666647741362674,
                                   0.96028985649753623};
  static constexpr double kW[4] = {0.36268378337836198, 0.31370664587788729, 0.22238103445337447,
                                   0.10122853629037626};
  const double mid = 0.5 * (a + b);
  const double half = 0.5 * (b - a);
  double sum = 0.0;
  for (int g = 0; g < 4; ++g) {
    Vec3 lo, hi;
    nurbs_derivative_pair(c, mid - half * kX[g], mid + half * kX[g], span, lo, hi);
    sum += kW[g] * (norm(lo) + norm(hi));
  }
  return half * sum;
}

// Adaptive: halves the interval until the two halves agree with the whole. The speed is a
// smooth function inside a span except near (almost) vanishing C', where it has a kink.
double adaptive_length(const NurbsView& c, double a, double b, double whole, int depth, int span) {
  const double mid = 0.5 * (a + b);
  const double left = gauss8_speed(c, a, mid, span);
  const double right = gauss8_speed(c, mid, b, span);
  const double both = left + right;
  if (depth <= 0 || std::fabs(both - whole) <= 1e-13 * std::fabs(both) + 1e-13) return both;
  return adaptive_length(c, a, mid, left, depth - 1, span) + adaptive_length(c, mid, b, right, depth - 1, span);
}

}  // namespace

double nurbs_arc_length(const NurbsView& c, double u0, double u1) {
  u0 = std::clamp(u0, c.u_min(), c.u_max());
  u1 = std::clamp(u1, c.u_min(), c.u_max());
  if (!(u1 > u0)) return 0.0;
  double total = 0.0;
  double a = u0;
  while (a < u1) {
    // One knot span at a time: the speed is smooth inside a span.
    const int span = find_span(c, a);
    double b = std::min(u1, c.knots[span + 1]);
    if (!(b > a)) b = u1;
    total += adaptive_length(c, a, b, gauss8_speed(c, a, b, span), 40, span);
    a = b;
  }
  return total;
}

// ---- projection ---------------------------------------------------------------------------

double nurbs_project(const NurbsView& c, const Vec3& p, double* distance, int samples_per_span) {
  const int per = std::max(samples_per_span, 2);
  const double lo = c.u_min(), hi = c.u_max();
  const double eps = 1e-15 * std::max(1.0, std::abs(hi - lo));
  // Newton on f(u) = (C - p) . C', f'(u) = C' . C' + (C - p) . C''; a step that does not
  // bring the point nearer is halved, and the search ends when the step no longer matters.
  auto newton = [&](double u, double d) {
    for (int it = 0; it < 50; ++it) {
      const NurbsEval e = nurbs_eval(c, u);
      const Vec3 r = e.p - p;
      const double f = dot(r, e.d1);
      const double fp = dot(e.d1, e.d1) + dot(r, e.d2);
      if (!(std::abs(fp) > 0.0) || !std::isfinite(f / fp)) break;
      double step = -f / fp;
      bool moved = false;
      for (int h = 0; h < 30 && std::abs(step) > eps; ++h, step *= 0.5) {
        const double un = std::clamp(u + step, lo, hi);
        const double dn = norm(nurbs_point(c, un) - p);
        if (dn <= d) {
          moved = un != u;
          d = dn;
          u = un;
          break;
        }
      }
      if (!moved || std::abs(step) <= eps) break;
    }
    return std::pair<double, double>{u, d};
  };
  // The nearest sample of each knot span starts a Newton search; the nearest result wins (a
  // closed curve's point near its end is also near its start: both are tried).
  double best_u = lo;
  double best_d = norm(nurbs_point(c, lo) - p);
  for (int j = c.degree; j < c.count; ++j) {
    const double a = c.knots[j], b = c.knots[j + 1];
    if (!(a < b)) continue;
    double su = a, sd = 1e300;
    for (int k = 0; k <= per; ++k) {
      const double u = a + (b - a) * static_cast<double>(k) / per;
      const double d = norm(nurbs_point(c, u) - p);
      if (d < sd) {
        sd = d;
        su = u;
      }
    }
    const auto [u, d] = newton(su, sd);
    if (d < best_d) {
      best_d = d;
      best_u = u;
    }
  }
  if (distance) *distance = best_d;
  return best_u;
}

// ---- knot insertion and splitting -------------------------------------------------------

NurbsCurve insert_knot(const NurbsCurve& curve, double u, int times) {
  NurbsCurve out = curve;
  for (int r = 0; r < times; ++r) {
    const NurbsCurve in = out;
    const int p = in.degree;
    const int count = static_cast<int>(in.points.size());
    if (!(u > in.u_min() && u < in.u_max())) {
      throw std::invalid_argument("insert_knot: parameter outside the open domain");
    }
    const int k = find_span(in.view(), u);  // knots[k] <= u < knots[k+1]
    out.points.assign(static_cast<std::size_t>(count + 1), Vec3{});
    out.weights.assign(static_cast<std::size_t>(count + 1), 0.0);
    for (int i = 0; i <= count; ++i) {
      const auto si = static_cast<std::size_t>(i);
      if (i <= k - p) {
        out.points[si] = in.points[si];
        out.weights[si] = in.weights[si];
      } else if (i >= k + 1) {
        out.points[si] = in.points[si - 1];
        out.weights[si] = in.weights[si - 1];
      } else {
        // Blend in homogeneous coordinates (w P, w).
        const double alpha = safe_div(u - in.knots[si], in.knots[si + static_cast<std::size_t>(p)] - in.knots[si]);
        const double w = alpha * in.weights[si] + (1.0 - alpha) * in.weights[si - 1];
        const Vec3 wp = alpha * in.weights[si] * in.points[si] + (1.0 - alpha) * in.weights[si - 1] * in.points[si - 1];
        out.weights[si] = w;
        out.points[si] = (1.0 / w) * wp;
      }
    }
    out.knots = in.knots;
    out.knots.insert(out.knots.begin() + k + 1, u);
  }
  return out;
}

NurbsCurve nurbs_segment(const NurbsCurve& curve, double a, double b) {
  NurbsCurve c = curve;
  const int p = c.degree;
  // Make a and b knots of multiplicity p (the curve then passes through a control point
  // there), then keep the control points between them and clamp the knot vector.
  for (const double x : {a, b}) {
    if (x > c.u_min() && x < c.u_max()) {
      const int have = multiplicity(c.knots, x);
      if (have < p) c = insert_knot(c, x, p - have);
    }
  }
  // First control point index: the one whose basis function is 1 at a.
  const NurbsView v = c.view();
  int first = 0;
  if (a > c.u_min()) first = find_span(v, a) - p;  // last knot equal to a is r: C(a) = P_{r-p}
  int last = static_cast<int>(c.points.size()) - 1;
  if (b < c.u_max()) last = find_span(v, b) - p;  // knots[r] == b (multiplicity p): C(b) = P_{r-p}
  NurbsCurve out;
  out.degree = p;
  out.points.assign(c.points.begin() + first, c.points.begin() + last + 1);
  out.weights.assign(c.weights.begin() + first, c.weights.begin() + last + 1);
  out.knots.assign(static_cast<std::size_t>(p + 1), a);
  for (double t : c.knots) {
    if (t > a && t < b) out.knots.push_back(t);
  }
  out.knots.insert(out.knots.end(), static_cast<std::size_t>(p + 1), b);
  return out;
}

std::vector<double> corner_knots(const NurbsCurve& curve) {
  const int p = curve.degree;
  const double lo = curve.u_min();
  const double hi = curve.u_max();
  const NurbsView v = curve.view();
  std::vector<double> corners;
  for (std::size_t i = 0; i < curve.knots.size(); ++i) {
    const double t = curve.knots[i];
    if (!(t > lo && t < hi) || (!corners.empty() && corners.back() == t)) continue;
    if (i > 0 && curve.knots[i - 1] == t) continue;  // only the first of a run
    if (multiplicity(curve.knots, t) < p) continue;  // C1 there: no corner possible
    const Vec3 before = nurbs_tangent(v, std::nextafter(t, lo), false);
    const Vec3 after = nurbs_tangent(v, t, true);
    if (dot(before, after) < std::cos(kTangentKinkTurn)) corners.push_back(t);
  }
  return corners;
}

std::vector<NurbsCurve> split_nurbs(const NurbsCurve& curve, int max_points) {
  const int p = curve.degree;
  if (max_points < p + 1) throw std::invalid_argument("split_nurbs: max_points below the order");
  const double lo = curve.u_min();
  const double hi = curve.u_max();
  const std::vector<double> corners = corner_knots(curve);
  // Distinct interior knots with multiplicities, in increasing order.
  std::vector<std::pair<double, int>> interior;
  for (const double t : curve.knots) {
    if (!(t > lo && t < hi)) continue;
    if (!interior.empty() && interior.back().first == t) {
      ++interior.back().second;
    } else {
      interior.emplace_back(t, 1);
    }
  }
  // A clamped piece over [a, b] has p + 1 + (multiplicities of the knots strictly inside)
  // control points. Cut greedily where the next knot would make the piece too big.
  std::vector<double> cuts{lo};
  int inside = 0;
  for (const auto& [t, mult] : interior) {
    const bool corner = std::find(corners.begin(), corners.end(), t) != corners.end();
    if (corner || p + 1 + inside + mult > max_points) {
      cuts.push_back(t);
      inside = 0;
    } else {
      inside += mult;
    }
  }
  cuts.push_back(hi);
  std::vector<NurbsCurve> pieces;
  if (cuts.size() == 2) {
    pieces.push_back(curve);
    return pieces;
  }
  for (std::size_t i = 0; i + 1 < cuts.size(); ++i) pieces.push_back(nurbs_segment(curve, cuts[i], cuts[i + 1]));
  return pieces;
}

}  // namespace pcnc
