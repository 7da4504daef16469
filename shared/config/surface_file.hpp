// surface_file.hpp — the surface file: a B-spline surface (geometry/bspline_surface.hpp) as
// JSON a person can read, written by `pcnc surface fit`, read by `pcnc run/check/serve
// --surface` (the surface-correction stage) and, for the simulated workpiece of issue 15, by
// the machine's config. It lives here, not in geometry/ (pure mathematics, no I/O) nor in
// host/ (the rt may not include host/): config/ is the room both processes and the tools read
// files through. Format (docs/surface.md):
//
//   {"format": "pcnc-bspline-surface", "version": 1, "units": "mm", "degree": 3, "e": 0.5,
//    "knots_u": [0, 0, 0, 0, ..., 1, 1, 1, 1], "knots_v": [...],
//    "control_points": [[[x, y, z], ... count_u], ... count_v rows]}
//
// Reading is strict: every key is required and no other is accepted, every number finite,
// the sizes consistent (knots = control points + degree + 1, every row as long as the first)
// and the knots clamped and non-decreasing. A refusal is a SurfaceFileError whose message
// names the file and the key.
//
// May include: the standard library, POSIX, nlohmann/json, config.hpp, atomic_file.hpp, geometry/.
#pragma once

#include <string>
#include <string_view>

#include "config/config.hpp"
#include "geometry/bspline_surface.hpp"

namespace pcnc {

constexpr int kSurfaceFileVersion = 1;

struct SurfaceFileError : ConfigError {
  using ConfigError::ConfigError;
};

/// The surface in `text`; `origin` (the file's name) starts every message.
BSplineSurface parse_surface_json(std::string_view text, const std::string& origin);
/// Reads and parses `path` (a regular file of at most 64 MB).
BSplineSurface load_surface_file(const std::string& path);
/// The file's text (numbers with 17 significant digits: a round trip is exact).
std::string surface_json(const BSplineSurface& s);
/// Writes the file atomically; throws SurfaceFileError naming the file on failure.
void save_surface_file(const std::string& path, const BSplineSurface& s);

}  // namespace pcnc
