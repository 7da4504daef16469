// nurbs_tool.cpp — `pcnc nurbs`: rough interpolation of a program's NURBS curves, as the seed
// paper does it, against the direct NURBS block. See nurbs_tool.hpp.
#include "nurbs_tool.hpp"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <iostream>
#include <ostream>

#include "config/config.hpp"
#include "number_format.hpp"
#include "geometry/nurbs.hpp"
#include "ipc/block_nurbs.hpp"
#include "gcode/nurbs_reader.hpp"
#include "gcode/nurbs_rough.hpp"

namespace pcnc {
namespace {


}  // namespace

int run_nurbs_rough(const NurbsToolOptions& o, std::ostream& out, std::ostream& err) {
  MachineConfig cfg;
  try {
    cfg = load_config(o.config_path.empty() ? default_config_path() : o.config_path);
  } catch (const ConfigError& e) {
    for (const auto& p : e.problems) err << "pcnc nurbs: " << p << "\n";
    return 2;
  }
  const double tol = o.tolerance_mm >= 0.0 ? o.tolerance_mm : cfg.gcode.nurbs_chord_tolerance_mm;
  if (!(tol > 0.0) || !(o.period_s > 0.0)) {
    err << "pcnc nurbs: --tolerance and --period must be > 0\n";
    return 2;
  }
  KnotRule rule = cfg.gcode.nurbs_knots == 1 ? KnotRule::kChordLength : KnotRule::kOpenUniform;
  if (o.knots == "open") rule = KnotRule::kOpenUniform;
  if (o.knots == "chord") rule = KnotRule::kChordLength;

  const NurbsProgram prog = read_nurbs_program(o.file, rule);
  if (!prog.error.empty()) {
    err << o.file << ": " << prog.error << "\n";
    return 2;
  }
  if (prog.curves.empty()) {
    err << o.file << ": no G5.2 ... G5.3 NURBS curve in the program\n";
    return 2;
  }
  std::size_t total_rough = 0, total_cam = 0, total_blocks = 0;
  int index = 0;
  for (const ProgramCurve& pc : prog.curves) {
    ++index;
    const NurbsCurve& c = pc.curve;
    const double feed_mm_s = o.feed_mm_min >= 0.0 ? o.feed_mm_min / 60.0 : pc.feed_mm_s;
    const double length = nurbs_arc_length(c.view(), c.u_min(), c.u_max());
    out << "curve " << index << " (line " << pc.line << "): order " << c.degree + 1 << ", " << c.points.size()
        << " control points, " << (rule == KnotRule::kChordLength ? "chord-length" : "open uniform") << " knots [";
    for (std::size_t i = 0; i < c.knots.size(); ++i) out << (i ? " " : "") << format_number("%g", c.knots[i]);
    out << "], length " << format_number("%.4f", length) << " mm\n";
    if (!(feed_mm_s > 0.0)) {
      err << o.file << ":" << pc.line << ": no feed for this curve; give F in the program or --feed\n";
      return 2;
    }
    const double step = feed_mm_s * o.period_s;
    const RoughPolyline rough = rough_interpolate(c, step, tol);
    // Bisection alone (one step over the whole curve): the fewest G01 blocks of this method.
    const RoughPolyline cam = rough_interpolate(c, 2.0 * length + 1.0, tol);
    const std::size_t blocks = split_for_blocks(c).size();
    out << "  feed " << format_number("%g", feed_mm_s * 60.0) << " mm/min: rough step " << format_number("%.6g", step) << " mm ("
        << format_number("%g", o.period_s * 1000.0) << " ms per rough sample), tolerance " << format_number("%g", tol) << " mm\n";
    out << "  rough interpolation: " << rough.segments << " segments (" << rough.bisections
        << " bisections), max deviation " << format_number("%.3e", rough.max_deviation_mm) << " mm\n";
    out << "  bisection alone (a CAM polyline within the tolerance): " << cam.segments << " G01 segments, max deviation "
        << format_number("%.3e", cam.max_deviation_mm) << " mm\n";
    out << "  direct NURBS: 1 G5.2 block (" << blocks << " ring block" << (blocks == 1 ? "" : "s") << ") instead of "
        << cam.segments << " G01 blocks\n";
    if (o.print_points) {
      for (std::size_t i = 0; i < rough.points.size(); ++i) {
        const Vec3& p = rough.points[i];
        out << "    " << format_number("%.6f", rough.params[i]) << " X" << format_number("%.6f", p[0]) << " Y" << format_number("%.6f", p[1]) << " Z"
            << format_number("%.6f", p[2]) << "\n";
      }
    }
    total_rough += rough.segments;
    total_cam += cam.segments;
    total_blocks += blocks;
  }
  out << "total: " << prog.curves.size() << " NURBS curve" << (prog.curves.size() == 1 ? "" : "s") << ", "
      << total_rough << " rough segments, " << total_cam << " G01 blocks within " << format_number("%g", tol) << " mm vs "
      << total_blocks << " NURBS ring blocks\n";
  return 0;
}

void add_nurbs_subcommand(CLI::App& app, int& exit_code) {
  auto opts = std::make_shared<NurbsToolOptions>();
  auto* sub = app.add_subcommand("nurbs", "rough interpolation of a program's G5.2 NURBS curves (the seed's comparison)");
  sub->add_option("FILE", opts->file, "G-code program with G5.2 ... G5.3 curves")->required()->check(CLI::ExistingFile);
  sub->add_option("--tolerance", opts->tolerance_mm, "chord tolerance delta, mm (default: the config's)");
  sub->add_option("--feed", opts->feed_mm_min, "feed, mm/min (default: the program's F)");
  sub->add_option("--period", opts->period_s, "rough sampling period, s")->capture_default_str();
  sub->add_option("--knots", opts->knots, "knot vector when the program gives none (default: the config's)")
      ->check(CLI::IsMember({"open", "chord"}));
  sub->add_option("--config", opts->config_path, "machine configuration (TOML)");
  sub->add_flag("--points", opts->print_points, "print the polyline vertices (u X Y Z)");
  sub->callback([opts, &exit_code] { exit_code = run_nurbs_rough(*opts, std::cout, std::cerr); });
}

}  // namespace pcnc
