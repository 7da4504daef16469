// volumetric_error.cpp — E_V(X, Y, Z), its inverse and its calibration from artefact lengths
// (see volumetric_error.hpp).
#include "geometry/volumetric_error.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>

namespace pcnc {
namespace {

constexpr double kUrad = 1e-6;

// The node k and the fraction w of `pos` in a table (clamped: outside, w is 0 or 1 at an end).
void pitch_cell(const PitchTable& t, double pos, int& k, double& w) {
  const double s = std::clamp((pos - t.start_mm) / t.step_mm, 0.0, static_cast<double>(t.count - 1));
  k = std::min(static_cast<int>(s), t.count - 2);
  w = s - k;
}

// The parameters being identified: pitch nodes 1.. of each axis, then S_xy, S_yz, S_zx.
struct Columns {
  std::array<int, kAxes> first{};  // column of node 1 of axis i
  int squareness = 0;              // column of S_xy
  int total = 0;
};

Columns columns(const VolumetricError& layout) {
  Columns c;
  int col = 0;
  for (int i = 0; i < kAxes; ++i) {
    c.first[static_cast<std::size_t>(i)] = col;
    col += std::max(0, layout.pitch[static_cast<std::size_t>(i)].count - 1);
  }
  c.squareness = col;
  c.total = col + 3;
  return c;
}

// Adds sign·∂E(p)/∂θ_j for every column j into the 3 × total block d.
void add_basis(const VolumetricError& layout, const Columns& c, const Vec3& p, double sign, Eigen::MatrixXd& d) {
  for (int i = 0; i < kAxes; ++i) {
    const PitchTable& t = layout.pitch[static_cast<std::size_t>(i)];
    if (t.count < 2) continue;
    int k = 0;
    double w = 0.0;
    pitch_cell(t, p[static_cast<std::size_t>(i)], k, w);
    const int first = c.first[static_cast<std::size_t>(i)];
    if (k >= 1) d(i, first + k - 1) += sign * (1.0 - w);
    d(i, first + k) += sign * w;  // node k + 1 >= 1
  }
  d(1, c.squareness + 0) += sign * p[0] * kUrad;  // S_xy·x into y
  d(1, c.squareness + 1) += sign * p[2] * kUrad;  // S_yz·z into y
  d(0, c.squareness + 2) += sign * p[2] * kUrad;  // S_zx·z into x
}

// The model with the parameters θ written into the layout's tables and squarenesses.
VolumetricError with_params(const VolumetricError& layout, const Columns& c, const Eigen::VectorXd& x) {
  VolumetricError m = layout;
  for (int i = 0; i < kAxes; ++i) {
    PitchTable& t = m.pitch[static_cast<std::size_t>(i)];
    if (t.count < 1) continue;
    t.error_mm[0] = 0.0;
    for (int k = 1; k < t.count; ++k) t.error_mm[static_cast<std::size_t>(k)] = x(c.first[static_cast<std::size_t>(i)] + k - 1);
  }
  m.squareness_xy_urad = x(c.squareness);
  m.squareness_yz_urad = x(c.squareness + 1);
  m.squareness_zx_urad = x(c.squareness + 2);
  return m;
}

std::string column_name(const VolumetricError& layout, const Columns& c, int col) {
  static const char* kSquare[3] = {"squareness_xy (no length with both X and Y travel)",
                                   "squareness_yz (no length with both Y and Z travel)",
                                   "squareness_zx (no length with both Z and X travel)"};
  if (col >= c.squareness) return kSquare[col - c.squareness];
  for (int i = kAxes - 1; i >= 0; --i) {
    if (col >= c.first[static_cast<std::size_t>(i)]) {
      const PitchTable& t = layout.pitch[static_cast<std::size_t>(i)];
      const int k = col - c.first[static_cast<std::size_t>(i)] + 1;
      return std::string("pitch ") + axis_name(i) + " node " + std::to_string(k) + " at " +
             std::to_string(t.start_mm + k * t.step_mm) + " mm (no measured point within a step of it)";
    }
  }
  return "?";
}

void summarise_errors(const std::vector<double>& v, double& rms, double& max_abs) {
  double ss = 0.0;
  max_abs = 0.0;
  for (double x : v) {
    ss += x * x;
    max_abs = std::max(max_abs, std::abs(x));
  }
  rms = v.empty() ? 0.0 : std::sqrt(ss / static_cast<double>(v.size()));
}

}  // namespace

double PitchTable::at(double position_mm) const {
  if (count < 1) return 0.0;
  if (count == 1) return error_mm[0];
  int k = 0;
  double w = 0.0;
  pitch_cell(*this, position_mm, k, w);
  return (1.0 - w) * error_mm[static_cast<std::size_t>(k)] + w * error_mm[static_cast<std::size_t>(k + 1)];
}

std::string validate(const VolumetricError& m) {
  for (int i = 0; i < kAxes; ++i) {
    const PitchTable& t = m.pitch[static_cast<std::size_t>(i)];
    const std::string key = std::string("pitch_") + static_cast<char>('x' + i);
    if (t.count < 0 || t.count > kMaxPitchNodes) return key + ": count must be 0.." + std::to_string(kMaxPitchNodes);
    if (!std::isfinite(t.start_mm) || (t.count >= 2 && !(t.step_mm > 0.0 && std::isfinite(t.step_mm))))
      return key + ": start must be finite and the step > 0";
    for (int k = 0; k < t.count; ++k) {
      if (!std::isfinite(t.error_mm[static_cast<std::size_t>(k)])) return key + ": an error is not a finite number";
      if (k > 0 && std::abs(t.error_mm[static_cast<std::size_t>(k)] - t.error_mm[static_cast<std::size_t>(k - 1)]) >= 0.01 * t.step_mm)
        return key + ": the error changes by 1 % of the travel or more between nodes " + std::to_string(k - 1) + " and " +
               std::to_string(k);
    }
  }
  for (double s : {m.squareness_xy_urad, m.squareness_yz_urad, m.squareness_zx_urad})
    if (!(std::abs(s) < 1e4)) return "squareness: must be finite and below 10000 µrad";
  for (int i = 0; i < kAxes; ++i) {
    const std::size_t a = static_cast<std::size_t>(i);
    if (!std::isfinite(m.growth_per_K[a]) || !std::isfinite(m.origin_drift_mm[a]) ||
        !(std::abs(m.growth_per_K[a] * m.temperature_offset_K) < 0.01))
      return "thermal: growth, temperature offset and drift must be finite, growth x offset below 0.01";
  }
  return {};
}

Vec3 volumetric_offset(const VolumetricError& m, const Vec3& p) {
  const double dt = m.temperature_offset_K;
  Vec3 e{};
  for (int i = 0; i < kAxes; ++i) {
    const std::size_t a = static_cast<std::size_t>(i);
    e[a] = m.pitch[a].at(p[a]) + m.growth_per_K[a] * dt * p[a] + m.origin_drift_mm[a];
  }
  e[0] += m.squareness_zx_urad * kUrad * p[2];
  e[1] += m.squareness_xy_urad * kUrad * p[0] + m.squareness_yz_urad * kUrad * p[2];
  return e;
}

Vec3 actual_position(const VolumetricError& m, const Vec3& nominal) { return nominal + volumetric_offset(m, nominal); }

Vec3 nominal_position(const VolumetricError& m, const Vec3& actual) {
  Vec3 n = actual;
  for (int it = 0; it < 30; ++it) {
    const Vec3 next = actual - volumetric_offset(m, n);
    const double step = norm(next - n);
    n = next;
    if (step < 1e-12) break;
  }
  return n;
}

VolumetricCalibration calibrate_volumetric(const std::vector<LengthMeasurement>& measurements,
                                           const VolumetricError& layout) {
  VolumetricCalibration out;
  for (int i = 0; i < kAxes; ++i) {
    const PitchTable& t = layout.pitch[static_cast<std::size_t>(i)];
    if (t.count < 0 || t.count > kMaxPitchNodes || (t.count >= 2 && !(t.step_mm > 0.0))) {
      out.error = std::string("pitch table ") + axis_name(i) + ": count 0.." + std::to_string(kMaxPitchNodes) +
                  " and a step > 0 are needed";
      return out;
    }
  }
  const Columns c = columns(layout);
  const int n = static_cast<int>(measurements.size());
  if (n < c.total) {
    out.error = std::to_string(n) + " lengths for " + std::to_string(c.total) + " parameters";
    return out;
  }
  for (const LengthMeasurement& m : measurements) {
    if (!(m.length_mm > 0.0) || !(norm(m.b - m.a) > 0.0)) {
      out.error = "a length measurement with no length";
      return out;
    }
  }
  // The known part of the model (growth, ΔT, drift), without pitch or squareness.
  VolumetricError known = layout;
  for (PitchTable& t : known.pitch) t.error_mm.fill(0.0);
  known.squareness_xy_urad = known.squareness_yz_urad = known.squareness_zx_urad = 0.0;

  std::vector<Eigen::MatrixXd> basis(static_cast<std::size_t>(n));  // ∂(E(b) − E(a))/∂θ
  for (int r = 0; r < n; ++r) {
    Eigen::MatrixXd d = Eigen::MatrixXd::Zero(3, c.total);
    add_basis(layout, c, measurements[static_cast<std::size_t>(r)].b, 1.0, d);
    add_basis(layout, c, measurements[static_cast<std::size_t>(r)].a, -1.0, d);
    basis[static_cast<std::size_t>(r)] = d;
  }
  Eigen::VectorXd x = Eigen::VectorXd::Zero(c.total);
  Eigen::MatrixXd j(n, c.total);
  Eigen::VectorXd f(n);
  for (int it = 0; it < 10; ++it) {
    for (int r = 0; r < n; ++r) {
      const LengthMeasurement& m = measurements[static_cast<std::size_t>(r)];
      const Vec3 fixed = (m.b - m.a) + volumetric_offset(known, m.b) - volumetric_offset(known, m.a);
      const Eigen::Vector3d delta = Eigen::Vector3d(fixed[0], fixed[1], fixed[2]) + basis[static_cast<std::size_t>(r)] * x;
      const double len = delta.norm();
      f(r) = len - m.length_mm;
      j.row(r) = (delta / len).transpose() * basis[static_cast<std::size_t>(r)];
    }
    // Each parameter must move some length enough to be told apart: a pitch node by at least
    // 5% of its own value (a measured point within 95% of a step of it), a squareness by at
    // least 0.05 µm per 1000 µrad (a length with 0.05 mm of travel across the leaning axis).
    Eigen::VectorXd scale(c.total);
    for (int col = 0; col < c.total; ++col) {
      const double seen = j.col(col).cwiseAbs().maxCoeff();
      const double needed = col >= c.squareness ? 0.05 * kUrad : 0.05;
      if (it == 0 && !(seen >= needed)) {
        out.error = "the artefact does not determine " + column_name(layout, c, col);
        return out;
      }
      scale(col) = seen > 0.0 ? 1.0 / j.col(col).norm() : 1.0;
    }
    Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(j * scale.asDiagonal());
    qr.setThreshold(1e-9);
    if (qr.rank() < c.total) {
      out.error = "the artefact's lengths leave " + std::to_string(c.total - qr.rank()) +
                  " combination(s) of pitch and squareness undetermined: measure more positions or diagonals";
      return out;
    }
    const Eigen::VectorXd step = scale.asDiagonal() * qr.solve(-f);
    x += step;
    out.iterations = it + 1;
    if (step.lpNorm<Eigen::Infinity>() < 1e-10) break;  // mm and µrad: far below any figure
  }
  out.model = with_params(layout, c, x);
  for (const LengthMeasurement& m : measurements) {
    out.before_mm.push_back(norm(m.b - m.a) - m.length_mm);
    out.after_mm.push_back(norm(actual_position(out.model, m.b) - actual_position(out.model, m.a)) - m.length_mm);
  }
  summarise_errors(out.before_mm, out.rms_before, out.max_before);
  summarise_errors(out.after_mm, out.rms_after, out.max_after);
  return out;
}

}  // namespace pcnc
