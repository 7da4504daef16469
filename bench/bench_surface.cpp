// bench_surface.cpp — figures for the measured surface (issue 15, items 4-5; never pass/fail):
//  1. accuracy: a travel-sized freeform design surface (20 x 20 mm, X/Y 2.5..22.5, heights of
//     +-0.6 mm) plus the seed's symmetrised Wiener surface (eq. 16) as machining error, scaled to
//     --error-um RMS; probed on a 7 x 7 grid (exact points, or with --noise-um of normal
//     noise); the RMS and maximum distance (Z) to the true surface over 201 x 201 points of the
//     fitted B-spline surface (e = 1 and faired), bilinear (bCNC, CNCjs) and Catmull–Rom
//     (Candle) interpolation of the same probes; the mean over --seeds error surfaces, for
//     errors of several lattice sizes (the error's shortest wavelength: 20 mm / cells);
//  2. fairing (the seed's Fig. 5-6): F and the fitted-minus-design mean and std before (e = 1)
//     and after fairing, on the uniform grid and on an unevenly spaced one;
//  3. the cost of one evaluation: point, point with derivatives, and the height at an X/Y (what
//     the surface-correction stage calls);
//  4. the measuring chain on a 100 x 100 mm part (issue 15's goals): section 1's design scaled
//     to 100 mm (+-0.6 mm, and +-3 mm: slopes up to 9°) plus the Wiener error, touched straight down on a 7 x 7 grid by a 1 mm ball
//     (each latch solved exactly against the true surface: the ball centre where its distance
//     to the surface reaches R - pre-travel - noise), the centres corrected along the measured
//     normal (compensate_grid) and fitted; against autolevel (the centre's Z - R as the height
//     at the grid's X/Y, bilinear and Catmull–Rom) and against the same baselines of the
//     corrected points; the height error left at the corrected points (the slope error after
//     the ball correction).

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <random>
#include <vector>

#include "bench_cli.hpp"
#include "geometry/bspline_surface.hpp"
#include "geometry/probe_calibration.hpp"
#include "geometry/probe_compensation.hpp"
#include "geometry/surface_fit.hpp"
#include "geometry/surface_interp.hpp"
#include "geometry/wiener_surface.hpp"

using namespace pcnc;
using Clock = std::chrono::steady_clock;

namespace {

constexpr double kX0 = 2.5, kSpan = 20.0;

double design(double x, double y) { return 0.6 * std::sin(0.25 * x) * std::cos(0.2 * y); }

struct Truth {
  WienerSurface error;
  double operator()(double x, double y) const {
    return design(x, y) + error.smooth_value((x - kX0) / kSpan, (y - kX0) / kSpan);
  }
};

std::vector<double> positions(bool uneven) {
  static const double even[7] = {0, 1.0 / 6, 2.0 / 6, 3.0 / 6, 4.0 / 6, 5.0 / 6, 1};
  static const double odd[7] = {0, 0.08, 0.3, 0.42, 0.7, 0.78, 1};
  std::vector<double> v;
  for (int i = 0; i < 7; ++i) v.push_back(kX0 + kSpan * (uneven ? odd[i] : even[i]));
  return v;
}

template <class F>
PointGrid probe(const std::vector<double>& at, F z, double noise_mm, std::mt19937_64& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  PointGrid g;
  g.cols = g.rows = static_cast<int>(at.size());
  for (double y : at)
    for (double x : at) g.points.push_back({x, y, z(x, y) + (noise_mm > 0 ? noise_mm * n(rng) : 0.0)});
  return g;
}

struct Stats {
  double rms = 0, max = 0, mean = 0, std = 0;
};

// Over n x n points of the square x0 .. x0 + span (default: section 1's).
template <class Model, class Ref>
Stats compare(const Model& model, const Ref& ref, double x0 = kX0, double span = kSpan) {
  constexpr int n = 201;
  double sum = 0, sq = 0, mx = 0;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double x = x0 + span * i / (n - 1), y = x0 + span * j / (n - 1);
      const double e = model(x, y) - ref(x, y);
      sum += e;
      sq += e * e;
      mx = std::max(mx, std::fabs(e));
    }
  Stats s;
  s.mean = sum / (n * n);
  s.rms = std::sqrt(sq / (n * n));
  s.max = mx;
  s.std = std::sqrt(std::max(0.0, s.rms * s.rms - s.mean * s.mean));
  return s;
}

double um(double mm) { return mm * 1000.0; }

template <class F>
double ns_per_call(F f, int calls) {
  const auto t0 = Clock::now();
  double sink = 0;
  for (int i = 0; i < calls; ++i) sink += f(i);
  const double ns = std::chrono::duration<double, std::nano>(Clock::now() - t0).count() / calls;
  if (sink == 12345.678) std::printf(" ");
  return ns;
}

// ---- 4. the measuring chain on a travel-sized part ----
constexpr double kBigX0 = 10.0, kBigSpan = 100.0;

// Section 1's design scaled 5x in X/Y (same shape relative to the grid), amplitude `a`.
struct BigTruth {
  WienerSurface error;
  double a;
  double operator()(double x, double y) const {
    return a * std::sin(0.05 * x) * std::cos(0.04 * y) + error.smooth_value((x - kBigX0) / kBigSpan, (y - kBigX0) / kBigSpan);
  }
};

// The distance from c to the height field f: Gauss–Newton on the foot point (u, v), where
// c − (u, v, f(u, v)) is normal to the surface.
template <class F>
double distance_to(const F& f, const Vec3& c) {
  double u = c[0], v = c[1];
  for (int it = 0; it < 40; ++it) {
    const double h = 1e-5, z = f(u, v);
    const double fu = (f(u + h, v) - f(u - h, v)) / (2 * h), fv = (f(u, v + h) - f(u, v - h)) / (2 * h);
    const double gu = (u - c[0]) + (z - c[2]) * fu, gv = (v - c[1]) + (z - c[2]) * fv;
    const double a = 1 + fu * fu, b = fu * fv, d = 1 + fv * fv, det = a * d - b * b;
    const double du = -(d * gu - b * gv) / det, dv = -(a * gv - b * gu) / det;
    u += du, v += dv;
    if (std::fabs(du) + std::fabs(dv) < 1e-13) break;
  }
  return norm(c - Vec3{u, v, f(u, v)});
}

// The ball centre's Z where a ball descending at (x, y) triggers: its distance to the surface
// equals the trigger radius (bisection).
template <class F>
double latch_z(const F& f, double x, double y, double trigger_radius) {
  double lo = f(x, y), hi = f(x, y) + 3.0 * trigger_radius;
  for (int i = 0; i < 60; ++i) {
    const double mid = 0.5 * (lo + hi);
    (distance_to(f, {x, y, mid}) > trigger_radius ? hi : lo) = mid;
  }
  return 0.5 * (lo + hi);
}

void measuring_chain(double amplitude, double error_um, double noise_um, int seeds, double ball_mm, double pretravel_um) {
  std::printf("\n4. the measuring chain: 100 x 100 mm, design %.1f sin(x/20) cos(y/25) (slopes up to %.1f°) + Wiener "
              "error %.1f µm RMS, 7 x 7 touches straight down, ball R %.2f mm, pre-travel %.1f µm, noise %.1f µm, mean of "
              "%d seeds; µm\n",
              amplitude, std::atan(amplitude * std::hypot(0.05, 0.04)) * 180 / 3.14159265358979, error_um, ball_mm,
              pretravel_um, noise_um, seeds);
  std::printf("  %-6s %-34s %9s %9s   %s\n", "cells", "surface from the probes", "RMS", "max", "RMS vs B-spline");
  const double r_eff = ball_mm - pretravel_um / 1000.0;
  const ProbeCalibration cal = constant_calibration(r_eff);  // as calibrated on the sphere (bench_probe_math)
  std::mt19937_64 rng(11);
  std::normal_distribution<double> n01(0.0, 1.0);
  for (int cells : {2, 4}) {
    enum { kFit, kFair, kBilin, kCr, kAutoBilin, kAutoCr, kRows };
    Stats acc[kRows] = {};
    double naive_max = 0, corrected_max = 0, corrected_rms = 0;
    for (int sd = 1; sd <= seeds; ++sd) {
      const BigTruth truth{WienerSurface(static_cast<std::uint64_t>(sd), cells, error_um / 1000.0), amplitude};
      PointGrid centres, autolevel;
      double naive = 0;
      centres.cols = centres.rows = autolevel.cols = autolevel.rows = 7;
      for (int r = 0; r < 7; ++r)
        for (int c = 0; c < 7; ++c) {
          const double x = kBigX0 + kBigSpan * c / 6, y = kBigX0 + kBigSpan * r / 6;
          const double z = latch_z(truth, x, y, r_eff - noise_um / 1000.0 * n01(rng));
          centres.points.push_back({x, y, z});
          autolevel.points.push_back({x, y, z - r_eff});
          naive = std::max(naive, std::fabs(z - r_eff - truth(x, y)));
        }
      naive_max += naive / seeds;
      const GridCompensation comp = compensate_grid(centres, {{0.0, 0.0, -1.0}}, cal);
      if (!comp.ok()) {
        std::printf("  compensation refused: %s\n", comp.error.c_str());
        return;
      }
      double mx = 0, sq = 0;
      for (const Vec3& q : comp.contacts.points) {
        const double e = q[2] - truth(q[0], q[1]);
        mx = std::max(mx, std::fabs(e)), sq += e * e;
      }
      corrected_max += mx / seeds, corrected_rms += std::sqrt(sq / 49) / seeds;
      const SurfaceFit fit = interpolate_grid(comp.contacts, 3, 1.0);
      const FairFit fair = fair_fit(comp.contacts, 3);
      const GridHeights base(comp.contacts), autol(autolevel);
      const Stats st[kRows] = {
          compare([&](double x, double y) { return surface_height(fit.surface, x, y).z; }, truth, kBigX0, kBigSpan),
          compare([&](double x, double y) { return surface_height(fair.fit.surface, x, y).z; }, truth, kBigX0, kBigSpan),
          compare([&](double x, double y) { return base.bilinear(x, y); }, truth, kBigX0, kBigSpan),
          compare([&](double x, double y) { return base.catmull_rom(x, y); }, truth, kBigX0, kBigSpan),
          compare([&](double x, double y) { return autol.bilinear(x, y); }, truth, kBigX0, kBigSpan),
          compare([&](double x, double y) { return autol.catmull_rom(x, y); }, truth, kBigX0, kBigSpan)};
      for (int k = 0; k < kRows; ++k) acc[k].rms += st[k].rms / seeds, acc[k].max += st[k].max / seeds;
    }
    const char* names[kRows] = {"B-spline e=1 (ball-corrected)", "B-spline faired (ball-corrected)",
                                "bilinear (ball-corrected)",     "Catmull-Rom (ball-corrected)",
                                "bilinear (autolevel: Z - R)",   "Catmull-Rom (autolevel: Z - R)"};
    for (int k = 0; k < kRows; ++k)
      std::printf("  %-6d %-34s %9.3f %9.3f   %.2fx\n", cells, names[k], um(acc[k].rms), um(acc[k].max),
                  acc[k].rms / acc[kFit].rms);
    std::printf("  %-6d height error at the touches: autolevel max %.3f; after the ball correction RMS %.3f max %.3f\n",
                cells, um(naive_max), um(corrected_rms), um(corrected_max));
  }
}

}  // namespace

int main(int argc, char** argv) {
  pcnc::BenchCli app{"bench_surface: the measured B-spline surface against bilinear and Catmull-Rom probe interpolation"};
  double error_um = 20.0, noise_um = 0.0;
  int seeds = 10;
  double ball_mm = 1.0, pretravel_um = 4.0;
  app.add_option("--error-um", error_um, "RMS of the injected Wiener error, µm")->show_default();
  app.add_option("--noise-um", noise_um, "probe noise (normal, standard deviation), µm")->show_default();
  app.add_option("--seeds", seeds, "error surfaces per row (seeds 1..N), figures are their mean")->show_default();
  app.add_option("--ball-mm", ball_mm, "section 4: the probe ball's radius, mm")->show_default();
  app.add_option("--pretravel-um", pretravel_um, "section 4: the pre-travel straight down, µm")->show_default();
  if (const int rc = app.parse(argc, argv); rc >= 0) return rc;
  std::mt19937_64 rng(7);

  std::printf("1. accuracy: 20 x 20 mm design surface (+-0.6 mm) + Wiener error %.1f µm RMS, 7 x 7 probes, noise %.1f µm,"
              " mean of %d seeds; distance (Z) to the true surface over 201 x 201 points, µm\n",
              error_um, noise_um, seeds);
  std::printf("  %-6s %-18s %9s %9s   %s\n", "cells", "method", "RMS", "max", "RMS vs B-spline");
  for (int cells : {2, 3, 4, 6, 8, 16}) {
    Stats acc[4] = {};
    for (int s = 1; s <= seeds; ++s) {
      const Truth truth{WienerSurface(static_cast<std::uint64_t>(s), cells, error_um / 1000.0)};
      const PointGrid g = probe(positions(false), truth, noise_um / 1000.0, rng);
      const SurfaceFit fit = interpolate_grid(g, 3, 1.0);
      const FairFit fair = fair_fit(g, 3);
      const GridHeights base(g);
      const Stats st[4] = {
          compare([&](double x, double y) { return surface_height(fit.surface, x, y).z; }, truth, kBigX0, kBigSpan),
          compare([&](double x, double y) { return surface_height(fair.fit.surface, x, y).z; }, truth, kBigX0, kBigSpan),
          compare([&](double x, double y) { return base.bilinear(x, y); }, truth, kBigX0, kBigSpan),
          compare([&](double x, double y) { return base.catmull_rom(x, y); }, truth, kBigX0, kBigSpan)};
      for (int k = 0; k < 4; ++k) acc[k].rms += st[k].rms / seeds, acc[k].max += st[k].max / seeds;
    }
    const char* names[4] = {"B-spline e=1", "B-spline faired", "bilinear", "Catmull-Rom"};
    for (int k = 0; k < 4; ++k)
      std::printf("  %-6d %-18s %9.3f %9.3f   %.2fx\n", cells, names[k], um(acc[k].rms), um(acc[k].max),
                  acc[k].rms / acc[0].rms);
  }

  std::printf("\n2. fairing (seed Fig. 5-6): F and the fitted-minus-design error before (e = 1) and after, "
              "Wiener error %.1f µm RMS over 4 cells, seeds 1..%d (mean)\n",
              error_um, seeds);
  for (bool uneven : {false, true}) {
    double f0 = 0, f1 = 0, e1 = 0, m0 = 0, s0 = 0, m1 = 0, s1 = 0, t0 = 0, t1 = 0;
    for (int s = 1; s <= seeds; ++s) {
      const Truth truth{WienerSurface(static_cast<std::uint64_t>(s), 4, error_um / 1000.0)};
      const PointGrid g = probe(positions(uneven), truth, noise_um / 1000.0, rng);
      const SurfaceFit fit = interpolate_grid(g, 3, 1.0);
      const FairFit fair = fair_fit(g, 3);
      auto h0 = [&](double x, double y) { return surface_height(fit.surface, x, y).z; };
      auto h1 = [&](double x, double y) { return surface_height(fair.fit.surface, x, y).z; };
      const Stats d0 = compare(h0, design), d1 = compare(h1, design);
      const Stats r0 = compare(h0, truth), r1 = compare(h1, truth);
      f0 += fairness(fit) / seeds, f1 += fair.fairness / seeds, e1 += fair.e / seeds;
      m0 += d0.mean / seeds, s0 += d0.std / seeds, m1 += d1.mean / seeds, s1 += d1.std / seeds;
      t0 += r0.rms / seeds, t1 += r1.rms / seeds;
      if (std::getenv("BENCH_SURFACE_SEEDS"))
        std::printf("    seed %d: e %.4f, F %.5g -> %.5g, RMS to true %.3f -> %.3f µm\n", s, fair.e, fairness(fit), fair.fairness, um(r0.rms), um(r1.rms));
    }
    std::printf("  %s grid: F %.5g -> %.5g (%+.2f %%, mean e %.3f); fitted - design: mean %.3f -> %.3f µm, std %.3f -> "
                "%.3f µm; RMS to the true surface %.3f -> %.3f µm\n",
                uneven ? "uneven " : "uniform", f0, f1, 100 * (f1 - f0) / f0, e1, um(m0), um(m1), um(s0), um(s1),
                um(t0), um(t1));
  }

  std::printf("\n3. cost of one evaluation (degree 3, 7 x 7 control points), ns per call:\n");
  const Truth truth{WienerSurface(1, 4, error_um / 1000.0)};
  const SurfaceFit fit = interpolate_grid(probe(positions(false), truth, 0.0, rng), 3, 1.0);
  std::vector<double> us(4096), vs(4096);
  std::uniform_real_distribution<double> d(0.0, 1.0);
  for (std::size_t i = 0; i < us.size(); ++i) us[i] = d(rng), vs[i] = d(rng);
  const int calls = 2000000;
  const double p = ns_per_call([&](int i) { return surface_point(fit.surface, us[i & 4095], vs[i & 4095])[2]; }, calls);
  const double e = ns_per_call([&](int i) { return surface_eval(fit.surface, us[i & 4095], vs[i & 4095]).svv[2]; }, calls);
  const double h = ns_per_call(
      [&](int i) { return surface_height(fit.surface, kX0 + kSpan * us[i & 4095], kX0 + kSpan * vs[i & 4095]).z; },
      calls / 4);
  std::printf("  point %.0f ns, point + 1st and 2nd derivatives %.0f ns, height at an X/Y (Newton) %.0f ns\n", p, e, h);

  for (double amplitude : {0.6, 3.0}) measuring_chain(amplitude, error_um, noise_um > 0 ? noise_um : 0.3, seeds, ball_mm, pretravel_um);
  return 0;
}
