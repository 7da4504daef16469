// bench_probe_math.cpp — figures for the measurement mathematics of issue 15 item 3 (never
// pass/fail; docs/measurement.md quotes them):
//  1. the probe calibration on a 6 mm reference sphere: lobed pre-travel (axial, lateral,
//     three-lobed), seeded repeatability noise; residuals, and the error of r_eff(d) against the
//     truth over random directions, with the sphere's centre known and fitted;
//  2. the slope error of a 1 mm ball probed straight down on a 7 × 7 grid over X/Y 2.5..22.5 on
//     a surface with slopes up to 45°, on the plane z = x and on an under-sampled wavy surface:
//     the naive reading (centre Z − r, at the centre's X/Y) against the contact point moved back
//     along the normal of the B-spline through the centres, with the calibrated r_eff; the true
//     latched centres are computed from the surface's own normal (q + r_eff n(q) on the probe's
//     vertical, Newton), independently of the library;
//  3. the volumetric error of a synthetic machine (pitch ±5 µm, squareness 40/-25/15 µrad)
//     before and after compensation by the model calibrated on an artefact (step gauges along
//     X, Y, Z, two diagonals per plane, lengths with seeded noise), over random points, relative
//     to the machine's centre (where a work offset is touched off); and the chain: section 2's
//     surface probed on that machine, ball-corrected with and without E_V removed first;
//  4. the cost of one evaluation (ns per call) and of each fit.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>
#include <vector>

#include "bench_cli.hpp"
#include "geometry/probe_calibration.hpp"
#include "geometry/probe_compensation.hpp"
#include "geometry/sphere_fit.hpp"
#include "geometry/volumetric_error.hpp"

using namespace pcnc;
using Clock = std::chrono::steady_clock;

namespace {

double um(double mm) { return mm * 1000.0; }

// The probe of the bench: 1 mm ball, pre-travel by approach direction (the simulation's form).
constexpr double kBall = 1.0, kAxial = 0.002, kLateral = 0.008, kLobe = 0.003;
double true_reff(const Vec3& d) {
  const Vec3 u = normalized(d);
  const double psi = (u[0] == 0.0 && u[1] == 0.0) ? 0.0 : std::atan2(u[1], u[0]);
  return kBall - (kAxial * u[2] * u[2] + (kLateral + kLobe * std::cos(3.0 * psi)) * (u[0] * u[0] + u[1] * u[1]));
}

// A height field with its gradient.
// kind 0: 8 sin((x - 2.5)/8) + 0.5 cos(y/4) (45° at x = 2.5, curvature radius >= 8 mm);
// kind 1: the plane z = x; kind 2: 3 sin(x/3) + 0.5 cos(y/4) (45° slopes every 9.4 mm, a
// 7 x 7 grid puts 5.7 points on its wavelength: under-sampled, the normals' limit).
struct Field {
  int kind = 0;
  double lift = 0.0;  // added to z (the chain puts the surface inside the Z table)
  double z(double x, double y) const { return lift + z0(x, y); }
  double z0(double x, double y) const {
    if (kind == 1) return x;
    return kind == 0 ? 8.0 * std::sin((x - 2.5) / 8.0) + 0.5 * std::cos(y / 4.0) : 3.0 * std::sin(x / 3.0) + 0.5 * std::cos(y / 4.0);
  }
  void grad(double x, double y, double& fx, double& fy) const {
    fx = kind == 1 ? 1.0 : kind == 0 ? std::cos((x - 2.5) / 8.0) : std::cos(x / 3.0);
    fy = kind == 1 ? 0.0 : -0.125 * std::sin(y / 4.0);
  }
  Vec3 normal(double x, double y) const {
    double fx, fy;
    grad(x, y, fx, fy);
    return normalized(Vec3{-fx, -fy, 1.0});
  }
};

// Probing straight down at (x, y): the contact q with q + r n(q) on the vertical through (x, y)
// (Newton on the 2 × 2 system, numeric Jacobian); returns the latched centre and q.
void latch(const Field& f, double x, double y, double r, Vec3& centre, Vec3& q) {
  double u = x, v = y;
  for (int it = 0; it < 50; ++it) {
    auto g = [&](double a, double b, double& gx, double& gy) {
      const Vec3 n = f.normal(a, b);
      gx = a + r * n[0] - x;
      gy = b + r * n[1] - y;
    };
    double gx, gy;
    g(u, v, gx, gy);
    const double h = 1e-6;
    double ax, ay, bx, by;
    g(u + h, v, ax, ay);
    g(u, v + h, bx, by);
    const double j11 = (ax - gx) / h, j21 = (ay - gy) / h, j12 = (bx - gx) / h, j22 = (by - gy) / h;
    const double det = j11 * j22 - j12 * j21;
    const double du = (gx * j22 - gy * j12) / det, dv = (gy * j11 - gx * j21) / det;
    u -= du;
    v -= dv;
    if (std::abs(du) + std::abs(dv) < 1e-14) break;
  }
  q = {u, v, f.z(u, v)};
  centre = q + r * f.normal(u, v);
}

struct Stats {
  double ss = 0.0, max = 0.0;
  int n = 0;
  void add(double e) {
    ss += e * e;
    max = std::max(max, std::abs(e));
    ++n;
  }
  double rms() const { return n ? std::sqrt(ss / n) : 0.0; }
};

ProbeCalibration section_calibration(std::uint64_t seed, double noise_um) {
  std::printf("1. probe calibration on a 6 mm reference sphere (pre-travel axial %.0f, lateral %.0f, lobe %.0f µm; "
              "repeatability %.2f µm; 7 polar nodes x order 4; 16 azimuths a ring, 3 repeats: 289 touches)\n",
              um(kAxial), um(kLateral), um(kLobe), noise_um);
  const Vec3 centre{20.0, 5.0, 2.0};
  const double rs = 6.0;
  const CalibrationLayout layout;
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, noise_um * 1e-3);
  std::vector<ProbeTouch> touches;
  for (int rep = 0; rep < 3; ++rep)
    for (const Vec3& d : calibration_directions(layout, 16)) touches.push_back({centre - (rs + true_reff(d) + noise(rng)) * d, d});
  ProbeCalibration known_cal;
  for (int fitted = 0; fitted < 2; ++fitted) {
    const ProbeCalibrationResult r = calibrate_probe(touches, rs, layout, fitted ? nullptr : &centre);
    if (!r.ok()) {
      std::printf("  refused: %s\n", r.error.c_str());
      continue;
    }
    const Vec3 dc = r.sphere_centre - centre;
    Stats raw, offset_removed;
    std::uniform_real_distribution<double> th(0.0, std::numbers::pi / 2), ps(-std::numbers::pi, std::numbers::pi);
    for (int i = 0; i < 2000; ++i) {
      const Vec3 d = approach_direction(th(rng), ps(rng));
      raw.add(effective_radius(r.cal, d) - true_reff(d));
      offset_removed.add(effective_radius(r.cal, d) - true_reff(d) - dot(dc, d));
    }
    std::printf("  centre %-6s residuals RMS %.3f max %.3f µm; r_eff - truth over 2000 directions RMS %.3f max %.3f µm",
                fitted ? "fitted" : "known", um(r.rms), um(r.max_abs), um(raw.rms()), um(raw.max));
    if (fitted)
      std::printf("; centre off by (%.2f, %.2f, %.2f) µm, minus (c_fit - c).d: RMS %.3f max %.3f µm", um(dc[0]), um(dc[1]),
                  um(dc[2]), um(offset_removed.rms()), um(offset_removed.max));
    std::printf("\n");
    if (!fitted) known_cal = r.cal;
  }
  // The seed's Fig. 2: pre-travel R_ball − r_eff by direction, calibrated (known centre) / true.
  std::printf("  pre-travel by direction, µm, calibrated / true (polar θ from -Z down the rows, azimuth ψ across):\n  %8s", "");
  for (int psi = 0; psi < 360; psi += 45) std::printf("    ψ=%3d°   ", psi);
  std::printf("\n");
  for (int th = 0; th <= 90; th += 30) {
    std::printf("  θ=%3d° ", th);
    for (int psi = 0; psi < 360; psi += 45) {
      const Vec3 d = approach_direction(th * std::numbers::pi / 180, psi * std::numbers::pi / 180);
      std::printf(" %5.2f/%5.2f", um(kBall - effective_radius(known_cal, d)), um(kBall - true_reff(d)));
    }
    std::printf("\n");
  }
  return known_cal;
}

void section_slope(const ProbeCalibration& cal) {
  std::printf("\n2. ball correction, 1 mm ball straight down, 7 x 7 grid over X/Y 2.5..22.5, r_eff(-Z) = %.4f mm calibrated "
              "(true %.4f)\n", effective_radius(cal, {0, 0, -1}), true_reff({0, 0, -1}));
  std::printf("  %-30s %6s %11s %13s %11s %12s %13s\n", "surface", "slope", "naive max", "normal error", "corr. Z max",
              "corr. Z RMS", "corr. to q max");
  for (int kind = 0; kind < 3; ++kind) {
    const Field f{kind};
    const double r = true_reff({0, 0, -1});
    PointGrid centres;
    centres.cols = centres.rows = 7;
    std::vector<Vec3> truth;
    for (int row = 0; row < 7; ++row)
      for (int col = 0; col < 7; ++col) {
        const double x = 2.5 + 20.0 * col / 6, y = 2.5 + 20.0 * row / 6;
        Vec3 c, q;
        latch(f, x, y, r, c, q);
        centres.points.push_back(c);
        truth.push_back(q);
      }
    const GridCompensation comp = compensate_grid(centres, {{0, 0, -1}}, cal);
    Stats naive, angle, corrected, to_q;
    double max_slope = 0.0;
    for (std::size_t i = 0; i < truth.size(); ++i) {
      const Vec3& c = centres.points[i];
      const Vec3 n = f.normal(truth[i][0], truth[i][1]);
      const double slope = std::acos(n[2]) * 180.0 / std::numbers::pi;
      max_slope = std::max(max_slope, slope);
      const double e_naive = (c[2] - kBall) - f.z(c[0], c[1]);
      naive.add(e_naive);
      angle.add(std::acos(std::min(1.0, dot(comp.normals[i], n))));
      const Vec3& q = comp.contacts.points[i];
      corrected.add(q[2] - f.z(q[0], q[1]));  // height error at the corrected point's X/Y
      to_q.add(norm(q - truth[i]));
    }
    static const char* names[3] = {"8 sin((x-2.5)/8) + 0.5 cos(y/4)", "plane z = x", "3 sin(x/3) + 0.5 cos(y/4)"};
    std::printf("  %-30s %5.1f° %8.1f µm %9.4f rad %8.3f µm %9.3f µm %10.3f µm\n", names[kind], max_slope, um(naive.max),
                angle.max, um(corrected.max), um(corrected.rms()), um(to_q.max));
  }
  std::printf("  (naive: centre Z - ball radius taken as the height at the centre's X/Y, r (1/cos 45° - 1) = %.1f µm for "
              "r = 1 mm; corr. Z: the corrected point's Z minus the surface at its X/Y; corr. to q: its distance to the true "
              "contact point)\n", um(kBall * (std::sqrt(2.0) - 1.0)));
}

VolumetricError synthetic_machine(std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, 1e-3);
  VolumetricError m;
  for (int a = 0; a < kAxes; ++a) {
    PitchTable& t = m.pitch[static_cast<std::size_t>(a)];
    t.step_mm = 2.5;
    t.count = 11;
    for (int k = 0; k < 11; ++k) t.error_mm[static_cast<std::size_t>(k)] = 4e-3 * std::sin(0.5 * k + a) + noise(rng);
    // zero at node 0, as calibration sets it (lengths do not see it): the calibrated model can
    // then equal the truth, with no constant shift between the two
    for (int k = 10; k >= 0; --k) t.error_mm[static_cast<std::size_t>(k)] -= t.error_mm[0];
  }
  m.squareness_xy_urad = 40.0;
  m.squareness_yz_urad = -25.0;
  m.squareness_zx_urad = 15.0;
  return m;
}

// Returns the calibrated model (count 0 tables when the calibration was refused).
VolumetricError section_volumetric(std::uint64_t seed, double noise_um) {
  std::printf("\n3. volumetric error, synthetic machine (pitch tables 0..25 mm every 2.5 mm, ~5 µm; squareness 40/-25/15 "
              "µrad), artefact: 3 step gauges (10 lengths each) + 6 diagonals, length noise %.2f µm\n", noise_um);
  const VolumetricError truth = synthetic_machine(seed);
  std::mt19937_64 rng(seed + 1);
  std::normal_distribution<double> noise(0.0, noise_um * 1e-3);
  std::vector<LengthMeasurement> lengths;
  auto add = [&](const Vec3& a, const Vec3& b) {
    lengths.push_back({nominal_position(truth, a), nominal_position(truth, b), norm(b - a) + noise(rng)});
  };
  for (int k = 1; k <= 10; ++k) {
    add({0, 12.5, 5}, {2.5 * k, 12.5, 5});
    add({12.5, 0, 5}, {12.5, 2.5 * k, 5});
    add({12.5, 12.5, 0}, {12.5, 12.5, 2.5 * k});
  }
  add({0, 0, 5}, {25, 25, 5});
  add({0, 25, 5}, {25, 0, 5});
  add({12.5, 0, 0}, {12.5, 25, 25});
  add({12.5, 0, 25}, {12.5, 25, 0});
  add({0, 12.5, 0}, {25, 12.5, 25});
  add({0, 12.5, 25}, {25, 12.5, 0});
  VolumetricError layout;
  for (int a = 0; a < kAxes; ++a) {
    layout.pitch[static_cast<std::size_t>(a)] = truth.pitch[static_cast<std::size_t>(a)];
    layout.pitch[static_cast<std::size_t>(a)].error_mm.fill(0.0);
  }
  const VolumetricCalibration cal = calibrate_volumetric(lengths, layout);
  if (!cal.ok()) {
    std::printf("  refused: %s\n", cal.error.c_str());
    return {};
  }
  std::printf("  artefact lengths: error RMS %.3f max %.3f µm before, %.3f / %.3f µm after (%d Gauss-Newton steps)\n",
              um(cal.rms_before), um(cal.max_before), um(cal.rms_after), um(cal.max_after), cal.iterations);
  std::printf("  squareness identified: xy %.2f, yz %.2f, zx %.2f µrad\n", cal.model.squareness_xy_urad,
              cal.model.squareness_yz_urad, cal.model.squareness_zx_urad);
  // Moving to a wanted (actual) point: uncompensated, command it as it is; compensated, command
  // nominal_position(model, it). Errors relative to the machine's centre (the work origin).
  const Vec3 origin{12.5, 12.5, 12.5};
  auto landed = [&](const Vec3& want, bool comp) {
    return actual_position(truth, comp ? nominal_position(cal.model, want) : want);
  };
  const Vec3 o_raw = landed(origin, false) - origin, o_comp = landed(origin, true) - origin;
  Stats before, after;
  std::uniform_real_distribution<double> u(0.0, 25.0);
  for (int i = 0; i < 2000; ++i) {
    const Vec3 p{u(rng), u(rng), u(rng)};
    before.add(norm(landed(p, false) - p - o_raw));
    after.add(norm(landed(p, true) - p - o_comp));
  }
  std::printf("  position error over 2000 random points (|.|, relative to the centre): before RMS %.3f max %.3f µm, "
              "after RMS %.3f max %.3f µm\n", um(before.rms()), um(before.max), um(after.rms()), um(after.max));
  return cal.model;
}

// The chain: the 8 sin surface probed straight down on the synthetic machine (encoders read
// nominal positions), ball-corrected with and without E_V removed first.
void section_chain(std::uint64_t seed, const VolumetricError& model, const ProbeCalibration& cal) {
  const VolumetricError truth = synthetic_machine(seed);
  const Field f{0, 10.0};  // z 2..18 mm: inside the Z pitch table
  const double r = true_reff({0, 0, -1});
  PointGrid nominal;
  nominal.cols = nominal.rows = 7;
  for (int row = 0; row < 7; ++row)
    for (int col = 0; col < 7; ++col) {
      Vec3 c, q;
      latch(f, 2.5 + 20.0 * col / 6, 2.5 + 20.0 * row / 6, r, c, q);  // in actual space
      nominal.points.push_back(nominal_position(truth, c));            // what the encoders read
    }
  PointGrid actual = nominal;
  for (Vec3& p : actual.points) p = actual_position(model, p);
  std::printf("  the chain: 10 + 8 sin((x-2.5)/8) + 0.5 cos(y/4) on this machine, 7 x 7 probes straight down, "
              "corrected Z minus the surface at its X/Y, less its mean (a Z touch-off):\n");
  for (int with_ev = 0; with_ev < 2; ++with_ev) {
    const GridCompensation comp = compensate_grid(with_ev ? actual : nominal, {{0, 0, -1}}, cal);
    std::vector<double> dz;
    double mean = 0.0;
    for (const Vec3& q : comp.contacts.points) {
      dz.push_back(q[2] - f.z(q[0], q[1]));
      mean += dz.back() / static_cast<double>(comp.contacts.points.size());
    }
    Stats z;  // less the mean: a Z touch-off on the part removes it
    for (double e : dz) z.add(e - mean);
    std::printf("    %-34s RMS %.3f max %.3f µm\n", with_ev ? "ball correction after E_V removed" : "ball correction only",
                um(z.rms()), um(z.max));
  }
}

template <class F>
double ns_per_call(int n, F&& f) {
  const auto t0 = Clock::now();
  for (int i = 0; i < n; ++i) f(i);
  return std::chrono::duration<double, std::nano>(Clock::now() - t0).count() / n;
}

void section_cost(const ProbeCalibration& cal) {
  std::printf("\n4. cost, ns per call (mean over many calls; one core of a shared VM):\n");
  const VolumetricError m = synthetic_machine(1);
  volatile double sink = 0.0;
  const double reff = ns_per_call(200000, [&](int i) { sink = sink + effective_radius(cal, approach_direction(1e-5 * i, 3e-5 * i)); });
  const double fwd = ns_per_call(200000, [&](int i) { sink = sink + actual_position(m, {1e-4 * i, 2.0, 3.0})[1]; });
  const double inv = ns_per_call(200000, [&](int i) { sink = sink + nominal_position(m, {1e-4 * i, 2.0, 3.0})[1]; });
  const double cp = ns_per_call(200000, [&](int i) { sink = sink + contact_point({1e-4 * i, 0, 1}, {0.1, 0.2, 1}, {0, 0, -1}, cal)[2]; });
  std::printf("  r_eff(d) %.0f, actual_position %.0f, nominal_position (fixed point) %.0f, contact_point with r_eff %.0f\n",
              reff, fwd, inv, cp);
  PointGrid g;
  g.cols = g.rows = 7;
  for (int r = 0; r < 7; ++r)
    for (int c = 0; c < 7; ++c) g.points.push_back({c * 3.0, r * 3.0, std::sin(c * 0.3) + 1.0});
  const double grid = ns_per_call(200, [&](int) { sink = sink + compensate_grid(g, {{0, 0, -1}}, cal).contacts.points[5][2]; });
  std::vector<Vec3> sphere;
  for (const Vec3& d : calibration_directions(CalibrationLayout{}, 8)) sphere.push_back(-7.0 * d);
  const double sf = ns_per_call(2000, [&](int) { sink = sink + fit_sphere(sphere).radius; });
  std::printf("  compensate_grid 7 x 7 %.1f µs, fit_sphere %zu points %.1f µs\n", grid / 1000, sphere.size(), sf / 1000);
  if (sink == 12345.678) std::printf(" ");
}

}  // namespace

int main(int argc, char** argv) {
  pcnc::BenchCli app{"bench_probe_math: ball correction, probe calibration, volumetric error (issue 15 item 3)"};
  std::uint64_t seed = 1;
  double noise_um = 0.3, length_noise_um = 0.2;
  app.add_option("--seed", seed, "seed of the noise and of the synthetic machine")->show_default();
  app.add_option("--noise-um", noise_um, "probe repeatability (1 sigma), µm")->show_default();
  app.add_option("--length-noise-um", length_noise_um, "artefact length noise (1 sigma), µm")->show_default();
  if (const int rc = app.parse(argc, argv); rc >= 0) return rc;
  const ProbeCalibration cal = section_calibration(seed, noise_um);
  section_slope(cal);
  const VolumetricError model = section_volumetric(seed, length_noise_um);
  section_chain(seed, model, cal);
  section_cost(cal);
  return 0;
}
