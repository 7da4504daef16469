// point_grid_csv.hpp — the measured grid as CSV, the form `pcnc measure` writes and
// `pcnc surface fit` reads (docs/surface.md): a header line `x,y,z`, then one point a row in
// machine millimetres; the grid in rows of (nominally) constant y, y increasing, x increasing
// within a row. A row ends where x stops increasing; the grid's size follows from the rows.
// Measured points need not share exact coordinates (a probe's ball correction moves them).
//
// Reading is strict and every refusal names FILE:LINE:COLUMN: the header, three finite
// numbers a row, every row as long as the first, the rows' mean y increasing.
//
// May include: the standard library, geometry/.
#pragma once

#include <stdexcept>
#include <string>
#include <string_view>

#include "geometry/surface_fit.hpp"

namespace pcnc {

struct PointGridError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// The grid in `text`; `origin` (the file's name) starts every message.
PointGrid parse_point_grid_csv(std::string_view text, const std::string& origin);
/// Reads `path` (a regular file of at most 64 MB) and parses it.
PointGrid load_point_grid_csv(const std::string& path);
/// The CSV text of a grid (17 significant digits).
std::string point_grid_csv(const PointGrid& g);

}  // namespace pcnc
