// surface_tool.cpp — `pcnc surface fit` (see surface_tool.hpp).
#include "surface_tool.hpp"

#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>

#include "config/exit_status.hpp"
#include "config/output_path.hpp"
#include "config/point_grid_csv.hpp"
#include "config/surface_file.hpp"
#include "geometry/surface_fit.hpp"
#include "report/report_html.hpp"  // fixed()
#include "report/surface_page.hpp"

namespace pcnc {
namespace {

// Six significant digits (F spans many decades).
std::string sig(double v) {
  std::ostringstream o;
  o.precision(6);
  o << v;
  return o.str();
}

std::string signed_percent(double v) { return (v >= 0 ? "+" : "") + fixed(v, 2); }

struct Distance {
  double mean = 0, std = 0, max_abs = 0;
  int samples = 0;
};

// Fitted minus design height (Z), over an n x n grid of X/Y inside the grid's footprint.
template <class Design>
Distance distance(const BSplineSurface& s, const Design& design, int n = 101) {
  Distance d;
  double sum = 0, sq = 0;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const Vec3 p = surface_point(s, s.u_min() + (s.u_max() - s.u_min()) * i / (n - 1),
                                   s.v_min() + (s.v_max() - s.v_min()) * j / (n - 1));
      const double e = p[2] - design(p[0], p[1]);
      sum += e;
      sq += e * e;
      d.max_abs = std::max(d.max_abs, std::fabs(e));
      ++d.samples;
    }
  d.mean = sum / d.samples;
  d.std = std::sqrt(std::max(0.0, sq / d.samples - d.mean * d.mean));
  return d;
}

std::string describe(const Distance& d) {
  return "mean " + fixed(d.mean * 1000, 3) + " µm, std " + fixed(d.std * 1000, 3) + " µm, max |d| " +
         fixed(d.max_abs * 1000, 3) + " µm";
}

}  // namespace

int run_surface_fit(const SurfaceFitOptions& o, std::ostream& out, std::ostream& err) {
  if (!o.design.empty() && o.design_plane) {
    err << "pcnc surface fit: give --design or --design-plane, not both\n";
    return kExitBadInput;
  }
  if (!(o.e >= 0.0 && o.e <= 1.0)) {
    err << "pcnc surface fit: --e must lie in [0, 1]\n";
    return kExitBadInput;
  }
  PointGrid grid;
  std::optional<BSplineSurface> design;
  try {
    check_output_paths({{o.output, "-o"}, {o.report, "--report"}});
    grid = load_point_grid_csv(o.points);
    if (!o.design.empty()) design = load_surface_file(o.design);
  } catch (const std::exception& e) {
    err << "pcnc surface fit: " << e.what() << "\n";
    return kExitBadInput;
  }
  const SurfaceFit initial = interpolate_grid(grid, o.degree, o.e);
  if (!initial.ok()) {
    err << "pcnc surface fit: " << o.points << ": " << initial.error << "\n";
    return kExitBadInput;
  }
  const double f_initial = fairness(initial);
  out << o.points << ": " << grid.cols << " x " << grid.rows << " points, degree " << o.degree << "\n";
  out << "  e = " << fixed(o.e, 4) << ": F = " << sig(f_initial) << " mm^-2\n";
  SurfaceFit chosen = initial;
  if (o.fair) {
    FairFit fair = fair_fit(grid, o.degree);
    if (!fair.fit.ok()) {
      err << "pcnc surface fit: " << o.points << ": " << fair.fit.error << "\n";
      return kExitBadInput;
    }
    out << "  faired: e = " << fixed(fair.e, 4) << ": F = " << sig(fair.fairness) << " mm^-2 ("
        << signed_percent(f_initial > 0 ? 100.0 * (fair.fairness - f_initial) / f_initial : 0.0) << " %; " << fair.fits
        << " fits: scan of e in steps of 0.05, then golden section)\n";
    chosen = std::move(fair.fit);
  }
  std::function<double(double, double)> design_z;
  std::string design_name;
  if (design) {
    design_z = [&](double x, double y) { return surface_height(*design, x, y).z; };
    design_name = o.design;
  } else if (o.design_plane) {
    const double z = *o.design_plane;
    design_z = [z](double, double) { return z; };
    design_name = "the plane z = " + sig(z) + " mm";
  }
  std::vector<std::pair<std::string, std::string>> figures = {
      {"points", o.points + ": " + std::to_string(grid.cols) + " × " + std::to_string(grid.rows)},
      {"degree", std::to_string(o.degree)},
      {"F before fairing", sig(f_initial) + " mm⁻² (e = " + fixed(o.e, 4) + ")"}};
  if (o.fair)
    figures.push_back({"F after fairing", sig(fairness(chosen)) + " mm⁻² (e = " + fixed(chosen.surface.e, 4) + ")"});
  if (design_z) {
    const Distance d0 = distance(initial.surface, design_z);
    out << "  distance to " << design_name << " (Z, fitted - design, " << d0.samples << " samples): " << describe(d0)
        << "\n";
    figures.push_back({"distance to design", describe(d0) + (o.fair ? " (before fairing)" : "")});
    if (o.fair) {
      const Distance d1 = distance(chosen.surface, design_z);
      out << "  ... after fairing: " << describe(d1) << "\n";
      figures.push_back({"distance to design after fairing", describe(d1)});
    }
  }
  try {
    save_surface_file(o.output, chosen.surface);
  } catch (const std::exception& e) {
    err << "pcnc surface fit: " << e.what() << "\n";
    return kExitBadInput;
  }
  out << "  wrote " << o.output << "\n";
  if (!o.report.empty()) {
    SurfacePage page;
    page.title = o.points;
    page.figures = figures;
    page.nx = page.ny = 60;
    page.probes = grid.points;
    page.x0 = page.y0 = INFINITY;
    page.x1 = page.y1 = -INFINITY;
    for (const Vec3& p : grid.points) {
      page.x0 = std::min(page.x0, p[0]), page.x1 = std::max(page.x1, p[0]);
      page.y0 = std::min(page.y0, p[1]), page.y1 = std::max(page.y1, p[1]);
    }
    page.map_label = design_z ? "Fitted minus design surface (Z), µm" : "Fitted surface height minus its mean, µm";
    double mean = 0;
    for (int j = 0; j < page.ny; ++j)
      for (int i = 0; i < page.nx; ++i) {
        const double x = page.x0 + (page.x1 - page.x0) * (i + 0.5) / page.nx;
        const double y = page.y0 + (page.y1 - page.y0) * (j + 0.5) / page.ny;
        const double z = surface_height(chosen.surface, x, y).z;
        page.values.push_back(1000.0 * (design_z ? z - design_z(x, y) : z));
        mean += page.values.back() / (page.nx * page.ny);
      }
    if (!design_z)
      for (double& v : page.values) v -= mean;
    std::ofstream f(o.report, std::ios::binary | std::ios::trunc);
    f << surface_page_html(page);
    f.close();
    if (!f) {
      err << "pcnc surface fit: " << o.report << ": cannot be written\n";
      return kExitBadInput;
    }
    out << "  wrote " << o.report << "\n";
  }
  return kExitOk;
}

void add_surface_subcommand(CLI::App& app, int& exit_code) {
  auto* surface = app.add_subcommand("surface", "measured surfaces: fit a probed grid (docs/surface.md)");
  surface->require_subcommand(1);
  auto o = std::make_shared<SurfaceFitOptions>();
  auto* fit = surface->add_subcommand(
      "fit",
      "fit the seed paper's non-uniform B-spline surface through a probed grid (CSV: header x,y,z; rows of constant y, "
      "y increasing; x increasing within a row), optionally faired (the e in [0,1] minimising F = sum of the squared "
      "normal curvatures at the points), and write it as a surface file for run/check/serve --surface");
  fit->add_option("POINTS", o->points, "the grid CSV (machine mm)")->required();
  fit->add_option("-o,--output", o->output, "the surface file to write (JSON)")->required();
  fit->add_option("--degree", o->degree, "degree of the surface in u and v, 1..5")
      ->check(CLI::Range(1, 5))
      ->capture_default_str();
  fit->add_option("--e", o->e, "parameter exponent without --fair: 0 uniform, 0.5 centripetal, 1 chord length")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  fit->add_flag("--fair", o->fair, "choose e in [0,1] minimising the fairness F (seed eq. 15)");
  fit->add_option("--design", o->design, "design surface file: print the fitted surface's distance to it");
  fit->add_option("--design-plane", o->design_plane, "design plane z = Z mm: print the distance to it");
  fit->add_option("--report", o->report, "also write an HTML page with the figures and a coloured error map");
  fit->callback([o, &exit_code] { exit_code = run_surface_fit(*o, std::cout, std::cerr); });
}

}  // namespace pcnc
