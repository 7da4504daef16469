// biarc_tool.cpp — `pcnc biarc`: the command line around rewrite_biarcs. See biarc_tool.hpp.
#include "biarc_tool.hpp"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>

#include "config/exit_status.hpp"
#include "number_format.hpp"

namespace pcnc {
namespace {


}  // namespace

int run_biarc_tool(const BiarcToolOptions& o, std::ostream& out, std::ostream& err) {
  const BiarcRewriteOptions& r = o.rewrite;
  if (!(r.tolerance_mm >= 1e-6) || r.max_tool_radius_mm < 0.0 || r.min_moves < 2 || !(r.max_segment_mm > 0.0) ||
      !(r.max_turn_deg > 0.0)) {
    err << "pcnc biarc: --tolerance must be >= 0.000001 mm (the output's resolution), --max-segment and --max-turn > 0, "
           "--min-moves >= 2, --max-tool-radius >= 0\n";
    return kExitBadInput;
  }
  std::ifstream f(o.file, std::ios::binary);
  if (!f) {
    err << "pcnc biarc: cannot read '" << o.file << "'\n";
    return kExitBadInput;
  }
  std::stringstream ss;
  ss << f.rdbuf();
  BiarcRewriteOptions opt = r;
  opt.side = o.side == "left" ? 1 : o.side == "right" ? -1 : 0;
  BiarcRewriteReport rep;
  out << rewrite_biarcs(ss.str(), opt, rep);
  out.flush();

  int runs = 0, curves = 0, moves_in = 0, moves_out = 0, loops = 0;
  double dev_nurbs = 0, dev_points = 0, dev_segments = 0, sagitta = 0, change = 0;
  bool within = true;
  for (const BiarcRewriteItem& it : rep.items) {
    err << o.file << ":" << it.first_line << "-" << it.last_line << ": "
        << (it.spline_degree == 3 ? std::string("G5 spline")
            : it.spline_degree == 2 ? std::string("G5.1 spline")
            : it.nurbs ? std::string("NURBS") : std::to_string(it.moves_in) + " G1 moves")
        << " -> " << it.moves_out
        << " arcs, deviation " << format_number("%.6f", it.deviation_mm) << " mm";
    if (!it.nurbs)
      err << " (points), " << format_number("%.6f", it.segment_deviation_mm) << " mm from the segments (their sagitta "
          << format_number("%.6f", it.sagitta_mm) << ")";
    if (it.loops_removed > 0)
      err << "; " << it.loops_removed << " loop" << (it.loops_removed == 1 ? "" : "s") << " removed, contour moved up to "
          << format_number("%.4f", it.loop_change_mm) << " mm";
    if (it.unresolved > 0)
      err << "; warning: " << it.unresolved << " piece" << (it.unresolved == 1 ? "" : "s")
          << " this tool cannot follow left (a start cut off, or walls closer than its diameter; docs/biarc-fit.md)";
    if (!it.within_tolerance) err << "; NOT within the tolerance";
    err << "\n";
    (it.nurbs ? curves : runs) += 1;
    moves_in += it.moves_in;
    moves_out += it.moves_out;
    loops += it.loops_removed;
    (it.nurbs ? dev_nurbs : dev_points) = std::max(it.nurbs ? dev_nurbs : dev_points, it.deviation_mm);
    dev_segments = std::max(dev_segments, it.segment_deviation_mm);
    sagitta = std::max(sagitta, it.sagitta_mm);
    change = std::max(change, it.loop_change_mm);
    within = within && it.within_tolerance;
  }
  for (const std::string& n : rep.notes) err << o.file << ": " << n << "\n";
  err << "pcnc biarc: " << curves << " curve" << (curves == 1 ? "" : "s") << " (NURBS, G5, G5.1) and " << runs << " smooth G1 run"
      << (runs == 1 ? "" : "s") << " (" << moves_in << " blocks) rewritten as " << moves_out << " blocks; program "
      << rep.lines_in << " lines before, " << rep.lines_out << " after; tolerance " << format_number("%g", r.tolerance_mm) << " mm\n";
  err << "pcnc biarc: max deviation " << format_number("%.6f", dev_nurbs) << " mm from the curves (Newton), "
      << format_number("%.6f", dev_points) << " mm from the G1 points, " << format_number("%.6f", dev_segments)
      << " mm from the G1 segments (their own sagitta up to " << format_number("%.6f", sagitta) << " mm)\n";
  if (r.max_tool_radius_mm > 0.0)
    err << "pcnc biarc: tool radius " << format_number("%g", r.max_tool_radius_mm) << " mm: " << loops << " loop"
        << (loops == 1 ? "" : "s") << " removed, the contour moved up to " << format_number("%.4f", change) << " mm\n";
  if (!within) err << "pcnc biarc: warning: some pieces are not within the tolerance (see above)\n";
  return kExitOk;
}

void add_biarc_subcommand(CLI::App& app, int& exit_code) {
  auto opts = std::make_shared<BiarcToolOptions>();
  auto* sub = app.add_subcommand(
      "biarc",
      "rewrite NURBS (G5.2 ... G5.3), G5/G5.1 splines and smooth runs of short G1 moves as G2/G3 biarcs within a tolerance, so that "
      "cutter compensation (G41/G42, on any controller) offsets them exactly; the program goes to stdout, the "
      "figures to stderr. Every other line passes through unchanged; nothing is refused for machine reasons.");
  sub->add_option("FILE", opts->file, "G-code program")->required()->check(CLI::ExistingFile);
  sub->add_option("--tolerance", opts->rewrite.tolerance_mm, "maximum deviation of the arcs from the curve or the programmed points, mm")
      ->capture_default_str();
  sub->add_option("--max-tool-radius", opts->rewrite.max_tool_radius_mm,
                  "remove the loops a tool of this radius (mm) would tangle on (the contour is offset by it, cut at the "
                  "offset's self-intersections and offset back); without it nothing is removed");
  sub->add_option("--side", opts->side,
                  "side of the tool for --max-tool-radius: auto (the program's G41/G42 where active, else both), "
                  "left (G41), right (G42), both")
      ->check(CLI::IsMember({"auto", "left", "right", "both"}))
      ->capture_default_str();
  sub->add_option("--min-moves", opts->rewrite.min_moves, "a smooth G1 run has at least this many moves")->capture_default_str();
  sub->add_option("--max-segment", opts->rewrite.max_segment_mm, "each move of a smooth G1 run is shorter than this, mm")
      ->capture_default_str();
  sub->add_option("--max-turn", opts->rewrite.max_turn_deg, "a smooth G1 run turns by less than this at each junction, degrees")
      ->capture_default_str();
  sub->callback([opts, &exit_code] { exit_code = run_biarc_tool(*opts, std::cout, std::cerr); });
}

}  // namespace pcnc
