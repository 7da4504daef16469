// test_biarc.cpp — biarc fitting and arc offsets (geometry/biarc.hpp) against independent
// checks: the deviation bound by dense sampling of both the curve and the arcs (the arcs
// evaluated from centre, radius and angles here, not by arc_point), G1 continuity, exact
// end points, exact offsets, arc intersections, loop removal (the offset of the result by the
// tool radius keeps the radius from the contour everywhere), degenerate inputs.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "gcode/biarc_moves.hpp"
#include "geometry/arc_intersect.hpp"
#include "geometry/biarc.hpp"
#include "nurbs_circles.hpp"
#include "test_constants.hpp"

namespace pcnc {
namespace {


// ---- independent measures -------------------------------------------------------------

// Dense points of an arc from its centre, radius, start angle and sweep.
std::vector<Vec2> dense(const Arc2& a, int n = 400) {
  std::vector<Vec2> pts;
  if (a.line) {
    for (int i = 0; i <= n; ++i) pts.push_back(a.start + (static_cast<double>(i) / n) * (a.end - a.start));
    return pts;
  }
  const double t0 = std::atan2(a.start.y - a.centre.y, a.start.x - a.centre.x);
  for (int i = 0; i <= n; ++i) {
    const double t = t0 + a.sweep * i / n;
    pts.push_back({a.centre.x + a.radius * std::cos(t), a.centre.y + a.radius * std::sin(t)});
  }
  return pts;
}

double seg_dist(Vec2 q, Vec2 a, Vec2 b) {
  const Vec2 ab = b - a;
  const double L = dot(ab, ab);
  double f = L > 0 ? dot(q - a, ab) / L : 0.0;
  f = f < 0 ? 0 : f > 1 ? 1 : f;
  return norm(q - (a + f * ab));
}

double poly_dist(Vec2 q, const std::vector<Vec2>& poly) {
  double best = 1e300;
  for (std::size_t i = 0; i + 1 < poly.size(); ++i) best = std::min(best, seg_dist(q, poly[i], poly[i + 1]));
  return best;
}

std::vector<Vec2> dense_chain(const std::vector<Arc2>& arcs, int per_arc = 400) {
  std::vector<Vec2> pts;
  for (const Arc2& a : arcs)
    for (const Vec2& p : dense(a, per_arc)) pts.push_back(p);
  return pts;
}

std::vector<Vec2> dense_curve(const NurbsCurve& c, int n) {
  std::vector<Vec2> pts;
  for (int i = 0; i <= n; ++i) {
    const Vec3 p = nurbs_point(c.view(), c.u_min() + (c.u_max() - c.u_min()) * i / n);
    pts.push_back({p[0], p[1]});
  }
  return pts;
}

// Distance from p to an arc from its centre, radius and the angles of its ends (written
// here, not arc_distance): on the circle when the direction of p lies within the sweep.
double arc_dist(const Arc2& a, Vec2 p) {
  if (a.line) return seg_dist(p, a.start, a.end);
  const double t0 = std::atan2(a.start.y - a.centre.y, a.start.x - a.centre.x);
  double t = std::atan2(p.y - a.centre.y, p.x - a.centre.x) - t0;  // from the start, in the arc's sense
  if (a.sweep < 0) t = -t;
  t = std::fmod(t + 4 * kPi, 2 * kPi);
  if (t <= std::abs(a.sweep)) return std::abs(norm(p - a.centre) - a.radius);
  return std::min(norm(p - a.start), norm(p - a.end));
}

double chain_dist(Vec2 p, const std::vector<Arc2>& arcs) {
  double best = 1e300;
  for (const Arc2& a : arcs) best = std::min(best, arc_dist(a, p));
  return best;
}

// Distance from q to a dense polyline: the nearest of every 50th vertex, then the segments
// within 100 vertices of it (the curves here are far from touching themselves).
double dense_poly_dist(Vec2 q, const std::vector<Vec2>& poly) {
  std::size_t best = 0;
  for (std::size_t i = 0; i < poly.size(); i += 50)
    if (norm(poly[i] - q) < norm(poly[best] - q)) best = i;
  const std::size_t lo = best > 100 ? best - 100 : 0, hi = std::min(poly.size() - 1, best + 100);
  double d = 1e300;
  for (std::size_t i = lo; i < hi; ++i) d = std::min(d, seg_dist(q, poly[i], poly[i + 1]));
  return d;
}

// Two-sided distance between a densely sampled curve and arcs.
double hausdorff(const std::vector<Vec2>& curve, const std::vector<Arc2>& arcs) {
  double h = 0.0;
  for (const Vec2& p : curve) h = std::max(h, chain_dist(p, arcs));
  for (const Arc2& a : arcs)
    for (const Vec2& q : dense(a, 50)) h = std::max(h, dense_poly_dist(q, curve));
  return h;
}

void expect_chain(const std::vector<Arc2>& arcs, bool g1, double angle_tol = 1e-7) {
  for (const Arc2& a : arcs) {
    EXPECT_TRUE(std::isfinite(a.start.x) && std::isfinite(a.end.y) && std::isfinite(a.sweep));
    if (!a.line) {  // the ends lie on the circle
      EXPECT_NEAR(distance(a.start, a.centre), a.radius, 1e-9 * std::max(1.0, a.radius));
      EXPECT_NEAR(distance(a.end, a.centre), a.radius, 1e-7 * std::max(1.0, a.radius));
    }
  }
  for (std::size_t i = 1; i < arcs.size(); ++i) {
    EXPECT_EQ(arcs[i].start.x, arcs[i - 1].end.x) << i;
    EXPECT_EQ(arcs[i].start.y, arcs[i - 1].end.y) << i;
    if (g1) {
      const Vec2 t0 = end_tangent(arcs[i - 1]), t1 = start_tangent(arcs[i]);
      EXPECT_NEAR(std::atan2(cross(t0, t1), dot(t0, t1)), 0.0, angle_tol) << "joint " << i;
    }
  }
}

// A free-form S-shaped cubic (an inflection) in XY, 7 control points.
NurbsCurve s_curve() {
  return make_nurbs({{0, 0, 0}, {4, 6, 0}, {10, 8, 0}, {14, 0, 0}, {18, -8, 0}, {24, -6, 0}, {28, 0, 0}},
                    std::vector<double>(7, 1.0), 4);
}

// ---- one biarc ----------------------------------------------------------------------------

TEST(Biarc, KeepsEndsAndTangentsAndJoinsTangentially) {
  const Vec2 p0{0, 0}, t0 = normalized(Vec2{1, 1}), p1{10, 2}, t1 = normalized(Vec2{1, -0.5});
  for (double ratio : {0.5, 1.0, 2.0}) {
    const auto b = make_biarc(p0, t0, p1, t1, ratio);
    ASSERT_TRUE(b.has_value());
    EXPECT_EQ(b->first.start.x, p0.x);
    EXPECT_EQ(b->second.end.y, p1.y);
    EXPECT_NEAR(norm(start_tangent(b->first) - t0), 0.0, 1e-12);
    EXPECT_NEAR(norm(end_tangent(b->second) - t1), 0.0, 1e-12);
    EXPECT_NEAR(norm(end_tangent(b->first) - start_tangent(b->second)), 0.0, 1e-9);
  }
}

TEST(Biarc, OfAnArcIsThatArc) {
  // two points of a circle of radius 5 with their tangents: both arcs lie on the circle
  const Vec2 c{1, 2};
  const double r = 5;
  const auto b = make_biarc(c + r * unit_at(0.2), perp(unit_at(0.2)), c + r * unit_at(1.9), perp(unit_at(1.9)));
  ASSERT_TRUE(b);
  EXPECT_NEAR(b->first.radius, r, 1e-9);
  EXPECT_NEAR(b->second.radius, r, 1e-9);
  EXPECT_NEAR(distance(b->first.centre, c), 0.0, 1e-9);
  EXPECT_NEAR(b->first.sweep + b->second.sweep, 1.7, 1e-9);
}

TEST(Biarc, StraightAndDegenerateEnds) {
  const auto b = make_biarc({0, 0}, {1, 0}, {5, 0}, {1, 0});
  ASSERT_TRUE(b);
  EXPECT_TRUE(b->first.line && b->second.line);
  std::vector<Arc2> chain;
  append_biarc(chain, {b->first, b->second});
  ASSERT_EQ(chain.size(), 1u);  // two collinear segments are one
  EXPECT_FALSE(make_biarc({1, 1}, {1, 0}, {1, 1}, {1, 0}));  // no chord
  EXPECT_FALSE(make_biarc({0, 0}, {-1, 0}, {5, 0}, {-1, 0}));  // tangents against the chord
}

// ---- NURBS fit -----------------------------------------------------------------------------

void expect_fit(const NurbsCurve& c, double tol, bool g1 = true) {
  BiarcOptions o;
  o.tolerance_mm = tol;
  const BiarcFit fit = fit_biarcs(c, 2, o);
  ASSERT_FALSE(fit.arcs.empty());
  EXPECT_TRUE(fit.within_tolerance);
  EXPECT_LE(fit.max_deviation_mm, tol);
  expect_chain(fit.arcs, g1);
  // ends exactly the curve's first and last control points
  EXPECT_EQ(fit.arcs.front().start.x, c.points.front()[0]);
  EXPECT_EQ(fit.arcs.front().start.y, c.points.front()[1]);
  EXPECT_EQ(fit.arcs.back().end.x, c.points.back()[0]);
  EXPECT_EQ(fit.arcs.back().end.y, c.points.back()[1]);
  // independent bound: a dense curve vs the arcs (chords of 40000 add < 1e-8 here)
  const double h = hausdorff(dense_curve(c, 40000), fit.arcs);
  EXPECT_LE(h, tol * 1.01 + 1e-8) << "measured " << fit.max_deviation_mm;
  // the measure agrees with the independent one (it is not a loose over-estimate either)
  EXPECT_NEAR(fit.max_deviation_mm, h, 0.05 * tol + 2e-8);
}

TEST(BiarcFit, FreeFormCurveWithInflectionWithinTolerance) {
  expect_fit(s_curve(), 0.001);
  expect_fit(s_curve(), 0.01);
  expect_fit(s_curve(), 1e-5);
}

TEST(BiarcFit, UnreachableToleranceEndsAndSaysSo) {
  BiarcOptions o;
  o.tolerance_mm = 1e-13;  // below what doubles can measure on a 40 mm curve
  o.min_chord_mm = 0.05;
  const BiarcFit fit = fit_biarcs(s_curve(), 2, o);
  EXPECT_FALSE(fit.within_tolerance);
  EXPECT_LT(fit.arcs.size(), 4000u);  // pieces of at least 0.05 mm, not 2^30 of them
  expect_chain(fit.arcs, true, 1e-6);
}

TEST(BiarcFit, FinerToleranceNeedsMoreBiarcs) {
  BiarcOptions coarse, fine;
  coarse.tolerance_mm = 0.01, fine.tolerance_mm = 0.0001;
  EXPECT_LT(fit_biarcs(s_curve(), 2, coarse).biarcs, fit_biarcs(s_curve(), 2, fine).biarcs);
}

TEST(BiarcFit, CircleComesBackAsItsArcs) {
  const NurbsCurve q = test::quarter_circle(7.0, {1, 1, 0});
  const BiarcFit fit = fit_biarcs(q, 2);
  ASSERT_FALSE(fit.arcs.empty());
  EXPECT_EQ(fit.biarcs, 1u);  // one biarc of a circular arc is that arc
  for (const Arc2& a : fit.arcs) {
    EXPECT_NEAR(a.radius, 7.0, 1e-9);
    EXPECT_GT(a.sweep, 0.0);  // counter-clockwise: G3
  }
  expect_fit(q, 0.001);
}

TEST(BiarcFit, FullCircleClosedCurve) {
  const NurbsCurve c = test::full_circle(4.0, {2, -1, 0});
  expect_fit(c, 0.001);
  const BiarcFit fit = fit_biarcs(c, 2);
  double sweep = 0;
  for (const Arc2& a : fit.arcs) sweep += a.sweep;
  EXPECT_NEAR(sweep, 2 * kPi, 1e-9);
}

TEST(BiarcFit, StraightNurbsIsOneSegment) {
  const NurbsCurve c = make_nurbs({{0, 0, 0}, {1, 1, 0}, {2, 2, 0}, {5, 5, 0}}, {1, 1, 1, 1}, 3);
  const BiarcFit fit = fit_biarcs(c, 2);
  ASSERT_EQ(fit.arcs.size(), 1u);
  EXPECT_TRUE(fit.arcs[0].line);
  EXPECT_LE(fit.max_deviation_mm, 1e-12);
}

TEST(BiarcFit, CornerKnotKeepsTheCorner) {
  // order 2 (a polygon): corners at the interior knots; each edge is one segment
  const NurbsCurve c = make_nurbs({{0, 0, 0}, {5, 0, 0}, {5, 5, 0}}, {1, 1, 1}, 2);
  const BiarcFit fit = fit_biarcs(c, 2);
  ASSERT_EQ(fit.arcs.size(), 2u);
  EXPECT_TRUE(fit.arcs[0].line && fit.arcs[1].line);
  EXPECT_EQ(fit.arcs[0].end.x, 5.0);
  EXPECT_EQ(fit.arcs[0].end.y, 0.0);
}

TEST(BiarcFit, OtherPlanes) {
  // the S-curve in the YZ plane (G19: plane axes Y, Z): same arcs as in XY
  NurbsCurve yz = s_curve();
  for (Vec3& p : yz.points) p = {3.0, p[0], p[1]};
  const BiarcFit a = fit_biarcs(s_curve(), 2), b = fit_biarcs(yz, 0);
  ASSERT_EQ(a.arcs.size(), b.arcs.size());
  for (std::size_t i = 0; i < a.arcs.size(); ++i) EXPECT_NEAR(a.arcs[i].sweep, b.arcs[i].sweep, 1e-12);
}

TEST(BiarcFit, DoubledStartPointHasAUsableTangent) {
  // LinuxCNC programs repeat the start point: zero parametric speed at u = 0
  const NurbsCurve c = make_nurbs({{0, 0, 0}, {0, 0, 0}, {5, 5, 0}, {10, 0, 0}, {15, 3, 0}}, {1, 1, 1, 1, 1}, 4);
  expect_fit(c, 0.001);
}

// ---- polyline fit ----------------------------------------------------------------------------

std::vector<Vec2> rounded_sine(double step, double round_to) {
  std::vector<Vec2> pts;
  for (double x = 0; x <= 20.0 + 1e-9; x += step) {
    const double y = 3.0 * std::sin(x / 3.0);
    pts.push_back({std::round(x / round_to) * round_to, std::round(y / round_to) * round_to});
  }
  return pts;
}

TEST(BiarcPolyline, ThroughEveryPointWithinToleranceAndFewerMoves) {
  const std::vector<Vec2> pts = rounded_sine(0.1, 0.001);
  const PolylineFit fit = fit_biarcs_polyline(pts);
  ASSERT_FALSE(fit.arcs.empty());
  EXPECT_TRUE(fit.within_tolerance);
  expect_chain(fit.arcs, true, 1e-6);
  EXPECT_EQ(fit.arcs.front().start.x, pts.front().x);
  EXPECT_EQ(fit.arcs.back().end.y, pts.back().y);
  const std::vector<Vec2> arcs = dense_chain(fit.arcs);
  double point_dev = 0;
  for (const Vec2& p : pts) point_dev = std::max(point_dev, chain_dist(p, fit.arcs));
  EXPECT_LE(point_dev, 0.001 + 1e-8);
  EXPECT_NEAR(point_dev, fit.max_point_deviation_mm, 1e-6);
  // arcs to segments: within tolerance + the chords' sagitta
  double seg_dev = 0;
  for (const Vec2& q : arcs) seg_dev = std::max(seg_dev, poly_dist(q, pts));
  EXPECT_LE(seg_dev, 0.001 + fit.max_sagitta_mm + 1e-8);
  EXPECT_LT(fit.arcs.size() * 4, pts.size());  // far fewer moves than the 200 segments
}

TEST(BiarcPolyline, CollinearPointsAreOneSegment) {
  std::vector<Vec2> pts;
  for (int i = 0; i <= 20; ++i) pts.push_back({0.1 * i, 0.05 * i});
  const PolylineFit fit = fit_biarcs_polyline(pts);
  ASSERT_EQ(fit.arcs.size(), 1u);
  EXPECT_TRUE(fit.arcs[0].line);
}

TEST(BiarcPolyline, DegenerateInputs) {
  EXPECT_TRUE(fit_biarcs_polyline({}).arcs.empty());
  EXPECT_TRUE(fit_biarcs_polyline({{1, 1}}).arcs.empty());
  EXPECT_TRUE(fit_biarcs_polyline({{1, 1}, {1, 1}, {1, 1}}).arcs.empty());
  const PolylineFit two = fit_biarcs_polyline({{0, 0}, {0, 0}, {1, 0}});
  ASSERT_EQ(two.arcs.size(), 1u);
  EXPECT_EQ(two.arcs[0].end.x, 1.0);
}

TEST(BiarcPolyline, CirclePolylineWithInflectionFreeArcs) {
  // 0.2 mm chords of a circle of radius 10: the arcs are the circle
  std::vector<Vec2> pts;
  for (int i = 0; i <= 50; ++i) pts.push_back(10.0 * unit_at(0.02 * i));
  const PolylineFit fit = fit_biarcs_polyline(pts);
  ASSERT_LE(fit.arcs.size(), 2u);
  for (const Arc2& a : fit.arcs) EXPECT_NEAR(a.radius, 10.0, 1e-3);
}

// ---- offsets ----------------------------------------------------------------------------------

TEST(ArcOffset, RadiusChangesAboutTheSameCentre) {
  const Arc2 ccw = make_arc_about({0, 0}, {5, 0}, kPi / 2);  // G3, left is the centre
  const ArcOffset in = offset_arc(ccw, 2.0), out = offset_arc(ccw, -2.0);
  EXPECT_NEAR(in.arc.radius, 3.0, 1e-12);
  EXPECT_NEAR(out.arc.radius, 7.0, 1e-12);
  EXPECT_FALSE(in.collapsed || out.collapsed);
  EXPECT_NEAR(in.arc.end.y, 3.0, 1e-12);
  const Arc2 cw = reversed(ccw);  // G2: left is away from the centre
  EXPECT_NEAR(offset_arc(cw, 2.0).arc.radius, 7.0, 1e-12);
  // collapse: to the centre, then inside out
  EXPECT_TRUE(offset_arc(ccw, 5.0).collapsed);
  const ArcOffset inv = offset_arc(ccw, 6.0);
  EXPECT_TRUE(inv.collapsed);
  EXPECT_NEAR(inv.arc.radius, 1.0, 1e-12);
  EXPECT_NEAR(inv.arc.start.x, -1.0, 1e-12);
  // a segment shifts along its left normal
  const ArcOffset s = offset_arc(make_segment({0, 0}, {4, 0}), 1.5);
  EXPECT_NEAR(s.arc.start.y, 1.5, 1e-15);
  EXPECT_NEAR(s.arc.end.x, 4.0, 1e-15);
}

TEST(ArcOffset, ChainOffsetIsAtExactDistance) {
  const BiarcFit fit = fit_biarcs(s_curve(), 2);
  for (double d : {1.0, -1.0}) {
    const std::vector<Arc2> off = offset_chain(fit.arcs, d);
    EXPECT_EQ(off.size(), fit.arcs.size());  // G1 chain: no corner arcs
    for (const Vec2& q : dense_chain(off, 50)) EXPECT_NEAR(nearest_on_arcs(fit.arcs, q), 1.0, 1e-9);
  }
}

TEST(ArcOffset, CornerGetsAnArcAboutIt) {
  const std::vector<Arc2> square = {make_segment({0, 0}, {4, 0}), make_segment({4, 0}, {4, 4})};
  const std::vector<Arc2> off = offset_chain(square, -1.0);  // right side: outside of the left turn
  ASSERT_EQ(off.size(), 3u);
  EXPECT_FALSE(off[1].line);
  EXPECT_NEAR(off[1].radius, 1.0, 1e-12);
  EXPECT_NEAR(off[1].sweep, kPi / 2, 1e-12);
  EXPECT_NEAR(off[1].centre.x, 4.0, 1e-15);
}

// ---- intersections --------------------------------------------------------------------------

TEST(ArcIntersect, CircleCircleLineExact) {
  const Arc2 a = make_arc_about({0, 0}, {5, 0}, 2 * kPi - 1e-9);
  const Arc2 b = make_arc_about({6, 0}, {1, 0}, kPi);  // from (1,0) ccw over the bottom half
  const auto x = intersect(a, b);
  ASSERT_EQ(x.size(), 1u);  // (3, -4) is on b's lower half; (3, 4) is not
  EXPECT_NEAR(x[0].point.x, 3.0, 1e-12);
  EXPECT_NEAR(x[0].point.y, -4.0, 1e-12);
  const auto y = intersect(make_segment({-10, 3}, {10, 3}), a);
  ASSERT_EQ(y.size(), 2u);
  EXPECT_NEAR(std::abs(y[0].point.x), 4.0, 1e-12);
  const auto z = intersect(make_segment({0, 0}, {2, 2}), make_segment({0, 2}, {2, 0}));
  ASSERT_EQ(z.size(), 1u);
  EXPECT_NEAR(z[0].fa, 0.5, 1e-15);
  EXPECT_TRUE(intersect(make_segment({0, 0}, {1, 0}), make_segment({0, 1}, {1, 1})).empty());
}

// ---- loop removal --------------------------------------------------------------------------

// The smallest distance from the offset of `chain` by d to the chain itself: d where the tool
// follows without tangling, less where a loop of the offset cuts into the contour.
double offset_clearance(const std::vector<Arc2>& chain, double d) {
  const std::vector<Arc2> off = offset_chain(chain, d);
  double m = 1e300;
  for (const Vec2& q : dense_chain(off, 200)) {
    double best = 1e300;
    for (const Arc2& a : chain)
      for (const Vec2& p : dense(a, 200)) best = std::min(best, distance(p, q));
    m = std::min(m, best);
  }
  return m;
}

// A line with a narrow notch: left 0..10, a 2 mm wide, 3 mm deep slot, on to 20.
std::vector<Arc2> notched() {
  return {make_segment({0, 0}, {9, 0}), make_segment({9, 0}, {9, -3}), make_segment({9, -3}, {11, -3}),
          make_segment({11, -3}, {11, 0}), make_segment({11, 0}, {20, 0})};
}

TEST(LoopRemoval, NotchNarrowerThanTheToolIsBridged) {
  const double R = 3.0;
  const std::vector<Arc2> chain = notched();
  // on the left (above: the slot, 2 mm wide, opens toward the tool): the raw offset tangles
  EXPECT_LT(offset_clearance(chain, R), R - 0.5);
  const LoopRemoval r = remove_loops(chain, R, +1);
  EXPECT_GE(r.loops_removed, 1);
  EXPECT_EQ(r.unresolved, 0);
  expect_chain(r.arcs, false);
  EXPECT_EQ(r.arcs.front().start.x, 0.0);
  EXPECT_EQ(r.arcs.back().end.x, 20.0);
  EXPECT_GT(offset_clearance(r.arcs, R), R - 1e-3);
  // smaller tools fit the new contour too (the point of removing for the largest one)
  EXPECT_GT(offset_clearance(r.arcs, 1.0), 1.0 - 1e-3);
  // the slot is bridged: the new contour stays above its bottom
  double lowest = 0;
  for (const Vec2& p : dense_chain(r.arcs, 50)) lowest = std::min(lowest, p.y);
  EXPECT_GT(lowest, -3.0 + 0.5);
  EXPECT_GT(r.max_change_mm, 0.5);
  // on the right the slot is a tab the tool goes round: the concave corners where it meets the
  // line are loops of the raw offset too; they become fillets of radius R, the tab stays
  const LoopRemoval tab = remove_loops(chain, R, -1);
  EXPECT_GE(tab.loops_removed, 2);
  EXPECT_GT(offset_clearance(tab.arcs, -R), R - 1e-3);
  lowest = 0;
  for (const Vec2& p : dense_chain(tab.arcs, 50)) lowest = std::min(lowest, p.y);
  EXPECT_NEAR(lowest, -3.0, 1e-9);
  int fillets = 0;
  for (const Arc2& a : tab.arcs) fillets += !a.line && std::abs(a.radius - R) < 1e-9;
  EXPECT_EQ(fillets, 2);
}

TEST(LoopRemoval, SmallConcaveArcBiarcsAreRounded) {
  // an S-curve fitted with biarcs, offset by more than its tightest radius on the inside
  const BiarcFit fit = fit_biarcs(s_curve(), 2);
  double min_r = 1e300;
  for (const Arc2& a : fit.arcs) min_r = std::min(min_r, a.line ? 1e300 : a.radius);
  const double R = min_r * 1.5;
  const LoopRemoval r = remove_loops(fit.arcs, R, +1);
  EXPECT_GE(r.loops_removed, 1);
  expect_chain(r.arcs, false);  // every arc whole: its ends on its circle, pieces joined
  EXPECT_GT(offset_clearance(r.arcs, R), R - 1e-3);
  // a tool smaller than every radius: nothing to remove, the chain is returned as is
  const LoopRemoval none = remove_loops(fit.arcs, min_r * 0.5, +1);
  EXPECT_EQ(none.loops_removed, 0);
  EXPECT_EQ(none.arcs.size(), fit.arcs.size());
}

TEST(LoopRemoval, ClosedContourComesBackClosedFromItsStart) {
  // a 20 x 10 rectangle, counter-clockwise from the middle of its top edge, with a slot 2 mm
  // wide and 3 mm deep in its bottom edge; a tool of radius 3 outside (on the right)
  const std::vector<Arc2> box = {
      make_segment({10, 10}, {0, 10}), make_segment({0, 10}, {0, 0}),  make_segment({0, 0}, {9, 0}),
      make_segment({9, 0}, {9, 3}),    make_segment({9, 3}, {11, 3}),  make_segment({11, 3}, {11, 0}),
      make_segment({11, 0}, {20, 0}),  make_segment({20, 0}, {20, 10}), make_segment({20, 10}, {10, 10})};
  const double R = 3.0;
  EXPECT_LT(offset_clearance(box, -R), R - 0.5);  // the raw offset dives into the slot
  const LoopRemoval r = remove_loops(box, R, -1);
  EXPECT_GE(r.loops_removed, 1);
  EXPECT_EQ(r.unresolved, 0);
  expect_chain(r.arcs, false);
  EXPECT_EQ(r.arcs.front().start.x, 10.0);  // closed, from where it started
  EXPECT_EQ(r.arcs.front().start.y, 10.0);
  EXPECT_EQ(r.arcs.back().end.x, 10.0);
  EXPECT_EQ(r.arcs.back().end.y, 10.0);
  EXPECT_GT(offset_clearance(r.arcs, -R), R - 1e-3);
  double highest = 0;  // the slot (up to y = 3) is bridged below y = 1
  for (const Vec2& p : dense_chain(r.arcs, 50))
    if (p.x > 9.5 && p.x < 10.5 && p.y < 5) highest = std::max(highest, p.y);
  EXPECT_LT(highest, 1.0);
  // the same contour started inside the slot: its start is cut off, it comes back as it was
  std::vector<Arc2> from_slot(box.begin() + 4, box.end());
  from_slot.insert(from_slot.end(), box.begin(), box.begin() + 4);
  const LoopRemoval s = remove_loops(from_slot, R, -1);
  EXPECT_EQ(s.loops_removed, 0);
  EXPECT_GT(s.unresolved, 0);
  EXPECT_EQ(s.arcs.size(), from_slot.size());
}

TEST(LoopRemoval, InsideOutWithoutCrossingIsReported) {
  // up x = 0, a half circle of radius 1 over to x = 2, down: parallel legs 2 mm apart; a tool
  // of radius 2 inside: the legs' offsets swap sides without crossing
  const std::vector<Arc2> u = {make_segment({0, -3}, {0, 0}), make_arc_about({1, 0}, {0, 0}, -kPi),
                               make_segment({2, 0}, {2, -3})};
  const LoopRemoval r = remove_loops(u, 2.0, -1);
  EXPECT_GT(r.unresolved, 0);
  EXPECT_EQ(remove_loops(u, 0.5, -1).unresolved, 0);  // a tool that fits
  EXPECT_EQ(remove_loops(u, 2.0, +1).unresolved, 0);  // outside
}

// ---- moves ---------------------------------------------------------------------------------

TEST(BiarcMoves, ArcsBecomeArcMovesInThePlane) {
  Move like;
  like.line = 12;
  like.feed_mm_s = 10;
  const std::vector<Arc2> arcs = {make_arc_about({0, 0}, {5, 0}, kPi / 2), make_segment({0, 5}, {-3, 5})};
  const std::vector<Move> g17 = arc_moves(arcs, 2, 1.5, like);
  ASSERT_EQ(g17.size(), 2u);
  EXPECT_EQ(g17[0].kind, MoveKind::kArc);
  EXPECT_EQ(g17[0].line, 12);
  EXPECT_NEAR(g17[0].end[1], 5.0, 1e-12);
  EXPECT_EQ(g17[0].end[2], 1.5);
  EXPECT_GT(g17[0].sweep, 0.0);
  EXPECT_EQ(g17[1].kind, MoveKind::kLine);
  EXPECT_EQ(g17[1].start, g17[0].end);
  // G18: plane axes Z, X; the arc's plane x is Z
  const std::vector<Move> g18 = arc_moves(arcs, 1, -2.0, like);
  EXPECT_EQ(g18[0].start[2], 5.0);
  EXPECT_EQ(g18[0].start[1], -2.0);
  EXPECT_EQ(g18[0].normal_axis, 1);
}

}  // namespace
}  // namespace pcnc
