// volumetric_error.hpp — the machine's quasi-static volumetric error E_V(X, Y, Z) (issue 15
// item 3; the seed's eq. 3) as a value type: where the machine really is when its encoders
// read a nominal position, and the way back. Evaluation allocates nothing (fixed-size
// tables), so the rt's simulation can use it every cycle.
//
//   actual = nominal + E(nominal),  with, for nominal (x, y, z) in mm,
//     E_x = δ_x(x) + g_x·ΔT·x + o_x               + S_zx·z
//     E_y = δ_y(y) + g_y·ΔT·y + o_y + S_xy·x      + S_yz·z
//     E_z = δ_z(z) + g_z·ΔT·z + o_z
//   δ_i   the pitch error of axis i at its own position (a table, linear between nodes,
//         held at its end values outside),
//   S_xy  the X axis leaning towards +Y (µrad in the value type, rad in the formula), S_yz and
//         S_zx the Z axis leaning towards +Y and +X: the three squareness errors,
//   g_i   linear thermal growth (1/K), ΔT the temperature offset from the reference (K),
//   o_i   the origin drift (mm: the seed's Σ Δa_i, Σ Δb_i, Σ Δc_i).
// The seed's e = −E with its PYZ of the opposite sign (S_yz = −PYZ); docs/measurement.md.
//
// Calibration from a reference artefact (lengths known from a CMM, measured on the machine):
// each measurement is two nominal readings a, b whose true distance is L. |Δ| = |b − a +
// E(b) − E(a)| is linear in the pitch nodes and squarenesses but for the norm; Gauss–Newton
// solves for them (the first node of every table held at 0: lengths see only differences).
// Pure mathematics: std, Eigen in the .cpp only.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "geometry/vec3.hpp"

namespace pcnc {

constexpr int kMaxPitchNodes = 33;

/// The pitch error of one axis at its own position: nodes start + k·step, k < count.
struct PitchTable {
  double start_mm = 0.0;
  double step_mm = 1.0;
  int count = 0;                                   // 0: no pitch error
  std::array<double, kMaxPitchNodes> error_mm{};
  double at(double position_mm) const;            // linear between nodes, held outside
};

struct VolumetricError {
  std::array<PitchTable, kAxes> pitch{};
  double squareness_xy_urad = 0.0;
  double squareness_yz_urad = 0.0;
  double squareness_zx_urad = 0.0;
  Vec3 growth_per_K{0.0, 0.0, 0.0};   // g_x, g_y, g_z (1/K; steel ≈ 11.5e-6)
  double temperature_offset_K = 0.0;  // ΔT
  Vec3 origin_drift_mm{0.0, 0.0, 0.0};
};

/// Why `m` is not a usable model, as "<field>: <why>", or an empty string: table counts
/// 0..kMaxPitchNodes, a step > 0 where count >= 2, finite numbers, and a pitch slope plus the
/// squarenesses far below 1 (each table's slope between nodes below 0.01, each squareness
/// below 10000 µrad), which is what makes the inverse's fixed point converge.
std::string validate(const VolumetricError& m);

/// E(nominal), mm.
Vec3 volumetric_offset(const VolumetricError& m, const Vec3& nominal);
/// nominal + E(nominal): where the machine is when the encoders read `nominal`.
Vec3 actual_position(const VolumetricError& m, const Vec3& nominal);
/// The nominal reading that puts the machine at `actual`: the fixed point n = actual − E(n),
/// iterated from n = actual until the step is below 1e-12 mm (at most 30 steps; it contracts
/// while every pitch slope and squareness is far below 1).
Vec3 nominal_position(const VolumetricError& m, const Vec3& actual);

/// One artefact length: the nominal readings of two of its features and their true distance.
struct LengthMeasurement {
  Vec3 a{};
  Vec3 b{};
  double length_mm = 0.0;
};

struct VolumetricCalibration {
  VolumetricError model;            // the layout's tables filled, squareness identified
  std::vector<double> before_mm;    // per measurement: nominal |b − a| − L (the error seen)
  std::vector<double> after_mm;     // |actual(b) − actual(a)| − L with the identified model
  double rms_before = 0.0, rms_after = 0.0;
  double max_before = 0.0, max_after = 0.0;
  int iterations = 0;
  std::string error;                // refusal, or which parameter the artefact does not fix
  bool ok() const { return error.empty(); }
};

/// Identifies the pitch tables (the layout's start, step and count per axis; node 0 held at 0)
/// and the three squarenesses from the measurements; growth, ΔT and origin drift are taken
/// from `layout` as known (lengths at one temperature cannot separate growth from pitch, and
/// no length sees an origin). Refuses when the measurements leave a parameter undetermined
/// (a pitch node no measurement spans, a plane with no diagonal) and names it.
VolumetricCalibration calibrate_volumetric(const std::vector<LengthMeasurement>& measurements,
                                           const VolumetricError& layout);

}  // namespace pcnc
