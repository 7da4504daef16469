// nurbs_tool.hpp — `pcnc nurbs FILE --tolerance d [--feed F]`: the seed paper's comparison.
//
// For every G5.2 ... G5.3 curve in FILE it prints the rough interpolation of the seed design
// (steps of the feed per rough sample, bisected where the chord error exceeds d): the
// polyline's segment count and its maximum deviation measured against a dense evaluation of
// the curve; also the polyline made by bisection alone (what a CAM system would send as G01
// blocks within d) and how many ring blocks the direct NURBS move needs instead.
#pragma once

#include <iosfwd>
#include <string>

namespace CLI {
class App;
}

namespace pcnc {

struct NurbsToolOptions {
  std::string file;
  std::string config_path;     // empty: default_config_path()
  double tolerance_mm = -1.0;  // < 0: the config's gcode.nurbs_chord_tolerance_mm
  double feed_mm_min = -1.0;   // < 0: the program's F
  double period_s = 0.005;     // rough sampling period (the seed's NCK ran it every 5 ms)
  std::string knots;           // "open" | "chord" | empty: the config's gcode.nurbs_knots
  bool print_points = false;   // also print the polyline vertices
};

/// Exit status: 0 done, 1 the program has an error, 2 bad options or config.
int run_nurbs_rough(const NurbsToolOptions& options, std::ostream& out, std::ostream& err);

/// Registers the `nurbs` subcommand on `app`; its callback stores the exit status.
void add_nurbs_subcommand(CLI::App& app, int& exit_code);

}  // namespace pcnc
