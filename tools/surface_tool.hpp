// surface_tool.hpp — `pcnc surface fit POINTS.csv -o S.json [--degree 3] [--e E] [--fair]
// [--design DESIGN.json | --design-plane Z] [--report R.html]`: the seed paper's measured
// surface (issue 15, item 4). Reads the measured grid (config/point_grid_csv.hpp), fits the
// interpolating B-spline surface (geometry/surface_fit.hpp), fairs it when asked, writes the
// surface file (config/surface_file.hpp) and prints e, F before and after fairing and, with a
// design surface, the fitted surface's distance to it; --report writes the HTML page with the
// coloured error map (report/surface_page.hpp).
#pragma once

#include <iosfwd>
#include <optional>
#include <string>

namespace CLI {
class App;
}

namespace pcnc {

struct SurfaceFitOptions {
  std::string points;                  // the grid CSV
  std::string output;                  // -o S.json
  int degree = 3;
  double e = 1.0;                      // the exponent without --fair (1: chord length)
  bool fair = false;
  std::string design;                  // a design surface file
  std::optional<double> design_plane;  // ... or the plane z = Z
  std::string report;                  // --report R.html
};

/// Exit status: 0 written, 2 bad input or command line (the message on `err` names the file).
int run_surface_fit(const SurfaceFitOptions& options, std::ostream& out, std::ostream& err);

/// Registers `surface` with its subcommand `fit`; the callback stores the exit status.
void add_surface_subcommand(CLI::App& app, int& exit_code);

}  // namespace pcnc
