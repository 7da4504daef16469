// test_volumetric_error.cpp — the volumetric error model (geometry/volumetric_error): the
// forward formula against a hand evaluation, forward∘inverse and inverse∘forward the identity,
// and the calibration from a synthetic artefact (step gauges along X, Y, Z and two diagonals in
// each plane, read through a synthetic machine) recovering its pitch tables (up to the constant
// lengths cannot see) and squarenesses; artefacts that leave a parameter open are refused.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "geometry/volumetric_error.hpp"

namespace pcnc {
namespace {

constexpr double kStep = 2.5;
constexpr int kNodes = 11;  // 0 .. 25 mm

VolumetricError synthetic_machine(std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, 0.5e-3);
  VolumetricError m;
  for (int a = 0; a < kAxes; ++a) {
    PitchTable& t = m.pitch[static_cast<std::size_t>(a)];
    t.start_mm = 0.0;
    t.step_mm = kStep;
    t.count = kNodes;
    for (int k = 0; k < kNodes; ++k) t.error_mm[static_cast<std::size_t>(k)] = 4e-3 * std::sin(0.2 * k * kStep + a) + noise(rng);
  }
  m.squareness_xy_urad = 40.0;
  m.squareness_yz_urad = -25.0;
  m.squareness_zx_urad = 15.0;
  return m;
}

// The artefact: features at true (actual) positions; the machine reads where it must be
// commanded to touch them.
struct Artefact {
  std::vector<LengthMeasurement> lengths;
  void add(const VolumetricError& machine, const Vec3& a, const Vec3& b) {
    lengths.push_back({nominal_position(machine, a), nominal_position(machine, b), norm(b - a)});
  }
};

Artefact artefact(const VolumetricError& machine, bool xy_diagonals = true, int skip_x_from = -1) {
  Artefact art;
  for (int k = 1; k < kNodes; ++k) {
    const double s = k * kStep;
    if (skip_x_from < 0 || k < skip_x_from || k > skip_x_from + 2) art.add(machine, {0, 12.5, 5}, {s, 12.5, 5});
    art.add(machine, {12.5, 0, 5}, {12.5, s, 5});
    art.add(machine, {12.5, 12.5, 0}, {12.5, 12.5, s});
  }
  if (xy_diagonals) {
    art.add(machine, {0, 0, 5}, {25, 25, 5});
    art.add(machine, {0, 25, 5}, {25, 0, 5});
  }
  art.add(machine, {12.5, 0, 0}, {12.5, 25, 25});
  art.add(machine, {12.5, 0, 25}, {12.5, 25, 0});
  art.add(machine, {0, 12.5, 0}, {25, 12.5, 25});
  art.add(machine, {0, 12.5, 25}, {25, 12.5, 0});
  return art;
}

VolumetricError layout_of(const VolumetricError& m) {
  VolumetricError l;
  for (int a = 0; a < kAxes; ++a) {
    l.pitch[static_cast<std::size_t>(a)] = m.pitch[static_cast<std::size_t>(a)];
    l.pitch[static_cast<std::size_t>(a)].error_mm.fill(0.0);
  }
  return l;
}

TEST(VolumetricError, PitchTableInterpolatesAndHolds) {
  PitchTable t;
  t.start_mm = 5.0;
  t.step_mm = 2.0;
  t.count = 3;
  t.error_mm[0] = 1.0;
  t.error_mm[1] = 3.0;
  t.error_mm[2] = -1.0;
  EXPECT_DOUBLE_EQ(t.at(5.0), 1.0);
  EXPECT_DOUBLE_EQ(t.at(6.5), 1.0 + 0.75 * 2.0);
  EXPECT_DOUBLE_EQ(t.at(8.0), 1.0);
  EXPECT_DOUBLE_EQ(t.at(0.0), 1.0);   // held
  EXPECT_DOUBLE_EQ(t.at(20.0), -1.0);
  EXPECT_DOUBLE_EQ(PitchTable{}.at(3.0), 0.0);
}

TEST(VolumetricError, ForwardIsTheDocumentedFormula) {
  VolumetricError m = synthetic_machine(1);
  m.growth_per_K = {11.5e-6, 12e-6, 10e-6};
  m.temperature_offset_K = 2.0;
  m.origin_drift_mm = {0.001, -0.002, 0.003};
  const Vec3 p{7.3, 18.1, 3.9};
  const Vec3 e = volumetric_offset(m, p);
  // by hand: pitch by linear interpolation between the nodes around each coordinate
  auto pitch = [&](int a, double x) {
    const auto& t = m.pitch[static_cast<std::size_t>(a)];
    const int k = static_cast<int>(x / kStep);
    const double w = x / kStep - k;
    return (1 - w) * t.error_mm[static_cast<std::size_t>(k)] + w * t.error_mm[static_cast<std::size_t>(k + 1)];
  };
  EXPECT_NEAR(e[0], pitch(0, 7.3) + 11.5e-6 * 2 * 7.3 + 0.001 + 15e-6 * 3.9, 1e-15);
  EXPECT_NEAR(e[1], pitch(1, 18.1) + 12e-6 * 2 * 18.1 - 0.002 + 40e-6 * 7.3 - 25e-6 * 3.9, 1e-15);
  EXPECT_NEAR(e[2], pitch(2, 3.9) + 10e-6 * 2 * 3.9 + 0.003, 1e-15);
  EXPECT_EQ(actual_position(m, p), p + e);
}

TEST(VolumetricError, ForwardAndInverseAreInverse) {
  VolumetricError m = synthetic_machine(2);
  m.growth_per_K = {11.5e-6, 11.5e-6, 11.5e-6};
  m.temperature_offset_K = 3.0;
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> u(-2.0, 27.0);  // also outside the tables
  for (int i = 0; i < 500; ++i) {
    const Vec3 p{u(rng), u(rng), u(rng)};
    EXPECT_LT(norm(actual_position(m, nominal_position(m, p)) - p), 1e-11);
    EXPECT_LT(norm(nominal_position(m, actual_position(m, p)) - p), 1e-11);
  }
}

TEST(VolumetricError, InverseConvergesAtTheValidateLimits) {
  // every slope just inside validate's limits: a saw-tooth pitch of slope ±0.0099, squareness
  // 9999 µrad, growth × ΔT 0.0099 (E's max-norm Lipschitz constant just below 0.04)
  VolumetricError m;
  for (PitchTable& t : m.pitch) {
    t.step_mm = 2.5;
    t.count = 11;
    for (int k = 0; k < 11; ++k) t.error_mm[static_cast<std::size_t>(k)] = (k % 2) * 0.0099 * 2.5;
  }
  m.squareness_xy_urad = m.squareness_yz_urad = m.squareness_zx_urad = 9999.0;
  m.growth_per_K = {0.00099, 0.00099, 0.00099};
  m.temperature_offset_K = 10.0;
  ASSERT_EQ(validate(m), "");
  std::mt19937_64 rng(12);
  std::uniform_real_distribution<double> u(0.0, 25.0);
  for (int i = 0; i < 200; ++i) {
    const Vec3 p{u(rng), u(rng), u(rng)};
    EXPECT_LT(norm(actual_position(m, nominal_position(m, p)) - p), 1e-11);
  }
}

TEST(VolumetricError, CalibrationRecoversPitchAndSquareness) {
  const VolumetricError truth = synthetic_machine(3);
  const Artefact art = artefact(truth);
  const VolumetricCalibration cal = calibrate_volumetric(art.lengths, layout_of(truth));
  ASSERT_TRUE(cal.ok()) << cal.error;
  for (int a = 0; a < kAxes; ++a) {
    const auto& t = truth.pitch[static_cast<std::size_t>(a)].error_mm;
    const auto& got = cal.model.pitch[static_cast<std::size_t>(a)].error_mm;
    for (int k = 0; k < kNodes; ++k) EXPECT_NEAR(got[static_cast<std::size_t>(k)], t[static_cast<std::size_t>(k)] - t[0], 1e-9) << a << " " << k;
  }
  EXPECT_NEAR(cal.model.squareness_xy_urad, 40.0, 1e-4);
  EXPECT_NEAR(cal.model.squareness_yz_urad, -25.0, 1e-4);
  EXPECT_NEAR(cal.model.squareness_zx_urad, 15.0, 1e-4);
  EXPECT_GT(cal.rms_before, 1e-3);
  EXPECT_LT(cal.rms_after, 1e-9);
  // anywhere in the volume the calibrated model puts the machine where the truth does, up to
  // one constant vector (the pitch at node 0: no length sees it)
  const Vec3 shift = actual_position(truth, {0, 0, 0}) - actual_position(cal.model, {0, 0, 0});
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<double> u(0.0, 25.0);
  for (int i = 0; i < 200; ++i) {
    const Vec3 p{u(rng), u(rng), u(rng)};
    EXPECT_LT(norm(actual_position(truth, p) - actual_position(cal.model, p) - shift), 1e-8);
  }
}

TEST(VolumetricError, CalibrationWithNoiseStaysWithinItsError) {
  const VolumetricError truth = synthetic_machine(5);
  Artefact art = artefact(truth);
  std::mt19937_64 rng(6);
  const double sigma = 0.05e-3;
  std::normal_distribution<double> noise(0.0, sigma);
  for (LengthMeasurement& l : art.lengths) l.length_mm += noise(rng);
  const VolumetricCalibration cal = calibrate_volumetric(art.lengths, layout_of(truth));
  ASSERT_TRUE(cal.ok()) << cal.error;
  // each node from one length (σ); each squareness from two diagonals, each with its own noise
  // and the noise of the two pitch nodes at its ends (σ·sqrt(2) together), seen over a lever of
  // 0.707·25 mm: σ_S ≈ σ·sqrt(2)/17.7 mm/sqrt(2) = σ/17.7 mm; bound 4σ_S
  for (int a = 0; a < kAxes; ++a)
    for (int k = 1; k < kNodes; ++k) {
      const auto& t = truth.pitch[static_cast<std::size_t>(a)].error_mm;
      EXPECT_NEAR(cal.model.pitch[static_cast<std::size_t>(a)].error_mm[static_cast<std::size_t>(k)], t[static_cast<std::size_t>(k)] - t[0], 5 * sigma);
    }
  const double s_tol = 4.0 * sigma / (0.707 * 25.0) * 1e6;  // 11 µrad
  EXPECT_NEAR(cal.model.squareness_xy_urad, 40.0, s_tol);
  EXPECT_NEAR(cal.model.squareness_yz_urad, -25.0, s_tol);
  EXPECT_NEAR(cal.model.squareness_zx_urad, 15.0, s_tol);
}

TEST(VolumetricError, ValidateNamesTheField) {
  EXPECT_EQ(validate(synthetic_machine(1)), "");
  VolumetricError m = synthetic_machine(1);
  m.pitch[1].step_mm = 0.0;
  EXPECT_EQ(validate(m).rfind("pitch_y:", 0), 0u) << validate(m);
  m = synthetic_machine(1);
  m.pitch[2].error_mm[4] = 0.1;  // 0.1 mm over a 2.5 mm step: 4 %
  EXPECT_EQ(validate(m).rfind("pitch_z:", 0), 0u) << validate(m);
  m = synthetic_machine(1);
  m.squareness_zx_urad = std::nan("");
  EXPECT_EQ(validate(m).rfind("squareness:", 0), 0u) << validate(m);
  m = synthetic_machine(1);
  m.pitch[0].count = kMaxPitchNodes + 1;
  EXPECT_EQ(validate(m).rfind("pitch_x:", 0), 0u) << validate(m);
}

TEST(VolumetricError, RefusesArtefactsThatLeaveAParameterOpen) {
  const VolumetricError truth = synthetic_machine(7);
  const VolumetricCalibration no_xy = calibrate_volumetric(artefact(truth, false).lengths, layout_of(truth));
  EXPECT_FALSE(no_xy.ok());
  EXPECT_NE(no_xy.error.find("squareness_xy"), std::string::npos) << no_xy.error;
  const VolumetricCalibration gap = calibrate_volumetric(artefact(truth, true, 4).lengths, layout_of(truth));
  EXPECT_FALSE(gap.ok());
  EXPECT_NE(gap.error.find("pitch X node"), std::string::npos) << gap.error;
  EXPECT_FALSE(calibrate_volumetric({}, layout_of(truth)).ok());
}

}  // namespace
}  // namespace pcnc
