// ruled_tool.hpp — `pcnc ruled [SURFACE] [--tool-radius R] [--cusp H] [--config F] [--feed F]
// -o OUT.ngc`: plans the passes of a ball-end mill over a part surface (the seed's example
// scaled to the config's X/Y travel, or a B-spline surface file) as ruled-surface pieces
// (geometry/ruled_passes.hpp), writes them in the G5.4 ... G5.5 form (gcode/ruled_program.hpp) and
// prints the plan's figures and the seed's Tables 1-2 for chosen samples (docs/ruled-surface.md).
#pragma once

#include <iosfwd>
#include <string>

namespace CLI {
class App;
}

namespace pcnc {

struct RuledToolOptions {
  std::string surface;      // a surface file (docs/surface.md); empty: the seed's example
  std::string config_path;  // empty: the default config
  std::string output;       // the program
  std::string json;         // optional: the same pieces as JSON
  double tool_radius = 1.0;   // mm
  double cusp = 0.005;        // mm
  double feed = 600.0;        // mm/min
  double lead_deg = 0.0;      // the axis tilted toward the travel
  double point_spacing = 1.0; // mm between set points along a pass
  int samples = 6;            // Tables 1-2 rows from the first pass
};

/// Exit status: 0 written, 2 bad options, config, surface or output path.
int run_ruled_tool(const RuledToolOptions& options, std::ostream& out, std::ostream& err);

/// Registers the `ruled` subcommand on `app`; its callback stores the exit status.
void add_ruled_subcommand(CLI::App& app, int& exit_code);

}  // namespace pcnc
