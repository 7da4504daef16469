// probe_calibration.hpp — the touch probe's effective radius as a function of its approach
// direction, calibrated on a reference sphere (issue 15 item 3; the seed's Fig. 2, E_P(θ, ψ)).
//
// A touch-trigger probe latches its ball centre p a little after the ball first meets the
// surface: the stylus must deflect by the pre-travel δ, which depends on the direction d the
// probe moves in (lobing). At the latch the ball centre is r_eff(d) = R_ball − δ(d) from the
// surface, along the surface normal n. On a reference sphere (centre c, radius R_s) touched
// along d = −n, |p − c| = R_s + r_eff(d): each touch measures r_eff in its direction.
//
// The model (chosen here, docs/measurement.md): d's polar angle θ from −Z (θ = 0: straight
// down, π/2: horizontal) and azimuth ψ = atan2(d_y, d_x); polar nodes θ_k = k·θ_max/(K − 1),
// and at each node a Fourier series in ψ of order M:
//   f_k(ψ) = A_k0 + Σ_{m=1..M} A_km cos mψ + B_km sin mψ,   f_0 = A_00 (the pole has no ψ),
//   r_eff(θ, ψ) = (1 − w) f_k(ψ) + w f_{k+1}(ψ),   θ in [θ_k, θ_{k+1}], w its fraction;
// θ above θ_max is held at θ_max. The coefficients are the linear least-squares solution over
// all touches. Evaluation allocates nothing (fixed-size arrays), so the rt could use it.
// Pure mathematics: std, Eigen in the .cpp only.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "geometry/vec3.hpp"

namespace pcnc {

constexpr int kMaxPolarNodes = 13;  // up to 12 polar intervals (7.5° over 90°)
constexpr int kMaxHarmonic = 6;     // Fourier order in the azimuth

struct ProbeCalibration {
  int polar_nodes = 0;                      // K >= 2
  double polar_max_rad = 1.5707963267948966;  // θ_max
  int harmonics = 0;                        // M, 0..kMaxHarmonic
  // coeff[k][0] = A_k0, coeff[k][2m-1] = A_km, coeff[k][2m] = B_km (mm)
  std::array<std::array<double, 2 * kMaxHarmonic + 1>, kMaxPolarNodes> coeff{};
};

/// Why `cal` is not a usable table ("<field>: <why>"), or an empty string: polar_nodes
/// 2..kMaxPolarNodes, harmonics 0..kMaxHarmonic, polar_max_rad in (0, π], finite coefficients.
std::string validate(const ProbeCalibration& cal);

/// A probe without lobing: r_eff = `radius` in every direction.
ProbeCalibration constant_calibration(double radius);

/// The approach direction's angles (normalised inside): polar θ from −Z in [0, π], azimuth ψ
/// = atan2(d_y, d_x) (0 on the Z axis).
struct ApproachAngles {
  double polar = 0.0;
  double azimuth = 0.0;
};
ApproachAngles approach_angles(const Vec3& approach);
/// The unit approach direction of (θ, ψ): (sin θ cos ψ, sin θ sin ψ, −cos θ).
Vec3 approach_direction(double polar, double azimuth);

/// r_eff for a probe moving along `approach` (mm). Allocation-free. A table with polar_nodes
/// or harmonics out of range gives 0 (validate() says why).
double effective_radius(const ProbeCalibration& cal, const Vec3& approach);

/// One touch: the latched ball centre (mm) and the direction the probe was moving in.
struct ProbeTouch {
  Vec3 centre{};
  Vec3 approach{};
};

/// The layout of the table to calibrate.
struct CalibrationLayout {
  int polar_nodes = 7;                      // 15° steps over 90°
  double polar_max_rad = 1.5707963267948966;
  int harmonics = 4;
};

/// The touches a calibration needs: at each polar node one ring of `per_ring` azimuths
/// (equally spaced, starting at ψ = 0), the pole once; approach directions only.
std::vector<Vec3> calibration_directions(const CalibrationLayout& layout, int per_ring);

struct ProbeCalibrationResult {
  ProbeCalibration cal;
  Vec3 sphere_centre{};           // the known centre, or the one fitted through the touches
  bool centre_fitted = false;
  std::vector<double> measured;   // r_eff of each touch, |p − c| − R_s (mm)
  std::vector<double> residuals;  // measured − model, mm
  double rms = 0.0;
  double max_abs = 0.0;
  std::string error;
  bool ok() const { return error.empty(); }
};

/// Calibrates on a sphere of radius `sphere_radius` (mm). With `known_centre` null the centre
/// is the least-squares sphere through the latched centres (sphere_fit.hpp); then r_eff is
/// known only up to t·d for a constant vector t (the centre's error: a constant probe offset,
/// docs/measurement.md). Refuses bad layouts, too few touches, and tables that the touches do
/// not determine (a polar ring with fewer than 2M + 1 distinct azimuths near it).
ProbeCalibrationResult calibrate_probe(const std::vector<ProbeTouch>& touches, double sphere_radius,
                                       const CalibrationLayout& layout, const Vec3* known_centre = nullptr);

}  // namespace pcnc
