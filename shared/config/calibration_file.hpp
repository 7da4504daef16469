// calibration_file.hpp — the file `pcnc measure` writes its calibrations to and reads back
// with --calibration (docs/measurement.md, "The calibration file"): JSON, format
// "pcnc-measure-calibration" version 1, holding the probe's effective-radius table (the
// seed's Fig. 2, calibrated on the reference sphere) and the machine's volumetric error model
// (calibrated on the reference artefact), plus the figures of both fits for the record. The
// reader is strict: unknown keys, wrong types and a table or model that validate() refuses
// are errors naming the file and the key.
#pragma once

#include <string>
#include <string_view>

#include "config/config.hpp"
#include "geometry/probe_calibration.hpp"
#include "geometry/volumetric_error.hpp"

namespace pcnc {

struct MeasureCalibration {
  ProbeCalibration probe{};
  VolumetricError volumetric{};
  // the record (not used to compensate)
  int probe_touches = 0;
  double probe_rms_mm = 0.0, probe_max_mm = 0.0;
  Vec3 sphere_centre_mm{};
  double sphere_radius_mm = 0.0;
  int artefact_lengths = 0;
  double artefact_rms_before_mm = 0.0, artefact_rms_after_mm = 0.0;
  double artefact_max_before_mm = 0.0, artefact_max_after_mm = 0.0;
};

struct CalibrationFileError : ConfigError {
  using ConfigError::ConfigError;
};

/// Throws CalibrationFileError("<origin>: <why>").
MeasureCalibration parse_calibration_json(std::string_view text, const std::string& origin);
MeasureCalibration load_calibration_file(const std::string& path);
std::string calibration_json(const MeasureCalibration& c);
/// Written atomically; throws CalibrationFileError when it cannot be.
void save_calibration_file(const std::string& path, const MeasureCalibration& c);

}  // namespace pcnc
