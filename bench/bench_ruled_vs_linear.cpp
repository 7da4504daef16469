// bench_ruled_vs_linear.cpp — issue 17, item 4, the geometric half (never pass/fail): the same
// passes over the seed's example (scaled to the desktop mill: 25 x 25 mm, 2.5 mm high) written
// as short 5-axis G1 moves with the angles interpolated linearly (what CAM output on LinuxCNC
// or grblHAL gives: the tool tip on the chord between set points, the XYZAC table-table joints
// A and C from the inverse kinematics at the set points and linear between them) against the
// ruled-surface interpolation of the same set points (ruled_model_through: Ferguson directrix
// and ruling, the vectors normalised or the spherical angles), at point spacings 0.5, 1, 2 mm.
// Both are sampled at 2 kHz at the programmed feed (the chords at constant speed, the ruled
// piece by the corrected parameter step), with no acceleration planning and no blending.
// Printed per spacing and method:
//  - the deviation of the swept tool axis from the intended ruled surface (the exact tip curve
//    and the exact tool axis of the pass, from the surface): the distance of the tip and of the
//    point --height mm up the axis to the nearest ruling of the intended surface (golden section
//    over the pass's parameter), and the angle between the tool axis and the intended axis at
//    the nearest point of the intended tip curve;
//  - the joint jerk: third differences of the joints (inverse kinematics each cycle, the
//    solution nearest the cycle before) over the 0.5 ms period, max and RMS, X Y Z and A C;
//    also for the intended path itself at the same feed (the reference: what the surface and
//    the kinematics ask for whatever the interpolation).
// The machine time needs the rt's ruled block (issue 17, item 2) and comes later.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "bench_cli.hpp"
#include "geometry/kinematics.hpp"
#include "geometry/ruled_model.hpp"
#include "geometry/ruled_motion.hpp"
#include "geometry/ruled_passes.hpp"

using namespace pcnc;

namespace {

constexpr double kPeriod = 0.0005;  // 2 kHz
constexpr double kRad2Deg = 180.0 / M_PI;

struct Pose {
  Vec3 tip, axis;
};

// The intended ruled surface of one pass: the exact tip curve and axis at the surface's v.
struct Intended {
  BSplineSurface surface;
  double u = 0.0, lead = 0.0, radius = 1.0;
  Pose at(double v) const {
    const SurfaceEval e = surface_eval(surface, u, v);
    const PassPoint p = pass_point(e, e.sv, radius, lead);
    return {p.tip, p.axis};
  }
};

// Golden-section minimum of f over [lo, hi] after a coarse scan (f is smooth and has one
// minimum near the true one within a few set points).
template <class F>
double minimise(F f, double lo, double hi) {
  int best = 0;
  double fb = 1e300;
  const int n = 12;
  for (int i = 0; i <= n; ++i) {
    const double x = lo + (hi - lo) * i / n, fx = f(x);
    if (fx < fb) fb = fx, best = i;
  }
  double a = lo + (hi - lo) * std::max(0, best - 1) / n, b = lo + (hi - lo) * std::min(n, best + 1) / n;
  const double g = (std::sqrt(5.0) - 1) / 2;
  double m1 = b - g * (b - a), m2 = a + g * (b - a), f1 = f(m1), f2 = f(m2);
  for (int it = 0; it < 60; ++it) {
    if (f1 < f2) {
      b = m2, m2 = m1, f2 = f1, m1 = b - g * (b - a), f1 = f(m1);
    } else {
      a = m1, m1 = m2, f1 = f2, m2 = a + g * (b - a), f2 = f(m2);
    }
  }
  return f(0.5 * (a + b));
}

struct Stats {
  double tip_dev = 0, high_dev = 0, angle = 0;
  double jerk_lin_max = 0, jerk_rot_max = 0, jerk_lin_ss = 0, jerk_rot_ss = 0;
  long jerk_n = 0, samples = 0;
};

// Deviation of one pose from the intended surface; v_lo..v_hi brackets where to look.
void deviation(const Intended& in, const Pose& p, double v_lo, double v_hi, double height, Stats& st) {
  for (int which = 0; which < 2; ++which) {
    const Vec3 x = p.tip + (which == 0 ? 0.0 : height) * p.axis;
    const double d = minimise(
        [&](double v) {
          const Pose r = in.at(v);
          const Vec3 q = x - r.tip;
          return norm(q - dot(q, r.axis) * r.axis);
        },
        v_lo, v_hi);
    (which == 0 ? st.tip_dev : st.high_dev) = std::max(which == 0 ? st.tip_dev : st.high_dev, d);
  }
  double vbest = v_lo, dbest = 1e300;
  (void)minimise(
      [&](double v) {
        const double d = norm(in.at(v).tip - p.tip);
        if (d < dbest) dbest = d, vbest = v;
        return d;
      },
      v_lo, v_hi);
  const double c = std::clamp(dot(in.at(vbest).axis, p.axis), -1.0, 1.0);
  st.angle = std::max(st.angle, std::acos(c));
}

void jerk(const std::vector<Joints>& q, Stats& st) {
  const double t3 = kPeriod * kPeriod * kPeriod;
  for (std::size_t k = 3; k < q.size(); ++k) {
    double lin = 0, rot = 0;
    for (int j = 0; j < kJoints; ++j) {
      const double d3 = (q[k][j] - 3 * q[k - 1][j] + 3 * q[k - 2][j] - q[k - 3][j]) / t3;
      if (j < 3) lin = std::max(lin, std::abs(d3));
      else rot = std::max(rot, std::abs(d3) * kRad2Deg);
    }
    st.jerk_lin_max = std::max(st.jerk_lin_max, lin);
    st.jerk_rot_max = std::max(st.jerk_rot_max, rot);
    st.jerk_lin_ss += lin * lin;
    st.jerk_rot_ss += rot * rot;
    ++st.jerk_n;
  }
}

}  // namespace

int main(int argc, char** argv) {
  pcnc::BenchCli app{"bench_ruled_vs_linear: ruled-surface interpolation against G1 moves with linear angles"};
  double feed_mm_min = 600.0, height = 10.0, lead_deg = 0.0, radius = 1.0;
  app.add_option("--feed", feed_mm_min, "programmed feed, mm/min")->show_default();
  app.add_option("--height", height, "the point up the tool axis whose deviation is measured, mm")->show_default();
  app.add_option("--lead", lead_deg, "lead angle, degrees")->show_default();
  app.add_option("--tool-radius", radius, "ball radius, mm")->show_default();
  if (const int rc = app.parse(argc, argv); rc >= 0) return rc;
  const double F = feed_mm_min / 60.0;

  Kinematics kin;
  kin.kind = KinematicsKind::kTableTable;  // A and C axes through the part's program zero, tool length 0
  const BSplineSurface surf = example_surface(25.0, {-12.5, -12.5, -4.5});
  const double pass_u[3] = {0.1, 0.5, 0.9};
  std::printf("the seed's example scaled to 25 x 25 x 2.5 mm; passes at X = -10, 0, 10 mm along Y; ball R %g mm, lead %g "
              "deg; XYZAC table-table, pivots at program zero; F %g mm/min, samples at 2 kHz; no blending, no "
              "acceleration planning\n",
              radius, lead_deg, feed_mm_min);
  std::printf("deviation: from the intended ruled surface (exact tip curve + exact axis), the tip and the point %g mm "
              "up the axis; angle: axis against the intended axis at the nearest tip point\n",
              height);
  std::printf("%-8s %-26s %12s %14s %12s %14s %14s %14s %14s %8s\n", "spacing", "method", "tip dev um",
              "axis@h dev um", "angle urad", "jerk XYZ max", "jerk XYZ rms", "jerk AC max", "jerk AC rms", "samples");
  std::printf("%-8s %-26s %12s %14s %12s %14s %14s %14s %14s %8s\n", "", "", "", "", "", "mm/s^3", "mm/s^3", "deg/s^3",
              "deg/s^3", "");
  for (double spacing : {0.5, 1.0, 2.0}) {
    Stats st[4];
    for (double u0 : pass_u) {
      Intended in{surf, u0, lead_deg * M_PI / 180.0, radius};
      const int n = static_cast<int>(std::ceil(25.0 / spacing - 1e-9));
      std::vector<Vec3> tips, axes;
      std::vector<double> vs;
      for (int i = 0; i <= n; ++i) {
        const double v = static_cast<double>(i) / n;
        const Pose p = in.at(v);
        vs.push_back(v);
        tips.push_back(p.tip);
        axes.push_back(p.axis);
      }
      // 0: G1 moves, angles linear between the inverse kinematics at the set points
      {
        std::vector<Joints> qs(tips.size());
        Joints prev{};
        for (std::size_t i = 0; i < tips.size(); ++i) prev = qs[i] = inverse(kin, {tips[i], axes[i]}, prev);
        std::vector<double> at{0.0};
        for (std::size_t i = 1; i < tips.size(); ++i) at.push_back(at.back() + norm(tips[i] - tips[i - 1]));
        std::vector<Joints> traj;
        prev = qs[0];
        std::size_t seg = 0;
        for (long k = 0;; ++k) {
          const double s = F * kPeriod * static_cast<double>(k);
          if (s > at.back()) break;
          while (seg + 2 < at.size() && s > at[seg + 1]) ++seg;
          const double f = (s - at[seg]) / (at[seg + 1] - at[seg]);
          Joints q = prev;
          q[kTilt] = qs[seg][kTilt] + f * (qs[seg + 1][kTilt] - qs[seg][kTilt]);
          q[kRotary] = qs[seg][kRotary] + f * (qs[seg + 1][kRotary] - qs[seg][kRotary]);
          const Pose p{tips[seg] + f * (tips[seg + 1] - tips[seg]), forward(kin, q).axis};
          prev = inverse(kin, {p.tip, p.axis}, prev);
          traj.push_back(prev);
          deviation(in, p, vs[seg > 0 ? seg - 1 : 0], vs[std::min(seg + 2, vs.size() - 1)], height, st[0]);
          ++st[0].samples;
        }
        jerk(traj, st[0]);
      }
      // 1, 2: the ruled piece through the same set points, ruling as vectors / as angles
      for (int form = 0; form < 2; ++form) {
        Stats& s = st[1 + form];
        const RuledModelResult m = ruled_model_through(tips, axes, form == 0 ? RulingForm::kVector : RulingForm::kAngles);
        if (!m.error.empty()) {
          std::fprintf(stderr, "model: %s\n", m.error.c_str());
          return 1;
        }
        const RuledCurves c = m.model.curves();
        std::vector<Joints> traj;
        Joints prev = inverse(kin, {tips[0], axes[0]}, Joints{});
        for (double u = 0.0;;) {
          const RuledJet j = ruled_jet(c, u);
          const Pose p{j.c.p, j.e.p};
          prev = inverse(kin, {p.tip, p.axis}, prev);
          traj.push_back(prev);
          const std::size_t seg = std::min(static_cast<std::size_t>(u), vs.size() - 2);
          deviation(in, p, vs[seg > 0 ? seg - 1 : 0], vs[std::min(seg + 2, vs.size() - 1)], height, s);
          ++s.samples;
          // the last, shorter period (clamped at the end) is left out, as the chords' is
          const ParameterStep step = advance_parameter(c.directrix, u, F, 0.0, kPeriod, true);
          if (step.u_next >= c.u_max()) break;
          u = step.u_next;
        }
        jerk(traj, s);
      }
    }
    const char* names[4] = {"G1, angles linear", "ruled, ruling as vectors", "ruled, ruling as angles",
                            "exact path (reference)"};
    if (spacing == 0.5) {
      // The intended path itself at the same feed (no set points): the joint jerk the surface
      // and the kinematics ask for anyway. The tip advances by the chord F T (Newton in v).
      for (double u0 : pass_u) {
        const Intended in{surf, u0, lead_deg * M_PI / 180.0, radius};
        std::vector<Joints> traj;
        Joints prev = inverse(kin, {in.at(0.0).tip, in.at(0.0).axis}, Joints{});
        for (double v = 0.0;;) {
          const Pose p = in.at(v);
          prev = inverse(kin, {p.tip, p.axis}, prev);
          traj.push_back(prev);
          ++st[3].samples;
          const double h = 1e-7;
          double w = v + F * kPeriod / (norm(in.at(v + h).tip - in.at(v).tip) / h);
          for (int it = 0; it < 4 && w < 1.0; ++it) {
            const double chord = norm(in.at(w).tip - p.tip);
            const double slope = (norm(in.at(w + h).tip - p.tip) - chord) / h;
            w -= (chord - F * kPeriod) / slope;
          }
          if (w >= 1.0) break;
          v = w;
        }
        jerk(traj, st[3]);
      }
    }
    for (int m = 0; m < (spacing == 0.5 ? 4 : 3); ++m) {
      const Stats& s = st[m];
      const std::string label = m == 3 ? "" : std::to_string(spacing).substr(0, 3) + " mm";
      if (m == 3)  // the reference is the intended path: no deviation to measure
        std::printf("%-8s %-26s %12s %14s %12s", label.c_str(), names[m], "-", "-", "-");
      else
        std::printf("%-8s %-26s %12.4f %14.4f %12.2f", label.c_str(), names[m], s.tip_dev * 1e3, s.high_dev * 1e3,
                    s.angle * 1e6);
      std::printf(" %14.4g %14.4g %14.4g %14.4g %8ld\n", s.jerk_lin_max, std::sqrt(s.jerk_lin_ss / std::max(1L, s.jerk_n)),
                  s.jerk_rot_max, std::sqrt(s.jerk_rot_ss / std::max(1L, s.jerk_n)), s.samples);
    }
  }
  std::printf("machine time: needs the rt's ruled block (issue 17, item 2), not yet built; the feed time of these "
              "passes is their length over F for both\n");
  return 0;
}
