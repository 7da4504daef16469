// nurbs.hpp — the NURBS curve as a value type: exact evaluation (point, first and second
// derivative), knot vectors (LinuxCNC G5.2 open uniform, the seed paper's chord length),
// validation, knot insertion and splitting into ring-sized pieces.
//
// Used on both sides of the ring: the host builds a NurbsCurve from G5.2/G06.2 words,
// validates it, splits it into pieces that fit a block and copies each piece into the block
// (ipc/block_nurbs.hpp); the rt evaluates the block's arrays in place every cycle through a
// NurbsView. Evaluation allocates nothing (fixed arrays sized by kMaxNurbsDegree) and works
// the same on either storage. Pure mathematics: nothing here knows blocks or the ring.
//
// Conventions: degree p in 1..kMaxNurbsDegree (order p+1 in 2..6), n+1 control points,
// n+p+2 knots, non-decreasing. The parameter domain is [knots[p], knots[n+1]].
#pragma once

#include <string>
#include <vector>

#include "geometry/nurbs_order.hpp"
#include "geometry/vec3.hpp"

namespace pcnc {

/// How knots are made when a program gives none (GcodeConfig::nurbs_knots).
enum class KnotRule : int {
  kOpenUniform = 0,  // LinuxCNC G5.2: 0 (order times), 1, 2, ..., n-k+2 (order times)
  kChordLength = 1,  // the seed paper's eq. (4): spaced by the control polygon's chords
};

/// Read-only view of a curve's arrays: what evaluation works on. Cheap to copy; it points
/// into a NurbsCurve or a block's NurbsGeometry (view_of), which must outlive it.
struct NurbsView {
  const Vec3* points = nullptr;
  const double* weights = nullptr;
  const double* knots = nullptr;
  int count = 0;   // number of control points, n+1
  int degree = 0;  // p

  double u_min() const { return knots[degree]; }
  double u_max() const { return knots[count]; }
};

/// A point of the curve and its first two derivatives with respect to the parameter u.
struct NurbsEval {
  Vec3 p{};
  Vec3 d1{};
  Vec3 d2{};
};

/// The host-side curve: any number of control points (the ring's per-block limit is met by
/// split_nurbs). A plain value; no invariants are enforced until validate().
struct NurbsCurve {
  int degree = 3;
  std::vector<Vec3> points;
  std::vector<double> weights;
  std::vector<double> knots;

  NurbsView view() const {
    return {points.data(), weights.data(), knots.data(), static_cast<int>(points.size()), degree};
  }
  double u_min() const { return knots[static_cast<std::size_t>(degree)]; }
  double u_max() const { return knots[points.size()]; }
};

// ---- knot vectors -----------------------------------------------------------------------

/// LinuxCNC's G5.2 knot vector for `count` control points and order k = degree+1: k zeros,
/// then 1, 2, ..., count-k, then count-k+1 repeated k times (integers, domain [0, count-k+1]).
std::vector<double> open_uniform_knots(int count, int degree);

/// The seed paper's chord-length knot vector (its eq. 4, Rogers & Adams): clamped, same
/// domain [0, count-degree] as the open uniform one, interior knots placed by the chord
/// lengths c_i = |B_{i+1} - B_i| of the control polygon. Falls back to open uniform when
/// the polygon has zero length.
std::vector<double> chord_length_knots(const std::vector<Vec3>& points, int degree);

/// A complete curve from control points, weights and order, knots by `rule`.
NurbsCurve make_nurbs(std::vector<Vec3> points, std::vector<double> weights, int order,
                      KnotRule rule = KnotRule::kOpenUniform);

// ---- validation -------------------------------------------------------------------------

/// Empty when the curve is usable, else one sentence saying what is wrong (order out of
/// range 2..6, too few control points for the order, weight count or value, knot count,
/// decreasing or non-finite knots, empty parameter domain, knots not clamped (first and
/// last `order` knots equal, as G5.2 and G06.2 make them), interior knot multiplicity above
/// the degree, non-finite coordinates).
std::string validate(const NurbsCurve& curve);
std::string validate(const NurbsView& curve);

// ---- evaluation (allocation-free, real-time safe) ---------------------------------------

/// Knot span index i with knots[i] <= u < knots[i+1], in [degree, count-1]; u outside the
/// domain is clamped to it (u_max maps to the last non-empty span).
int find_span(const NurbsView& c, double u);

/// The same span, trying `hint` first (a caller walking along the curve passes the span it
/// found last): hint when knots[hint] <= u < knots[hint+1], else find_span(c, u).
int find_span(const NurbsView& c, double u, int hint);

/// C(u). u is clamped to the domain.
Vec3 nurbs_point(const NurbsView& c, double u);

/// C(u), C'(u), C''(u) by the Cox–de Boor basis and its derivatives, with the rational
/// quotient rule on the homogeneous curve. u is clamped to the domain. At an interior knot
/// the derivatives are those of the span starting there (right-hand side).
NurbsEval nurbs_eval(const NurbsView& c, double u);

/// The same, with the knot span tried first and updated (find_span with a hint): for a
/// caller that evaluates many parameters in order. The same values bit for bit.
NurbsEval nurbs_eval(const NurbsView& c, double u, int& span_hint);

/// C'(u) alone: the same value as nurbs_eval(c, u).d1, bit for bit (the same operations),
/// without the second derivative's basis work. The arc-length quadratures use it.
Vec3 nurbs_derivative(const NurbsView& c, double u);
Vec3 nurbs_derivative(const NurbsView& c, double u, int& span_hint);

/// nurbs_eval / nurbs_derivative / nurbs_point at two parameters, each value bit for bit the
/// single call's; two parameters of one knot span are evaluated together on two SIMD lanes (the
/// quadratures' pairs of Gauss points, consecutive samples: about half the time of two calls).
/// span_hint as above (ub's span). nurbs_eval_pair without `second`: d2 stays zero (p and d1
/// are nurbs_eval's all the same).
void nurbs_eval_pair(const NurbsView& c, double ua, double ub, int& span_hint, NurbsEval& ea, NurbsEval& eb,
                     bool second = true);
void nurbs_derivative_pair(const NurbsView& c, double ua, double ub, int& span_hint, Vec3& da, Vec3& db);
void nurbs_point_pair(const NurbsView& c, double ua, double ub, int& span_hint, Vec3& pa, Vec3& pb);

/// Unit tangent at u; where the parametric speed vanishes (a doubled control point, as in
/// LinuxCNC programs that repeat the start point) the direction of C'' is used instead,
/// looking forward (`toward_end`) or backward.
Vec3 nurbs_tangent(const NurbsView& c, double u, bool toward_end = true);

/// Curvature |C' x C''| / |C'|^3 at u (1/mm); 0 where the parametric speed vanishes.
double nurbs_curvature(const NurbsEval& e);

/// Arc length of the curve between parameters u0 <= u1 (Gauss–Legendre per knot span).
double nurbs_arc_length(const NurbsView& c, double u0, double u1);

// ---- projection (host side) -------------------------------------------------------------

/// The parameter u* of the curve point nearest to `p`: each knot span sampled
/// (`samples_per_span` points) for its nearest sample, from which Newton steps on
/// f(u) = (C(u) - p) . C'(u) = 0 run, kept inside the domain and never accepted when they move
/// away from p; the nearest of the spans' results wins. `distance` (when
/// given) receives |C(u*) - p|. Pure; allocates nothing.
double nurbs_project(const NurbsView& c, const Vec3& p, double* distance = nullptr, int samples_per_span = 32);

// ---- knot insertion and splitting (host side) -------------------------------------------

/// Boehm knot insertion of u, `times` times; the curve's shape and parametrisation do not
/// change. u must lie inside the domain.
NurbsCurve insert_knot(const NurbsCurve& curve, double u, int times = 1);

/// The part of the curve between parameters a < b as a clamped curve of its own (same
/// parametrisation, knots [a..b]).
NurbsCurve nurbs_segment(const NurbsCurve& curve, double a, double b);

/// The largest turn (rad) of the tangent at an interior knot that is a kink, not a corner: a
/// chain of programmed arcs packed into one curve (host/gcode/arc_packing.hpp) joins within it,
/// as CAM's rounded arc ends do. The feed schedule passes a kink without stopping, at a speed
/// whose velocity step stays within a share of one cycle's acceleration (nurbs_schedule.hpp).
constexpr double kTangentKinkTurn = 1e-3;

/// Interior knots where the curve has a corner: multiplicity >= degree and the tangent
/// direction turning there by more than kTangentKinkTurn.
std::vector<double> corner_knots(const NurbsCurve& curve);

/// Splits a valid curve at interior knots into consecutive pieces of at most `max_points`
/// control points (>= degree+1). It also splits at every corner: an interior knot of
/// multiplicity >= degree where the tangent direction turns, so that no piece contains a
/// tangent discontinuity (the rt then treats the corner like any block junction). Pieces
/// are the original curve restricted to [u_i, u_{i+1}], so they join with its continuity.
std::vector<NurbsCurve> split_nurbs(const NurbsCurve& curve, int max_points);

}  // namespace pcnc
