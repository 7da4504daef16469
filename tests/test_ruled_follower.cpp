// test_ruled_follower.cpp — the rt's evaluator of a ruled-surface piece (rt/motion/
// ruled_follower.hpp) on the XYZAC machine of configs/desktop-5axis.toml: the feed at
// constant-feed stretches within 0.1 % of the programmed feed; the analytic motion and joint
// feed-forward against finite differences of the pose and joints along u(t) integrated by
// RK4; a cylinder and a cone (closed forms: the axis's rates vanish and the acceleration is
// the directrix's curvature times F^2; the apex stands still on every ruling); the joints
// against the forward kinematics; the last cycle ends exactly at the piece's end.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "config/config.hpp"
#include "geometry/kinematics.hpp"
#include "geometry/ruled_model.hpp"
#include "ipc/block_ruled.hpp"
#include "motion/ruled_follower.hpp"
#include "test_constants.hpp"

namespace pcnc {
namespace {

constexpr double kPeriod = 0.0005;  // 2 kHz

Kinematics desktop_kinematics(double tool_length) {
  const MachineConfig cfg = load_config(std::string(PCNC_SOURCE_DIR) + "/configs/desktop-5axis.toml");
  Kinematics k = cfg.kinematics;
  k.tool_length = tool_length;
  return k;
}

// A freeform piece inside the desktop mill's travel: the tip on a wavy arc around the table
// centre, the axis tilted 20-35 degrees and turning in azimuth (A and C both move).
void wavy_piece(int n, std::vector<Vec3>& pts, std::vector<Vec3>& axes) {
  pts.clear();
  axes.clear();
  for (int i = 0; i <= n; ++i) {
    const double t = 1.2 * i / n;
    pts.push_back({12.5 + 6.0 * std::cos(t), 12.5 + 6.0 * std::sin(t), 3.0 + 0.8 * std::sin(3.0 * t)});
    const double tilt = (20.0 + 15.0 * std::sin(2.0 * t)) * kPi / 180.0;
    const double az = 0.3 + 1.5 * t;
    axes.push_back({std::sin(tilt) * std::cos(az), std::sin(tilt) * std::sin(az), std::cos(tilt)});
  }
}

RuledGeometry geometry_of(const std::vector<Vec3>& pts, const std::vector<Vec3>& axes, double feed, double accel,
                          double v0, double v1) {
  const RuledModelResult m = ruled_model_through(pts, axes, RulingForm::kVector);
  EXPECT_EQ(m.error, "");
  RuledGeometry g;
  EXPECT_EQ(to_geometry(m.model, feed, accel, v0, v1, g), "");
  return g;
}

Joints start_joints(const Kinematics& kin, const RuledGeometry& g) {
  const RuledJet j = ruled_jet(curves_of(g), 0.0);
  return inverse(kin, ToolPose{j.c.p, normalized(j.e.p)}, Joints{0, 0, 0, 0, 0});
}

std::vector<RuledSample> run(const RuledGeometry& g, const Kinematics& kin, double period) {
  RuledFollower f;
  f.start(g, kin, RotaryTravel{}, start_joints(kin, g));
  std::vector<RuledSample> out;
  for (int k = 0; k < 10'000'000 && !f.done(); ++k) out.push_back(f.step(g, period));
  EXPECT_TRUE(f.done());
  return out;
}

TEST(RuledFollower, FeedWithinATenthOfAPercentAtConstantFeed) {
  const Kinematics kin = desktop_kinematics(20.0);
  std::vector<Vec3> pts, axes;
  for (const int n : {6, 24}) {
    wavy_piece(n, pts, axes);
    for (const double feed : {10.0, 50.0}) {
      const RuledGeometry g = geometry_of(pts, axes, feed, 5000.0, 0.0, 0.0);
      for (const double period : {kPeriod, 0.01}) {
        const std::vector<RuledSample> s = run(g, kin, period);
        int constant = 0;
        double worst = 0.0;
        for (const RuledSample& x : s) {
          if (x.last || x.dfeed != 0.0) continue;
          ++constant;
          EXPECT_DOUBLE_EQ(x.feed, feed);
          worst = std::max(worst, std::abs(x.chord / (feed * period) - 1.0));
          // the sample's velocity is the programmed feed along the directrix
          EXPECT_NEAR(norm(x.motion.velocity), feed, 1e-9 * feed);
        }
        EXPECT_GT(constant, static_cast<int>(s.size()) / 2) << "most of the piece at constant feed";
        EXPECT_LE(worst, 1e-3) << "n " << n << " F " << feed << " T " << period;
        // The Taylor step with the chord correction is much better than the 0.1 % goal.
        EXPECT_LE(worst, 1e-8) << "n " << n << " F " << feed << " T " << period;
      }
    }
  }
}

TEST(RuledFollower, RampsAtTheAccelerationAndStopsAtTheEnd) {
  const Kinematics kin = desktop_kinematics(20.0);
  std::vector<Vec3> pts, axes;
  wavy_piece(12, pts, axes);
  const double a = 500.0, feed = 40.0;
  const RuledGeometry g = geometry_of(pts, axes, feed, a, 0.0, 0.0);
  const std::vector<RuledSample> s = run(g, kin, kPeriod);
  double prev = 0.0;
  for (const RuledSample& x : s) {
    if (x.last) {
      // it arrives nearly stopped: the cap left at most two cycles' speed change
      EXPECT_LE(prev, 2.0 * a * kPeriod);
      break;
    }
    EXPECT_LE(std::abs(x.feed - prev), a * kPeriod * (1 + 1e-9));
    EXPECT_LE(x.feed, feed * (1 + 1e-12));
    // during the ramps, the travelled chord is the trapezoid (F + F+)/2 T to the same precision
    if (!x.last && x.target > 0.0) {
      EXPECT_NEAR(x.chord, x.target, 1e-9 * x.target);
    }
    prev = x.feed;
  }
  EXPECT_EQ(s.back().feed, 0.0);
  // time: at least the time of the ramps plus the rest at F
  const double t_min = g.length / feed + feed / a;
  EXPECT_GE(s.size() * kPeriod, t_min * 0.999);
  EXPECT_LE(s.size() * kPeriod, t_min * 1.01);
}

TEST(RuledFollower, NeverOvershootsThePieceEnd) {
  const Kinematics kin = desktop_kinematics(0.0);
  std::vector<Vec3> pts, axes;
  wavy_piece(5, pts, axes);
  for (const double end_speed : {0.0, 25.0}) {
    for (const double period : {kPeriod, 0.0013, 0.01}) {
      const RuledGeometry g = geometry_of(pts, axes, 25.0, 2000.0, 25.0, end_speed);
      RuledFollower f;
      f.start(g, kin, RotaryTravel{}, start_joints(kin, g));
      double u_prev = 0.0;
      int cycles = 0;
      while (!f.done() && cycles < 1'000'000) {
        const RuledSample& x = f.step(g, period);
        ++cycles;
        EXPECT_GE(x.u, u_prev);
        EXPECT_LE(x.u, g.segment_count);
        EXPECT_LE(x.chord, x.target * (1 + 1e-9) + 1e-15);
        u_prev = x.u;
      }
      ASSERT_TRUE(f.done());
      EXPECT_EQ(f.sample().u, static_cast<double>(g.segment_count));
      EXPECT_LE(norm(f.sample().motion.position - pts.back()), 1e-12);
      EXPECT_LE(norm(f.sample().motion.A - normalized(axes.back())), 1e-12);
      EXPECT_LE(f.travelled(), g.length + 1e-9);
      EXPECT_GE(f.travelled(), g.length - 1e-6);
      EXPECT_EQ(f.sample().feed, end_speed);
      // further steps stay put
      const RuledSample after = f.step(g, period);
      EXPECT_EQ(after.u, f.sample().u);
    }
  }
}

TEST(RuledFollower, ALongPieceSplitIntoBlocksKeepsTheFeedAcrossTheJoins) {
  const Kinematics kin = desktop_kinematics(10.0);
  std::vector<Vec3> pts, axes;
  wavy_piece(2 * kMaxRuledSegments + 5, pts, axes);
  const RuledModelResult m = ruled_model_through(pts, axes, RulingForm::kVector);
  ASSERT_EQ(m.error, "");
  const std::vector<RuledModel> parts = split_for_blocks(m.model);
  ASSERT_EQ(parts.size(), 3u);
  EXPECT_EQ(parts[0].directrix.size(), static_cast<std::size_t>(kMaxRuledSegments));
  EXPECT_EQ(parts[2].directrix.size(), 5u);
  // the parts keep the piece's own segments
  EXPECT_EQ(parts[1].directrix[0].t0, m.model.directrix[kMaxRuledSegments].t0);
  const double F = 20.0;
  std::vector<RuledGeometry> blocks(parts.size());
  for (std::size_t i = 0; i < parts.size(); ++i) {
    ASSERT_EQ(to_geometry(parts[i], F, 1000.0, F, i + 1 == parts.size() ? 0.0 : F, blocks[i]), "");
  }
  RuledFollower f;
  f.start(blocks[0], kin, RotaryTravel{}, start_joints(kin, blocks[0]));
  int joins = 0;
  double total = 0.0;
  for (std::size_t b = 0; b < blocks.size(); ++b) {
    if (b > 0) {
      const double carry = f.leftover();
      const double before = f.sample().chord;  // the shortened last cycle of the block before
      const Joints q = f.sample().q;
      f.start(blocks[b], kin, RotaryTravel{}, q, carry);
      // that cycle travelled its rest of the block before and the carry in this one: F T
      EXPECT_NEAR(before + f.sample().chord, F * kPeriod, 1e-9 * F * kPeriod);
      EXPECT_GT(f.sample().u, 0.0);
      ++joins;
    }
    while (!f.done()) {
      const RuledSample& x = f.step(blocks[b], kPeriod);
      if (!x.last && b + 1 < blocks.size()) {
        EXPECT_NEAR(x.chord, F * kPeriod, 1e-9 * F * kPeriod);
      }
    }
    total += f.travelled();
  }
  EXPECT_EQ(joins, 2);
  EXPECT_LE(norm(f.sample().motion.position - pts.back()), 1e-12);
  EXPECT_NEAR(total, blocks[0].length + blocks[1].length + blocks[2].length, 1e-6);
}

TEST(RuledFollower, JointsAgreeWithTheForwardKinematics) {
  for (const double tool_length : {0.0, 35.0}) {
    const Kinematics kin = desktop_kinematics(tool_length);
    std::vector<Vec3> pts, axes;
    wavy_piece(10, pts, axes);
    const RuledGeometry g = geometry_of(pts, axes, 30.0, 1000.0, 0.0, 0.0);
    const std::vector<RuledSample> s = run(g, kin, kPeriod);
    ASSERT_GT(s.size(), 100u);
    Joints prev = start_joints(kin, g);
    for (const RuledSample& x : s) {
      const ToolPose p = forward(kin, x.q);
      EXPECT_LE(norm(p.tip - x.motion.position), 1e-9);
      EXPECT_LE(norm(p.axis - x.motion.A), 1e-12);
      // the rotary joints move continuously (nearest solution, no 2 pi jumps)
      EXPECT_LE(std::abs(x.q[kTilt] - prev[kTilt]), 0.01);
      EXPECT_LE(std::abs(x.q[kRotary] - prev[kRotary]), 0.01);
      prev = x.q;
    }
  }
}

// u(t) from u(0) by RK4 on du/dt = F/|c_u| (constant F), n steps.
double u_after(const RuledGeometry& g, double u0, double F, double t, int n) {
  const CurveSource c = curves_of(g).directrix;
  auto f = [&](double u) { return F / norm(curve_jet(c, u).d1); };
  const double h = t / n;
  double u = u0;
  for (int i = 0; i < n; ++i) {
    const double k1 = f(u), k2 = f(u + 0.5 * h * k1), k3 = f(u + 0.5 * h * k2), k4 = f(u + h * k3);
    u += h / 6.0 * (k1 + 2 * k2 + 2 * k3 + k4);
  }
  return u;
}

double rel(const Vec3& got, const Vec3& want) { return norm(got - want) / std::max(norm(want), 1e-300); }

TEST(RuledFollower, AnalyticMotionAndFeedForwardAgreeWithDifferences) {
  const Kinematics kin = desktop_kinematics(25.0);
  std::vector<Vec3> pts, axes;
  wavy_piece(8, pts, axes);
  const double F = 10.0;
  const RuledGeometry g = geometry_of(pts, axes, F, 1000.0, F, F);
  const double h = 2e-3;  // s; the stencil spans 4 h F = 0.08 mm, inside one segment
  for (const double u0 : {0.5, 2.5, 4.37, 6.6}) {
    const Joints q0 = start_joints(kin, g);
    const RuledSample x = ruled_sample_at(g, kin, RotaryTravel{}, q0, u0, F, 0.0);
    RuledSample at[5];
    for (int k = -2; k <= 2; ++k) {
      const double u = u_after(g, u0, k < 0 ? -F : F, std::abs(k) * h, 400 * std::abs(k) + 1);
      at[k + 2] = ruled_sample_at(g, kin, RotaryTravel{}, x.q, u, F, 0.0);
    }
    // fourth-order central differences
    auto d1 = [&](auto get) {
      return (1.0 / (12 * h)) * (get(at[0]) - 8.0 * get(at[1]) + 8.0 * get(at[3]) - get(at[4]));
    };
    auto d2 = [&](auto get) {
      return (1.0 / (12 * h * h)) *
             (-1.0 * get(at[0]) + 16.0 * get(at[1]) - 30.0 * get(at[2]) + 16.0 * get(at[3]) - get(at[4]));
    };
    auto tip = [](const RuledSample& s) { return s.motion.position; };
    auto ax = [](const RuledSample& s) { return s.motion.A; };
    auto xyz = [](const RuledSample& s) { return Vec3{s.q[0], s.q[1], s.q[2]}; };
    auto ac = [](const RuledSample& s) { return Vec3{s.q[kTilt], s.q[kRotary], 0.0}; };
    EXPECT_LE(rel(d1(tip), x.motion.velocity), 1e-6) << u0;
    EXPECT_LE(rel(d2(tip), x.motion.acceleration), 1e-6) << u0;
    EXPECT_LE(rel(d1(ax), x.motion.axis_velocity), 1e-6) << u0;
    EXPECT_LE(rel(d2(ax), x.motion.axis_acceleration), 1e-6) << u0;
    EXPECT_LE(rel(d1(xyz), Vec3{x.dq[0], x.dq[1], x.dq[2]}), 1e-6) << u0;
    EXPECT_LE(rel(d2(xyz), Vec3{x.ddq[0], x.ddq[1], x.ddq[2]}), 1e-6) << u0;
    EXPECT_LE(rel(d1(ac), Vec3{x.dq[kTilt], x.dq[kRotary], 0.0}), 1e-6) << u0;
    EXPECT_LE(rel(d2(ac), Vec3{x.ddq[kTilt], x.ddq[kRotary], 0.0}), 1e-6) << u0;
    // the angular velocity: omega x A is the axis's rate
    EXPECT_LE(rel(cross(x.motion.omega, x.motion.A), x.motion.axis_velocity), 1e-12) << u0;
  }
}

// A parabola, exact as a Ferguson chain: c(u) = p0 + w (u' ex' + k u'^2 ey'), u' = u - m.
std::vector<Vec3> parabola(int n, double w, double k) {
  std::vector<Vec3> p;
  for (int i = 0; i <= n; ++i) {
    const double x = (i - 0.5 * n) / n;
    p.push_back({12.5 + w * x, 12.5 + w * k * x * x - 2.0, 2.0 + 0.5 * w * x});
  }
  return p;
}

TEST(RuledFollower, CylinderAxisStandsStillAndTheAccelerationIsTheCurvature) {
  const Kinematics kin = desktop_kinematics(20.0);
  const int n = 6;
  const double w = 10.0, k = 0.8;
  const std::vector<Vec3> pts = parabola(n, w, k);
  const Vec3 e = normalized(Vec3{0.3, -0.4, 1.0});
  // exact tangents: dc/du = c_x / n, so the Ferguson chain is the parabola itself
  std::vector<Vec3> tangents;
  for (int i = 0; i <= n; ++i) tangents.push_back((1.0 / n) * Vec3{w, 2 * w * k * ((i - 0.5 * n) / n), 0.5 * w});
  RuledModel m;
  m.form = RulingForm::kVector;
  m.directrix = hermite_through(pts, tangents);
  m.ruling = hermite_through(std::vector<Vec3>(pts.size(), e), std::vector<Vec3>(pts.size(), Vec3{0, 0, 0}));
  const double F = 20.0;
  RuledGeometry g;
  ASSERT_EQ(to_geometry(m, F, 2000.0, F, F, g), "");
  // the ruled surface is a cylinder: the ruling stands still
  const RuledInvariants inv = ruled_invariants(ruled_jet(curves_of(g), 1.3));
  EXPECT_FALSE(inv.regular);
  const std::vector<RuledSample> s = run(g, kin, kPeriod);
  const Joints q0 = start_joints(kin, g);
  for (const RuledSample& x : s) {
    EXPECT_LE(norm(x.motion.A - e), 1e-14);
    EXPECT_NEAR(x.q[kTilt], q0[kTilt], 1e-12);
    EXPECT_NEAR(x.q[kRotary], q0[kRotary], 1e-12);
    EXPECT_NEAR(x.dq[kTilt], 0.0, 1e-12);
    EXPECT_NEAR(x.dq[kRotary], 0.0, 1e-12);
    EXPECT_NEAR(x.ddq[kTilt], 0.0, 1e-9);
    EXPECT_NEAR(x.ddq[kRotary], 0.0, 1e-9);
    EXPECT_LE(norm(x.motion.axis_velocity), 1e-12);
    // |a| = kappa F^2 with the parabola's curvature written out: c(x) = (w x, w k x^2, w x / 2)
    // over x in [-1/2, 1/2]; c_x = (w, 2 w k x, w/2), c_xx = (0, 2 w k, 0)
    const double xx = x.u / n - 0.5;
    const Vec3 cx{w, 2 * w * k * xx, 0.5 * w}, cxx{0.0, 2 * w * k, 0.0};
    const double kappa = norm(cross(cx, cxx)) / std::pow(norm(cx), 3);
    EXPECT_NEAR(norm(x.motion.acceleration), kappa * F * F, 1e-9 * kappa * F * F) << x.u;
    EXPECT_NEAR(dot(x.motion.acceleration, x.motion.velocity), 0.0, 1e-9);
    // the tool's joints X Y Z move with the tip: forward of the joint rates is v
    const double sp = norm(Vec3{x.dq[0], x.dq[1], x.dq[2]});
    EXPECT_NEAR(sp, F, 1e-9 * F);  // the table does not turn: the slides move at F
  }
}

TEST(RuledFollower, ConeApexStandsStillOnEveryRuling) {
  const Kinematics kin = desktop_kinematics(15.0);
  const int n = 7;
  const std::vector<Vec3> pts = parabola(n, 12.0, 0.6);
  const Vec3 apex{14.0, 9.0, -30.0};  // below the tips: the axis points away from it
  // ruling as vectors c - apex: a cubic, so e = unit(c(u) - apex) holds exactly between set
  // points too when its Hermite tangents are the directrix's
  const RuledModelResult m0 = ruled_model_through(pts, std::vector<Vec3>(pts.size(), Vec3{0, 0, 1}), RulingForm::kVector);
  ASSERT_EQ(m0.error, "");
  RuledModel m = m0.model;
  for (std::size_t i = 0; i < m.ruling.size(); ++i) {
    m.ruling[i] = {m.directrix[i].p0 - apex, m.directrix[i].p1 - apex, m.directrix[i].t0, m.directrix[i].t1};
  }
  RuledGeometry g;
  ASSERT_EQ(to_geometry(m, 15.0, 1500.0, 0.0, 0.0, g), "");
  const RuledCurves cv = curves_of(g);
  for (const double u : {0.4, 3.3, 6.9}) {
    const RuledJet j = ruled_jet(cv, u);
    EXPECT_NEAR(distribution_parameter(j), 0.0, 1e-12);
    EXPECT_LE(norm(striction_point(j) - apex), 1e-9);
    const RuledInvariants inv = ruled_invariants(j);
    ASSERT_TRUE(inv.regular);
    EXPECT_NEAR(inv.mu, norm(j.c.p - apex), 1e-9) << "striction at the apex: c = b + mu e";
  }
  const std::vector<RuledSample> s = run(g, kin, kPeriod);
  for (const RuledSample& x : s) {
    const ToolMotion& t = x.motion;
    const double lam = norm(t.position - apex);
    // the apex lies on the tool axis
    EXPECT_LE(norm(cross(t.position - apex, t.A)), 1e-9);
    // and stands still: apex = c - lam A with lam' = A . v, lam'' = A' . v + A . a
    const double dl = dot(t.A, t.velocity);
    const double ddl = dot(t.axis_velocity, t.velocity) + dot(t.A, t.acceleration);
    const Vec3 v_apex = t.velocity - dl * t.A - lam * t.axis_velocity;
    const Vec3 a_apex = t.acceleration - ddl * t.A - 2.0 * dl * t.axis_velocity - lam * t.axis_acceleration;
    EXPECT_LE(norm(v_apex), 1e-9 * (1.0 + norm(t.velocity)));
    EXPECT_LE(norm(a_apex), 1e-8 * (1.0 + norm(t.acceleration) + lam * norm(t.axis_acceleration)));
  }
}

TEST(RuledFollower, ScheduleSpeedIsLinearBetweenPointsAndConstantBeyond) {
  RuledGeometry g;
  g.schedule_count = 3;
  g.schedule_u[0] = 0.0;
  g.schedule_u[1] = 1.0;
  g.schedule_u[2] = 3.0;
  g.schedule_speed[0] = 10.0;
  g.schedule_speed[1] = 20.0;
  g.schedule_speed[2] = 5.0;
  int hint = 0;
  EXPECT_DOUBLE_EQ(ruled_schedule_speed(g, -1.0, hint), 10.0);
  EXPECT_DOUBLE_EQ(ruled_schedule_speed(g, 0.5, hint), 15.0);
  EXPECT_DOUBLE_EQ(ruled_schedule_speed(g, 2.0, hint), 12.5);
  EXPECT_DOUBLE_EQ(ruled_schedule_speed(g, 0.25, hint), 12.5);  // walking back
  EXPECT_DOUBLE_EQ(ruled_schedule_speed(g, 4.0, hint), 5.0);
}

TEST(RuledFollower, TheBlockBuilderRefusesWhatDoesNotFit) {
  std::vector<Vec3> pts, axes;
  wavy_piece(kMaxRuledSegments + 1, pts, axes);
  const RuledModelResult m = ruled_model_through(pts, axes, RulingForm::kVector);
  ASSERT_EQ(m.error, "");
  RuledGeometry g;
  EXPECT_NE(to_geometry(m.model, 10.0, 100.0, 0.0, 0.0, g).find("does not fit one block"), std::string::npos);
  wavy_piece(kMaxRuledSegments, pts, axes);
  const RuledModelResult m2 = ruled_model_through(pts, axes, RulingForm::kVector);
  EXPECT_EQ(to_geometry(m2.model, 10.0, 100.0, 0.0, 0.0, g), "");
  EXPECT_NE(to_geometry(m2.model, 0.0, 100.0, 0.0, 0.0, g), "");
  EXPECT_NE(to_geometry(m2.model, 10.0, -1.0, 0.0, 0.0, g), "");
  // the length against a fine polyline of the curve
  double poly = 0.0;
  Vec3 prev = ruled_jet(curves_of(g), 0.0).c.p;
  for (int i = 1; i <= 200000; ++i) {
    const Vec3 p = ruled_jet(curves_of(g), g.segment_count * i / 200000.0).c.p;
    poly += norm(p - prev);
    prev = p;
  }
  EXPECT_NEAR(g.length, poly, 1e-7 * poly);
}

}  // namespace
}  // namespace pcnc
