// probe_calibration.cpp — r_eff(θ, ψ) on a reference sphere (see probe_calibration.hpp).
#include "geometry/probe_calibration.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "geometry/sphere_fit.hpp"

namespace pcnc {
namespace {

// The polar cell k and the fraction w across it, θ clamped to [0, θ_max].
void polar_cell(int nodes, double polar_max, double polar, int& k, double& w) {
  const double h = polar_max / (nodes - 1);
  const double t = std::clamp(polar, 0.0, polar_max) / h;
  k = std::min(static_cast<int>(t), nodes - 2);
  w = t - k;
}

// The Fourier row [1, cos ψ, sin ψ, ..., cos Mψ, sin Mψ] (recurrence, no allocation).
void fourier(double azimuth, int harmonics, double* row) {
  row[0] = 1.0;
  const double c1 = std::cos(azimuth), s1 = std::sin(azimuth);
  double c = 1.0, s = 0.0;
  for (int m = 1; m <= harmonics; ++m) {
    const double cn = c * c1 - s * s1;
    s = s * c1 + c * s1;
    c = cn;
    row[2 * m - 1] = c;
    row[2 * m] = s;
  }
}

// Column of coefficient j at polar node k in the unknown vector (the pole has one).
int column(int k, int j, int harmonics) { return k == 0 ? 0 : 1 + (k - 1) * (2 * harmonics + 1) + j; }

}  // namespace

std::string validate(const ProbeCalibration& cal) {
  if (cal.polar_nodes < 2 || cal.polar_nodes > kMaxPolarNodes)
    return "polar_nodes: must be 2.." + std::to_string(kMaxPolarNodes);
  if (cal.harmonics < 0 || cal.harmonics > kMaxHarmonic) return "harmonics: must be 0.." + std::to_string(kMaxHarmonic);
  if (!(cal.polar_max_rad > 0.0 && cal.polar_max_rad <= std::numbers::pi)) return "polar_max_rad: must be in (0, pi]";
  for (int k = 0; k < cal.polar_nodes; ++k)
    for (int j = 0; j <= 2 * cal.harmonics; ++j)
      if (!std::isfinite(cal.coeff[static_cast<std::size_t>(k)][static_cast<std::size_t>(j)]))
        return "coeff: node " + std::to_string(k) + " holds a number that is not finite";
  return {};
}

ProbeCalibration constant_calibration(double radius) {
  ProbeCalibration c;
  c.polar_nodes = 2;
  c.harmonics = 0;
  c.coeff[0][0] = radius;
  c.coeff[1][0] = radius;
  return c;
}

ApproachAngles approach_angles(const Vec3& approach) {
  const Vec3 d = normalized(approach);
  ApproachAngles a;
  a.polar = std::acos(std::clamp(-d[2], -1.0, 1.0));
  a.azimuth = (d[0] == 0.0 && d[1] == 0.0) ? 0.0 : std::atan2(d[1], d[0]);
  return a;
}

Vec3 approach_direction(double polar, double azimuth) {
  return {std::sin(polar) * std::cos(azimuth), std::sin(polar) * std::sin(azimuth), -std::cos(polar)};
}

double effective_radius(const ProbeCalibration& cal, const Vec3& approach) {
  if (cal.polar_nodes < 2 || cal.polar_nodes > kMaxPolarNodes || cal.harmonics < 0 || cal.harmonics > kMaxHarmonic)
    return 0.0;
  const ApproachAngles a = approach_angles(approach);
  int k = 0;
  double w = 0.0;
  polar_cell(cal.polar_nodes, cal.polar_max_rad, a.polar, k, w);
  double row[2 * kMaxHarmonic + 1];
  fourier(a.azimuth, cal.harmonics, row);
  auto ring = [&](int node) {
    if (node == 0) return cal.coeff[0][0];
    double v = 0.0;
    for (int j = 0; j <= 2 * cal.harmonics; ++j) v += cal.coeff[static_cast<std::size_t>(node)][static_cast<std::size_t>(j)] * row[j];
    return v;
  };
  return (1.0 - w) * ring(k) + w * ring(k + 1);
}

std::vector<Vec3> calibration_directions(const CalibrationLayout& layout, int per_ring) {
  std::vector<Vec3> out;
  if (layout.polar_nodes < 2 || per_ring < 1) return out;
  out.push_back(approach_direction(0.0, 0.0));
  for (int k = 1; k < layout.polar_nodes; ++k) {
    const double polar = layout.polar_max_rad * k / (layout.polar_nodes - 1);
    for (int i = 0; i < per_ring; ++i) out.push_back(approach_direction(polar, 2.0 * std::numbers::pi * i / per_ring));
  }
  return out;
}

ProbeCalibrationResult calibrate_probe(const std::vector<ProbeTouch>& touches, double sphere_radius,
                                       const CalibrationLayout& layout, const Vec3* known_centre) {
  ProbeCalibrationResult out;
  if (layout.polar_nodes < 2 || layout.polar_nodes > kMaxPolarNodes) {
    out.error = "polar_nodes must be 2.." + std::to_string(kMaxPolarNodes) + ", got " + std::to_string(layout.polar_nodes);
    return out;
  }
  if (layout.harmonics < 0 || layout.harmonics > kMaxHarmonic) {
    out.error = "harmonics must be 0.." + std::to_string(kMaxHarmonic) + ", got " + std::to_string(layout.harmonics);
    return out;
  }
  if (!(layout.polar_max_rad > 0.0 && layout.polar_max_rad <= std::numbers::pi)) {
    out.error = "polar_max_rad must be in (0, pi]";
    return out;
  }
  if (!(sphere_radius > 0.0)) {
    out.error = "the reference sphere's radius must be > 0";
    return out;
  }
  const int n = static_cast<int>(touches.size());
  const int m = layout.harmonics;
  const int unknowns = 1 + (layout.polar_nodes - 1) * (2 * m + 1);
  if (n < unknowns) {
    out.error = std::to_string(n) + " touches for " + std::to_string(unknowns) + " coefficients: probe more directions";
    return out;
  }
  for (const ProbeTouch& t : touches) {
    if (!(norm(t.approach) > 0.0)) {
      out.error = "a touch has no approach direction";
      return out;
    }
  }
  if (known_centre) {
    out.sphere_centre = *known_centre;
  } else {
    std::vector<Vec3> pts;
    pts.reserve(touches.size());
    for (const ProbeTouch& t : touches) pts.push_back(t.centre);
    const SphereFit s = fit_sphere(pts);
    if (!s.ok()) {
      out.error = "sphere centre: " + s.error;
      return out;
    }
    out.sphere_centre = s.centre;
    out.centre_fitted = true;
  }

  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(n, unknowns);
  Eigen::VectorXd b(n);
  double row[2 * kMaxHarmonic + 1];
  for (int i = 0; i < n; ++i) {
    const ProbeTouch& t = touches[static_cast<std::size_t>(i)];
    const double r = norm(t.centre - out.sphere_centre) - sphere_radius;
    out.measured.push_back(r);
    b(i) = r;
    const ApproachAngles ang = approach_angles(t.approach);
    int k = 0;
    double w = 0.0;
    polar_cell(layout.polar_nodes, layout.polar_max_rad, ang.polar, k, w);
    fourier(ang.azimuth, m, row);
    for (int side = 0; side < 2; ++side) {
      const int node = k + side;
      const double weight = side == 0 ? 1.0 - w : w;
      if (node == 0) {
        a(i, 0) += weight;
        continue;
      }
      for (int j = 0; j <= 2 * m; ++j) a(i, column(node, j, m)) += weight * row[j];
    }
  }
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(a);
  qr.setThreshold(1e-10);
  if (qr.rank() < unknowns) {
    out.error = "the touches do not determine the table (rank " + std::to_string(qr.rank()) + " of " +
                std::to_string(unknowns) + "): each polar ring needs at least " + std::to_string(2 * m + 1) +
                " distinct azimuths near it";
    return out;
  }
  const Eigen::VectorXd x = qr.solve(b);
  out.cal.polar_nodes = layout.polar_nodes;
  out.cal.polar_max_rad = layout.polar_max_rad;
  out.cal.harmonics = m;
  out.cal.coeff[0][0] = x(0);
  for (int k = 1; k < layout.polar_nodes; ++k)
    for (int j = 0; j <= 2 * m; ++j) out.cal.coeff[static_cast<std::size_t>(k)][static_cast<std::size_t>(j)] = x(column(k, j, m));

  double ss = 0.0;
  for (int i = 0; i < n; ++i) {
    const double res = out.measured[static_cast<std::size_t>(i)] - effective_radius(out.cal, touches[static_cast<std::size_t>(i)].approach);
    out.residuals.push_back(res);
    ss += res * res;
    out.max_abs = std::max(out.max_abs, std::abs(res));
  }
  out.rms = std::sqrt(ss / n);
  return out;
}

}  // namespace pcnc
