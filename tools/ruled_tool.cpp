// ruled_tool.cpp — `pcnc ruled`: the command line around plan_passes and the ruled-surface
// G-code writer. See ruled_tool.hpp.
#include "ruled_tool.hpp"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <memory>

#include "config/atomic_file.hpp"
#include "config/config.hpp"
#include "config/exit_status.hpp"
#include "config/output_path.hpp"
#include "config/joint_map.hpp"
#include "config/surface_file.hpp"
#include "gcode/tcp_fit_travel.hpp"
#include "geometry/tcp_fit.hpp"
#include "geometry/ruled_motion.hpp"
#include "geometry/ruled_passes.hpp"
#include "geometry/ruled_surface.hpp"
#include "number_format.hpp"
#include "gcode/ruled_json_input.hpp"
#include "gcode/ruled_program.hpp"

namespace pcnc {
namespace {

std::string fmt(const char* f, double v) { return format_number(f, v); }
std::string vec(const Vec3& v, const char* f = "%.4f") { return fmt(f, v[0]) + ", " + fmt(f, v[1]) + ", " + fmt(f, v[2]); }

// The seed's Tables 1-2 at one u of a pass: frame, ds/du, first- and second-order positional
// and angular variation per unit u in the frame's components; then the motion in time at F.
void print_sample(std::ostream& out, const RuledModel& model, double u, double feed_mm_s, int index) {
  const RuledCurves c = model.curves();
  const RuledJet j = ruled_jet(c, u);
  const RuledInvariants k = ruled_invariants(j);
  const ToolMotion m = tool_motion(j, u, feed_mm_s, 0.0);
  out << "  sample " << index << ": u " << fmt("%.4f", u) << ", tool at (" << vec(m.position, "%.3f") << "), ds/du "
      << fmt("%.4f", k.ds_du) << (k.regular ? "" : " (the ruling stands still: the frame is the tool's A, O, N)") << "\n";
  const Vec3 fr[3] = {k.regular ? k.t : m.O, k.e, k.regular ? k.g : m.N};
  const char* nm[3] = {"O", "A", "N"};
  for (int r = 0; r < 3; ++r)
    out << "    " << nm[r] << "  frame " << fmt("%8.4f", fr[r][0]) << " " << fmt("%8.4f", fr[r][1]) << " "
        << fmt("%8.4f", fr[r][2]) << " | position 1st " << fmt("%9.4f", dot(j.c.d1, fr[r])) << " 2nd "
        << fmt("%9.4f", dot(j.c.d2, fr[r])) << " | angular 1st " << fmt("%8.4f", dot(m.omega_u, fr[r])) << " 2nd "
        << fmt("%8.4f", dot(m.omega_uu, fr[r])) << "\n";
  out << "    at F: |v| " << fmt("%.4f", norm(m.velocity)) << " mm/s, |a| " << fmt("%.4f", norm(m.acceleration))
      << " mm/s^2, |omega| " << fmt("%.5f", norm(m.omega)) << " rad/s, |alpha| " << fmt("%.5f", norm(m.alpha))
      << " rad/s^2, |dA/dt| " << fmt("%.5f", norm(m.axis_velocity)) << " 1/s\n";
}

// The part's top, sampled on a 129 x 129 grid of parameters (the control net's top can be higher).
double surface_top(const BSplineSurface& surface) {
  double top = -1e300;
  for (int i = 0; i <= 128; ++i)
    for (int k = 0; k <= 128; ++k)
      top = std::max(top, surface_point(surface, surface.u_min() + (surface.u_max() - surface.u_min()) * i / 128.0,
                                        surface.v_min() + (surface.v_max() - surface.v_min()) * k / 128.0)[2]);
  return top;
}

// The tool poses the example's program reaches, in order (program coordinates): over the first
// set point at the clearance, every set point of every pass (the links between them), over the
// last at the clearance; the axis of the nearest set point.
std::vector<FitPose> program_poses(const PassPlan& plan, double clearance) {
  std::vector<FitPose> poses;
  auto add = [&poses](const Vec3& tip, const Vec3& axis) {
    FitPose f;
    f.pose.tip = tip;
    f.pose.axis = axis;
    poses.push_back(f);
  };
  const PassPoint& first = plan.passes.front().points.front();
  const PassPoint& last = plan.passes.back().points.back();
  add({first.tip[0], first.tip[1], clearance}, first.axis);
  for (const Pass& p : plan.passes)
    for (const PassPoint& q : p.points) add(q.tip, q.axis);
  add({last.tip[0], last.tip[1], clearance}, last.axis);
  return poses;
}

}  // namespace

int run_ruled_tool(const RuledToolOptions& o, std::ostream& out, std::ostream& err) {
  if (!(o.tool_radius > 0.0) || !(o.cusp > 0.0) || o.cusp > o.tool_radius || !(o.feed > 0.0) ||
      !(o.point_spacing > 0.0) || o.samples < 0 || !(std::abs(o.lead_deg) < 80.0)) {
    err << "pcnc ruled: --tool-radius must be > 0, --cusp in (0, R], --feed and --point-spacing > 0, --samples >= 0, "
           "|--lead| < 80 degrees\n";
    return kExitBadInput;
  }
  const std::string config_path = o.config_path.empty() ? default_config_path() : o.config_path;
  MachineConfig cfg;
  try {
    cfg = load_config(config_path);
    check_output_paths({{o.output, "-o"}, {o.json, "--json"}});
  } catch (const ConfigError& e) {
    for (const auto& p : e.problems) err << "pcnc ruled: " << p << "\n";
    return kExitBadInput;
  } catch (const std::exception& e) {
    err << "pcnc ruled: " << e.what() << "\n";
    return kExitBadInput;
  }

  // The surface in program coordinates.
  BSplineSurface surface;
  std::string what;
  double surface_size = 0.0;  // the example's size and origin (program coordinates)
  Vec3 surface_origin{};
  if (o.surface.empty()) {
    // The seed's 200 x 200 x 20 mm example scaled to the X/Y travel, centred on it in program
    // coordinates (program = machine - G54), its top 2 mm below the top of the Z travel.
    const Vec3 lo = cfg.travel_min(), hi = cfg.travel_max(), g54 = cfg.gcode.work_offsets[0];
    const double size = std::min(hi[0] - lo[0], hi[1] - lo[1]);
    const double height = size / 10.0;
    const Vec3 origin{0.5 * (lo[0] + hi[0]) - g54[0] - 0.5 * size, 0.5 * (lo[1] + hi[1]) - g54[1] - 0.5 * size,
                      hi[2] - g54[2] - 2.0 - height};
    surface = example_surface(size, origin);
    surface_size = size;
    surface_origin = origin;
    what = "the seed's example surface, " + fmt("%.3f", size) + " x " + fmt("%.3f", size) + " mm, height " +
           fmt("%.3f", height) + " mm (200 x 200 x 20 mm scaled by " + fmt("%g", size / 200.0) + " to the X/Y travel of " +
           config_path + ")";
  } else {
    try {
      surface = load_surface_file(o.surface);
    } catch (const std::exception& e) {
      err << "pcnc ruled: " << e.what() << "\n";
      return kExitBadInput;
    }
    what = "the surface " + o.surface + " (degree " + std::to_string(surface.degree) + ", " +
           std::to_string(surface.count_u) + " x " + std::to_string(surface.count_v) + " control points)";
  }
  double top = surface_top(surface);
  double clearance = top + 2.0;

  PassOptions po;
  po.tool_radius = o.tool_radius;
  po.cusp_height = o.cusp;
  po.point_spacing = o.point_spacing;
  po.lead_angle = o.lead_deg * M_PI / 180.0;
  PassPlan plan = plan_passes(part_surface(surface), po);
  if (!plan.error.empty()) {
    err << "pcnc ruled: " << plan.error << "\n";
    return kExitBadInput;
  }

  // On a 5-axis machine the tool tilt moves the linear joints (a table-tilting machine turns
  // the part), so the example scaled to the X/Y travel can leave it: scale and move it (the
  // surface, about program zero, then the offset) until every joint at every set point and at
  // the clearance above the first and last, and along the straight moves between them, is
  // inside its travel less kFitMarginMm (the tool-centre-point --fit, tcp_fit.hpp, tool length
  // 0); then plan the passes again on it. The clearance scales with it.
  const bool five_axis = cfg.kinematics.kind != KinematicsKind::kTrivial;
  constexpr double kFitMarginMm = 0.5;
  std::string fit_line;
  if (five_axis && o.surface.empty()) {
    JointTravel travel = joint_travel(cfg);
    travel.min = travel.min + Vec3{kFitMarginMm, kFitMarginMm, kFitMarginMm};
    travel.max = travel.max - Vec3{kFitMarginMm, kFitMarginMm, kFitMarginMm};
    const TcpFitResult fit = fit_tcp_program(program_poses(plan, clearance), kinematics_with_tool(cfg, 0.0), travel,
                                             home_joints(cfg), 2, 1e-6);
    if (!fit.ok) {
      err << "pcnc ruled: the example does not fit the joints' travel of " << config_path << ": " << fit.error << "\n";
      return kExitBadInput;
    }
    const Vec3 g54 = cfg.gcode.work_offsets[0];
    const double size = surface_size * fit.scale;
    surface_origin = surface_origin * fit.scale + fit.offset - g54;
    surface = example_surface(size, surface_origin);
    top = surface_top(surface);
    clearance = clearance * fit.scale + fit.offset[2] - g54[2];
    what = "the seed's example surface, " + fmt("%.3f", size) + " x " + fmt("%.3f", size) + " mm, height " +
           fmt("%.3f", size / 10.0) + " mm (200 x 200 x 20 mm scaled by " + fmt("%.6g", size / 200.0) +
           " so that every joint stays " + fmt("%g", kFitMarginMm) + " mm inside the travel of " + config_path + ")";
    fit_line = "scale " + fmt("%.6f", fit.scale) + " of the X/Y travel's " + fmt("%.3f", surface_size) + " mm, origin (" +
               vec(surface_origin, "%.4f") + ") mm in program coordinates";
    plan = plan_passes(part_surface(surface), po);
    if (!plan.error.empty()) {
      err << "pcnc ruled: " << plan.error << "\n";
      return kExitBadInput;
    }
  }
  const PartSurface part = part_surface(surface);

  // The pieces: approach (down from the clearance), the passes, the links between them (along
  // the edge), the retract. On a 5-axis machine the joints turn to the first set point's axis
  // first, with TCP off, and the approach and retract keep the axis of the pass they lead to or
  // from (never leaving the pole of C under TCP); on a 3-axis machine they turn it from and back
  // to vertical.
  const Vec3 up{0, 0, 1};
  std::vector<RuledPiece> pieces;
  const PassPoint& first = plan.passes.front().points.front();
  pieces.push_back({{{first.tip[0], first.tip[1], clearance}, first.tip}, {five_axis ? first.axis : up, first.axis}, "approach"});
  ModelError model_err;
  for (const Pass& p : plan.passes) {
    const ModelError e = pass_model_error(part, p, po, 8);
    model_err.tip = std::max(model_err.tip, e.tip);
    model_err.axis = std::max(model_err.axis, e.axis);
  }
  double pass_length = 0.0, link_length = 0.0;
  std::size_t set_points = 0;
  double widest = 0.0;
  for (std::size_t k = 0; k < plan.passes.size(); ++k) {
    const Pass& p = plan.passes[k];
    RuledPiece piece;
    piece.comment = "pass " + std::to_string(k + 1);
    for (const PassPoint& q : p.points) {
      piece.points.push_back(q.tip);
      piece.axes.push_back(q.axis);
    }
    pieces.push_back(std::move(piece));
    pass_length += p.length;
    set_points += p.points.size();
    widest = std::max(widest, p.gap_to_next);
    if (k + 1 < plan.passes.size()) {
      const PassPoint& a = p.points.back();
      const PassPoint& b = plan.passes[k + 1].points.front();
      pieces.push_back({{a.tip, b.tip}, {a.axis, b.axis}, "link"});
      link_length += norm(b.tip - a.tip);
    }
  }
  const PassPoint& last = plan.passes.back().points.back();
  pieces.push_back({{last.tip, {last.tip[0], last.tip[1], clearance}}, {last.axis, five_axis ? last.axis : up}, "retract"});
  const double approach = (clearance - first.tip[2]) + (clearance - last.tip[2]);

  RuledProgramOptions ro;
  ro.feed_mm_min = o.feed;
  ro.clearance_z = clearance;
  if (five_axis) {  // the joints at the first set point's axis, nearest home (the rt starts there)
    const RuledTurnWords words = ruled_turn_words(cfg, first.tip + cfg.gcode.work_offsets[0], first.axis);
    ro.turn_joints = words.turn;
    ro.turn_back = words.back;
  }
  ro.header = {"pcnc ruled: ruled-surface passes (G5.4 ... G5.5, docs/ruled-surface.md)",
               "surface: " + what,
               "ball-end R " + fmt("%g", o.tool_radius) + " mm, cusp " + fmt("%g", o.cusp) + " mm, pass interval " +
                   fmt("%.6f", plan.interval) + " mm, " + std::to_string(plan.passes.size()) + " passes, lead " +
                   fmt("%g", o.lead_deg) + " deg",
               "X Y Z: tool tip (ball centre - R * axis), workpiece coordinates, mm; I J K: unit tool axis, tip to spindle"};
  const std::vector<std::string> lines = ruled_program_lines(pieces, ro);
  std::string text;
  for (const std::string& l : lines) text += l + "\n";
  std::string werr;
  if (!write_file_atomically(o.output, text, &werr)) {
    err << "pcnc ruled: " << werr << "\n";
    return kExitBadInput;
  }
  if (!o.json.empty() && !write_file_atomically(o.json, ruled_program_json(pieces, o.feed), &werr)) {
    err << "pcnc ruled: " << werr << "\n";
    return kExitBadInput;
  }

  const double total = pass_length + link_length + approach;
  out << "pcnc ruled: " << what << "\n";
  if (!fit_line.empty()) out << "  fitted            " << fit_line << "\n";
  out << "  tool              ball-end R " << fmt("%g", o.tool_radius) << " mm, cusp height " << fmt("%g", o.cusp)
      << " mm, lead " << fmt("%g", o.lead_deg) << " deg\n";
  out << "  pass interval     P " << fmt("%.6f", plan.interval) << " mm (2 sqrt(h (2R - h)))\n";
  out << "  passes            " << plan.passes.size() << " at constant u, widest gap " << fmt("%.6f", widest) << " mm\n";
  out << "  set points        " << set_points << " (" << fmt("%g", o.point_spacing) << " mm apart or less along a pass)\n";
  out << "  ruled model       tip within " << fmt("%.4f", model_err.tip * 1e3) << " um of the exact tip path, axis within "
      << fmt("%.2f", model_err.axis * 1e6) << " urad of the exact axis (8 samples per segment, every pass)\n";
  out << "  pieces            " << pieces.size() << " G5.4 groups (approach, " << plan.passes.size() << " passes, "
      << plan.passes.size() - 1 << " links, retract)\n";
  out << "  path length       " << fmt("%.3f", total) << " mm (passes " << fmt("%.3f", pass_length) << ", links "
      << fmt("%.3f", link_length) << ", approach and retract " << fmt("%.3f", approach) << ")\n";
  out << "  feed time         " << fmt("%.3f", total / (o.feed / 60.0)) << " s at F" << fmt("%g", o.feed)
      << " (path length over feed; the machine time: pcnc run, or bench_ruled_machine)\n";
  out << "  program           " << o.output << ", " << lines.size() << " lines" << (o.json.empty() ? "" : ", " + o.json)
      << "\n";
  if (o.samples > 0) {
    const Pass& p = plan.passes.front();
    const double umax = p.model.curves().u_max();
    out << "Tables 1-2 (the seed's form), pass 1, " << o.samples << " samples evenly over u in [0, " << fmt("%g", umax)
        << "] (one Ferguson segment per unit of u): the frame is the generator trihedron (O = t, A = e, N = g), "
           "positional variation c_u, c_uu (mm) and angular omega_u, omega_uu (rad) per unit u in its components\n";
    for (int i = 0; i < o.samples; ++i)
      print_sample(out, p.model, o.samples == 1 ? 0.0 : umax * i / (o.samples - 1), o.feed / 60.0, i + 1);
  }
  return kExitOk;
}

void add_ruled_subcommand(CLI::App& app, int& exit_code) {
  auto opts = std::make_shared<RuledToolOptions>();
  auto* sub = app.add_subcommand(
      "ruled",
      "plan the passes of a ball-end mill over a surface as ruled-surface pieces (tool tip and tool axis, the seed's "
      "5-axis method) and write them as G5.4 ... G5.5 groups (docs/ruled-surface.md); without SURFACE the seed's "
      "example (200 x 200 mm, 20 mm high) scaled to the config's X/Y travel. Prints the pass interval, the passes, "
      "the path length and the seed's Tables 1-2 (tool frame, ds/du, first- and second-order motion) for --samples "
      "points of the first pass. On a 5-axis config the example is scaled so that every joint (after the inverse "
      "kinematics) stays inside its travel, and the program turns the joints to the first tool axis with TCP off "
      "before M428; pcnc check/run run it (docs/ruled-surface.md).");
  sub->add_option("SURFACE", opts->surface, "a B-spline surface file (docs/surface.md), in program coordinates")
      ->check(CLI::ExistingFile);
  sub->add_option("-o,--output", opts->output, "the program to write (.ngc)")->required();
  sub->add_option("--json", opts->json, "also write the pieces as JSON (the file form, .json): pcnc check/run run it as they run the G-code form, with the same preamble made from their config");
  sub->add_option("--tool-radius", opts->tool_radius, "ball-end radius R, mm")->capture_default_str();
  sub->add_option("--cusp", opts->cusp, "cusp (scallop) height h between passes, mm")->capture_default_str();
  sub->add_option("--config", opts->config_path, "machine configuration (TOML); its X/Y travel sizes the example");
  sub->add_option("--feed", opts->feed, "feed of the tool tip, mm/min")->capture_default_str();
  sub->add_option("--lead", opts->lead_deg, "lead angle, degrees: the axis tilted from the normal toward the travel")
      ->capture_default_str();
  sub->add_option("--point-spacing", opts->point_spacing, "set points along a pass at most this far apart, mm")
      ->capture_default_str();
  sub->add_option("--samples", opts->samples, "rows of Tables 1-2, evenly over the first pass (0: none)")
      ->capture_default_str();
  sub->callback([opts, &exit_code] { exit_code = run_ruled_tool(*opts, std::cout, std::cerr); });
}

}  // namespace pcnc
