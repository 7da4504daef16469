// surface_page.hpp — the HTML page of `pcnc surface fit --report`: the fit's figures and a
// coloured map of the fitted surface's distance to the design surface (or, without a design,
// of its height) over X/Y, with the probed points, as inline SVG. One self-contained file:
// nothing from the network, no script.
#pragma once

#include <string>
#include <vector>

#include "geometry/vec3.hpp"

namespace pcnc {

struct SurfacePage {
  std::string title;                            // e.g. the points file
  std::vector<std::pair<std::string, std::string>> figures;  // label, value (already formatted)
  std::string map_label;                        // what the colours show, with its unit
  int nx = 0, ny = 0;                           // the map's cells
  double x0 = 0, x1 = 0, y0 = 0, y1 = 0;        // its X/Y extent, mm
  std::vector<double> values;                   // ny rows of nx, row 0 at y0, in µm
  std::vector<Vec3> probes;                     // the measured points (X/Y drawn)
};

std::string surface_page_html(const SurfacePage& page);

}  // namespace pcnc
