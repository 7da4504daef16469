// test_arc_packing.cpp — chains of short arcs as one exact curve: the rational quadratic NURBS
// of a chain of arcs (shared/geometry/arc_nurbs.hpp) lies on the arcs and passes through their
// ends, in every plane and both directions; the packing stage (host/gcode/arc_packing.hpp)
// packs a chain of short tangent arcs into one curve whose line marks name each arc, and leaves
// what it must not pack (helices, M22, tolerance 0, a change of feed, a real corner, arcs the
// ring does not slow) as arcs; the feed schedule passes a kink of a packed curve at a speed
// whose velocity step stays within a share of one cycle's acceleration, and a larger turn is a
// corner.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "config/config.hpp"
#include "gcode/arc_packing.hpp"
#include "gcode/nurbs_schedule.hpp"
#include "geometry/arc_nurbs.hpp"
#include "geometry/nurbs.hpp"
#include "geometry/plane.hpp"
#include "move_stage.hpp"
#include "test_paths.hpp"
#include "test_constants.hpp"

using namespace pcnc;

namespace {


// A chain of `n` arcs, each sweeping `sweep` (signed), tangent at every join: arc k has radius
// radius(k), its center on the normal of the path at its start. Starts at `from` heading along
// `heading` (rad from the first plane axis toward the second), in the plane normal to `normal`,
// on feed 100 mm/s under M21 with a tolerance of 5 um.
template <class Radius>
std::vector<Move> tangent_chain(int normal, Vec3 from, int n, double sweep, Radius radius, int first_line = 10,
                                double heading = 0.0) {
  const auto pa = plane_axes(normal);
  std::vector<Move> v;
  for (int k = 0; k < n; ++k) {
    const double r = radius(k);
    const double side = sweep > 0.0 ? 1.0 : -1.0;  // the center lies left of travel for G3
    Move m;
    m.kind = MoveKind::kArc;
    m.line = first_line + k;
    m.feed_mm_s = 100.0;
    m.contouring = true;
    m.path_tolerance_mm = 0.005;
    m.normal_axis = normal;
    m.start = from;
    m.center = from;
    m.center[pa[0]] += side * r * std::cos(heading + kPi / 2.0);
    m.center[pa[1]] += side * r * std::sin(heading + kPi / 2.0);
    const double a0 = std::atan2(from[pa[1]] - m.center[pa[1]], from[pa[0]] - m.center[pa[0]]);
    m.end = m.center;
    m.end[pa[0]] += r * std::cos(a0 + sweep);
    m.end[pa[1]] += r * std::sin(a0 + sweep);
    m.radius = r;
    m.sweep = sweep;
    v.push_back(m);
    from = m.end;
    heading += sweep;
  }
  return v;
}

std::vector<Move> pack(const std::vector<Move>& in, ArcPackingStats* stats = nullptr) {
  const MachineConfig config = load_config(test::default_config());
  ArcPacker packer(config);
  std::vector<Move> out = test::run_move_stage(packer, in);
  if (stats) *stats = packer.stats();
  return out;
}

PlaneArc plane_arc_of(const Move& m) { return {m.start, m.end, m.center, m.sweep, m.normal_axis}; }

// The distance of p from arc m's circle, and whether p lies within its sweep (to 1e-9 rad).
struct OnArc {
  double distance = 0.0;
  bool within = false;
};
OnArc on_arc(const Move& m, const Vec3& p) {
  const auto pa = plane_axes(m.normal_axis);
  const double a0 = std::atan2(m.start[pa[1]] - m.center[pa[1]], m.start[pa[0]] - m.center[pa[0]]);
  const double ap = std::atan2(p[pa[1]] - m.center[pa[1]], p[pa[0]] - m.center[pa[0]]);
  double phi = (ap - a0) * (m.sweep > 0.0 ? 1.0 : -1.0);
  while (phi < -1e-9) phi += 2.0 * kPi;
  const double rho = std::hypot(p[pa[0]] - m.center[pa[0]], p[pa[1]] - m.center[pa[1]]);
  return {std::hypot(rho - m.radius, p[m.normal_axis] - m.start[m.normal_axis]), phi <= std::abs(m.sweep) + 1e-9};
}

}  // namespace

TEST(ArcNurbs, AChainOfArcsIsTheSameCirclesThroughTheSameEnds) {
  for (const int normal : {0, 1, 2}) {
    for (const double sweep : {0.3, -0.3, 3.7, -5.0}) {  // 3.7 and 5.0 rad: arcs of several pieces
      const std::vector<Move> chain =
          tangent_chain(normal, {12.5, 12.5, 12.5}, 4, sweep, [](int k) { return 2.0 + 0.5 * k; });
      std::vector<PlaneArc> arcs;
      for (const Move& m : chain) arcs.push_back(plane_arc_of(m));
      std::vector<double> starts;
      const NurbsCurve c = arc_chain_nurbs(arcs, &starts);
      ASSERT_EQ(validate(c), "");
      EXPECT_EQ(c.degree, 2);
      ASSERT_EQ(starts.size(), chain.size());
      EXPECT_EQ(c.points.front(), chain.front().start);
      EXPECT_EQ(c.points.back(), chain.back().end);
      const NurbsView v = c.view();
      for (std::size_t k = 0; k < chain.size(); ++k) {
        const double u0 = starts[k], u1 = k + 1 < starts.size() ? starts[k + 1] : c.u_max();
        // the knots are arc length
        EXPECT_NEAR(u1 - u0, chain[k].radius * std::abs(sweep), 1e-12);
        EXPECT_LT(norm(nurbs_point(v, u0) - chain[k].start), 1e-12);
        EXPECT_LT(norm(nurbs_point(v, u1) - chain[k].end), 1e-12);
        for (int j = 1; j < 40; ++j) {
          const Vec3 p = nurbs_point(v, u0 + (u1 - u0) * j / 40.0);
          const OnArc o = on_arc(chain[k], p);
          EXPECT_LT(o.distance, 1e-12) << "normal " << normal << " sweep " << sweep << " arc " << k;
          EXPECT_TRUE(o.within) << "normal " << normal << " sweep " << sweep << " arc " << k << " j " << j;
        }
        // leaves along the direction of travel
        const Vec3 t = nurbs_tangent(v, u0, true);
        EXPECT_NEAR(dot(t, plane_arc_tangent(arcs[k], 0.0)), 1.0, 1e-12);
      }
      // tangent chains make no corners
      EXPECT_TRUE(corner_knots(c).empty());
    }
  }
}

TEST(ArcNurbs, TheTangentFollowsTheRightHandRuleOfThePlane) {
  // G17 counter-clockwise from +X about the origin: the quarter arc's middle is at +X +Y; G18
  // counter-clockwise (seen from +Y) goes from +Z toward +X; G19 from +Y toward +Z.
  const Vec3 o{0, 0, 0};
  const PlaneArc g17{{1, 0, 0}, {0, 1, 0}, o, kPi / 2.0, 2};
  const PlaneArc g18{{0, 0, 1}, {1, 0, 0}, o, kPi / 2.0, 1};
  const PlaneArc g19{{0, 1, 0}, {0, 0, 1}, o, kPi / 2.0, 0};
  const double h = std::sqrt(0.5);
  EXPECT_LT(norm(plane_arc_point(g17, kPi / 4.0) - Vec3{h, h, 0}), 1e-15);
  EXPECT_LT(norm(plane_arc_point(g18, kPi / 4.0) - Vec3{h, 0, h}), 1e-15);
  EXPECT_LT(norm(plane_arc_point(g19, kPi / 4.0) - Vec3{0, h, h}), 1e-15);
  EXPECT_LT(norm(plane_arc_tangent(g17, 0.0) - Vec3{0, 1, 0}), 1e-15);
  EXPECT_LT(norm(plane_arc_tangent(g18, 0.0) - Vec3{1, 0, 0}), 1e-15);
  for (const PlaneArc& a : {g17, g18, g19}) {
    const NurbsCurve c = arc_chain_nurbs({a});
    const NurbsView v = c.view();
    EXPECT_LT(norm(nurbs_point(v, 0.5 * (v.u_min() + v.u_max())) - plane_arc_point(a, kPi / 4.0)), 1e-15);
  }
}

TEST(ArcPacking, AChainOfShortTangentArcsBecomesOneExactCurve) {
  // 60 arcs of 6° on radii 5.5-6.5 mm, 0.6 mm each: at 100 mm/s the machine stops within three
  // of them only from 85 mm/s, so the ring would slow them
  const std::vector<Move> chain = tangent_chain(2, {12.5, 6.0, 20.0}, 60, 6.0 * kPi / 180.0,
                                                [](int k) { return 6.0 + 0.5 * std::sin(0.1 * k); });
  ArcPackingStats stats;
  const std::vector<Move> out = pack(chain, &stats);
  ASSERT_EQ(out.size(), 1u);
  const Move& c = out.front();
  EXPECT_EQ(c.kind, MoveKind::kNurbs);
  EXPECT_TRUE(c.packed_arcs);
  EXPECT_FALSE(c.smoothed);
  EXPECT_EQ(c.start, chain.front().start);
  EXPECT_EQ(c.end, chain.back().end);
  EXPECT_EQ(c.feed_mm_s, 100.0);
  EXPECT_EQ(c.line, chain.front().line);
  ASSERT_TRUE(c.nurbs && c.line_marks);
  ASSERT_EQ(c.line_marks->size(), chain.size());
  for (std::size_t k = 0; k < chain.size(); ++k) {
    EXPECT_EQ((*c.line_marks)[k].line, chain[k].line);
    EXPECT_LT(norm(nurbs_point(c.nurbs->view(), (*c.line_marks)[k].u) - chain[k].start), 1e-12);
  }
  EXPECT_EQ(stats.arcs, 60u);
  EXPECT_EQ(stats.curves, 1u);
  EXPECT_LT(stats.max_deviation_mm, 1e-9);
}

TEST(ArcPacking, WhatMustNotBePackedStaysArcs) {
  const double sweep = 6.0 * kPi / 180.0;
  auto six = [](int) { return 6.0; };
  auto all_arcs = [](const std::vector<Move>& v) {
    for (const Move& m : v) {
      if (m.kind != MoveKind::kArc) return false;
    }
    return true;
  };
  {  // a helix: the normal axis moves
    std::vector<Move> c = tangent_chain(2, {12.5, 6.0, 20.0}, 10, sweep, six);
    for (std::size_t k = 0; k < c.size(); ++k) {
      c[k].start[2] -= 0.01 * k;
      c[k].end[2] -= 0.01 * (k + 1);
      c[k].center[2] = c[k].start[2];
    }
    EXPECT_TRUE(all_arcs(pack(c)));
  }
  {  // M22, and tolerance 0 (the seed's rule runs arcs as the rt always has)
    std::vector<Move> m22 = tangent_chain(2, {12.5, 6.0, 20.0}, 10, sweep, six), t0 = m22;
    for (Move& m : m22) m.contouring = false;
    for (Move& m : t0) m.path_tolerance_mm = 0.0;
    EXPECT_TRUE(all_arcs(pack(m22)));
    EXPECT_TRUE(all_arcs(pack(t0)));
  }
  {  // long arcs: the ring holds enough of them (radius 6, 60°: 6.3 mm each)
    EXPECT_TRUE(all_arcs(pack(tangent_chain(2, {12.5, 6.0, 20.0}, 5, kPi / 3.0, six))));
  }
  {  // a single short arc
    EXPECT_TRUE(all_arcs(pack(tangent_chain(2, {12.5, 6.0, 20.0}, 1, sweep, six))));
  }
  {  // a change of feed splits the chain: two curves
    std::vector<Move> c = tangent_chain(2, {12.5, 6.0, 20.0}, 10, sweep, six);
    for (std::size_t k = 5; k < c.size(); ++k) c[k].feed_mm_s = 90.0;
    const std::vector<Move> out = pack(c);
    ASSERT_EQ(out.size(), 2u);
    EXPECT_EQ(out[0].end, c[4].end);
    EXPECT_EQ(out[1].feed_mm_s, 90.0);
  }
  {  // a real corner: the sixth arc leaves 2° off the fifth's end tangent
    std::vector<Move> a = tangent_chain(2, {12.5, 6.0, 20.0}, 5, sweep, six);
    const std::vector<Move> first = a;
    const std::vector<Move> b = tangent_chain(2, a.back().end, 5, sweep, six, 20, 5.0 * sweep + 2.0 * kPi / 180.0);
    a.insert(a.end(), b.begin(), b.end());
    const std::vector<Move> out = pack(a);
    ASSERT_EQ(out.size(), 2u);
    EXPECT_EQ(out[0].end, first.back().end);
    EXPECT_TRUE(out[0].packed_arcs);
    EXPECT_TRUE(out[1].packed_arcs);
  }
}

TEST(ArcPacking, AnEndPointARoundingOffItsRadiusIsFollowedAsTheRtRunsArcs) {
  // CAM rounds arc ends: each end here sits 0.2 um outside the start's radius. The curve keeps
  // the programmed ends and stays within a few nanometres of the arcs as the rt runs them (the
  // radius changing linearly with the angle), measured by the stage.
  std::vector<Move> c = tangent_chain(2, {12.5, 6.0, 20.0}, 20, 6.0 * kPi / 180.0, [](int) { return 6.0; });
  for (std::size_t k = 0; k < c.size(); ++k) {
    c[k].end = c[k].center + (c[k].end - c[k].center) * ((6.0 + 2e-4) / 6.0);
    if (k > 0) {
      c[k].start = c[k - 1].end;
      c[k].radius = std::hypot(c[k].start[0] - c[k].center[0], c[k].start[1] - c[k].center[1]);
    }
  }
  ArcPackingStats stats;
  const std::vector<Move> out = pack(c, &stats);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].end, c.back().end);
  EXPECT_GT(stats.max_deviation_mm, 0.0);
  EXPECT_LT(stats.max_deviation_mm, 1e-5);
}

TEST(ArcPacking, TheScheduleCapsAKinkAndStopsAtACorner) {
  const MachineConfig config = load_config(test::default_config());
  const NurbsLimits lim = nurbs_limits(config, 100.0);
  for (const double turn : {5e-4, 3e-3}) {
    // two arcs of radius 6, the second leaving `turn` rad off the first's end tangent
    PlaneArc a{{0, 0, 0}, {}, {0, 6, 0}, 0.1, 2};
    a.end = plane_arc_point(a, 0.1);
    PlaneArc b = a;
    b.start = a.end;
    const double h = 0.1 + turn;  // heading of b's start
    b.center = a.end + Vec3{6.0 * std::cos(h + kPi / 2.0), 6.0 * std::sin(h + kPi / 2.0), 0.0};
    b.end = plane_arc_point(b, 0.1);
    const NurbsCurve c = arc_chain_nurbs({a, b});
    const std::vector<double> corners = corner_knots(c);
    const FeedSchedule s = plan_nurbs_feed(c, lim, 0.0, 0.0);
    const double u_join = c.knots[3];
    double at_join = -1.0;
    for (const FeedSample& f : s.samples) {
      if (f.u == u_join) at_join = f.limit;
    }
    ASSERT_GE(at_join, 0.0);
    if (turn < kTangentKinkTurn) {
      EXPECT_TRUE(corners.empty());
      // the velocity step per axis at the join within kKinkStepShare of a cycle's acceleration
      const Vec3 t0 = nurbs_tangent(c.view(), std::nextafter(u_join, 0.0), false);
      const Vec3 t1 = nurbs_tangent(c.view(), u_join, true);
      for (std::size_t i = 0; i < 3; ++i) {
        EXPECT_LE(at_join * std::abs(t1[i] - t0[i]),
                  kKinkStepShare * lim.axis_accel_mm_s2[i] * lim.period_s * (1.0 + 1e-9));
      }
      EXPECT_GT(at_join, 10.0) << "a kink is passed at speed";
    } else {
      ASSERT_EQ(corners.size(), 1u);
      EXPECT_EQ(corners.front(), u_join);
      EXPECT_EQ(at_join, 0.0);
    }
  }
}
