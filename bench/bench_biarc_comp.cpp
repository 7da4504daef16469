// bench_biarc_comp.cpp — the seed paper's analysis (cutter-compensation-biarc.txt), as figures
// (never pass/fail). One free-form contour (a planar cubic NURBS) is given to a controller's
// cutter compensation three ways, and each is offset by tool radii r = 1..6 mm:
//  (a) line segments of length s with their end points rounded to 0.001 mm, as CAM output:
//      each segment offset along its own normal (what a controller does); the seed predicts
//      an error d = 2 r eps / s, eps = 0.0005 mm the largest rounding error;
//  (b) biarcs within 0.001 mm (fit_biarcs), offset exactly about their centres, written with
//      6 decimals (pcnc biarc) or rounded to 0.001 mm;
//  (c) LinuxCNC's G5.2 rule, re-implemented from its description: 4 equal-ratio biarcs per
//      control point at equal steps of the parameter, no error check.
// Error = the largest distance of the tool path from the exact offset curve C + r n: for a
// point q beside the curve | |q - C| - r | (nearest curve point by Newton projection).
// --svg FILE draws the curve, its biarcs and their offset (docs/biarc-fit.md).

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "bench_cli.hpp"
#include "geometry/biarc.hpp"
#include "geometry/nurbs.hpp"

using namespace pcnc;

namespace {

constexpr double kEps = 0.0005;  // largest rounding error of 0.001 mm output

NurbsCurve contour() {
  return make_nurbs({{0, 0, 0}, {12, 18, 0}, {30, 22, 0}, {42, 6, 0}, {56, -4, 0}, {70, 10, 0}, {80, 26, 0}},
                    std::vector<double>(7, 1.0), 4);
}

Vec2 pt(const NurbsCurve& c, double u) { return to_plane(nurbs_point(c.view(), u), 2); }

double round_to(double v, double q) { return std::round(v / q) * q; }
Vec2 round_to(Vec2 p, double q) { return {round_to(p.x, q), round_to(p.y, q)}; }

// Error of a tool-path point q meant to lie on the offset by r (left): | |q - C| - r |, the
// nearest curve point by Newton projection.
double offset_error(const NurbsCurve& c, Vec2 q, double r) {
  double d = 0.0;
  nurbs_project(c.view(), from_plane(q, 2, 0.0), &d, 64);
  return std::abs(d - r);
}

// Points of the curve at arc-length steps s (the last one the end point).
std::vector<Vec2> polyline(const NurbsCurve& c, double s) {
  std::vector<Vec2> pts{pt(c, c.u_min())};
  const int n = 20000;
  double acc = 0.0;
  Vec2 prev = pts.front();
  for (int i = 1; i <= n; ++i) {
    const Vec2 p = pt(c, c.u_min() + (c.u_max() - c.u_min()) * i / n);
    acc += distance(p, prev);
    prev = p;
    if (acc >= s) {
      pts.push_back(p);  // s to s + 0.005 mm from the last one
      acc = 0.0;
    }
  }
  // the end point: in place of the last sample when that is closer than s / 2 (no short segment)
  const Vec2 end = pt(c, c.u_max());
  if (distance(pts.back(), end) < 0.5 * s && pts.size() > 1) pts.back() = end;
  else if (distance(pts.back(), end) > 0.0) pts.push_back(end);
  return pts;
}

// (a) what a controller makes of the rounded segments: each offset along its own normal; at a
// junction turning toward the tool (concave) the two offset lines are cut at their
// intersection, at one turning away (convex) an arc of radius r about the vertex joins them
// (LinuxCNC's rule). A segment tilted by alpha moves its offset by r tan(alpha) along the path
// (the seed's d = 2 r eps / s); where two such nearly parallel offsets are intersected, the cut
// lands far off, and an offset cut before its own start runs backwards: the tangle.
struct SegmentResult {
  double shift = 0.0;  // largest r tan(alpha), alpha the tilt rounding gave a segment
  double error = 0.0;
  int reversed = 0;  // offset segments cut to negative length
};
SegmentResult segments_error(const NurbsCurve& c, const std::vector<Vec2>& pts, double r) {
  SegmentResult res;
  std::vector<Vec2> p;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const Vec2 rq = round_to(pts[i], 0.001);
    if (i > 0) {
      const Vec2 exact = pts[i] - pts[i - 1], got = rq - round_to(pts[i - 1], 0.001);
      res.shift = std::max(res.shift, r * std::abs(std::tan(std::atan2(cross(exact, got), dot(exact, got)))));
    }
    if (p.empty() || distance(p.back(), rq) > 0.0) p.push_back(rq);
  }
  double t_start = 0.0;  // where the current offset segment begins, as a fraction of it
  for (std::size_t i = 0; i + 1 < p.size(); ++i) {
    const Vec2 d = p[i + 1] - p[i];
    const Vec2 n = perp(normalized(d));
    const Vec2 a = p[i] + r * n, b = p[i + 1] + r * n;
    if (i + 2 >= p.size()) {
      res.error = std::max(res.error, offset_error(c, b, r));
      break;
    }
    const Vec2 e = p[i + 2] - p[i + 1];
    const Vec2 m = perp(normalized(e));
    const double turn = cross(d, e);
    if (turn > 0.0) {  // concave for a tool on the left: cut the two offset lines
      const Vec2 a2 = p[i + 1] + r * m;
      const double t = cross(a2 - a, e) / cross(d, e);  // along this offset segment
      const Vec2 x = a + t * d;
      if (t < t_start) ++res.reversed;
      res.error = std::max(res.error, offset_error(c, x, r));
      t_start = dot(x - a2, e) / dot(e, e);  // where the next one begins
    } else {
      res.error = std::max({res.error, offset_error(c, b, r), offset_error(c, p[i + 1] + r * m, r)});
      t_start = 0.0;
    }
  }
  return res;
}

// Arcs rounded as a G-code file writes them: ends and centre to q (0: exact), the radius the
// controller takes from the rounded start and centre.
std::vector<Arc2> rounded(const std::vector<Arc2>& arcs, double q) {
  if (q <= 0.0) return arcs;
  std::vector<Arc2> out;
  for (const Arc2& a : arcs) {
    Arc2 b = a;
    b.start = round_to(a.start, q);
    b.end = round_to(a.end, q);
    if (!a.line) {
      b.centre = round_to(a.centre, q);
      b.radius = distance(b.start, b.centre);
    }
    out.push_back(b);
  }
  return out;
}

// (b), (c): arcs offset exactly by r, sampled densely.
double arcs_error(const NurbsCurve& c, const std::vector<Arc2>& arcs, double r) {
  double worst = 0.0;
  for (const Arc2& a : arcs) {
    const ArcOffset o = offset_arc(a, r);
    for (int k = 0; k <= 24; ++k) worst = std::max(worst, offset_error(c, arc_point(o.arc, k / 24.0), r));
  }
  return worst;
}

// (c) LinuxCNC's G5.2 rule: (n+1)*4 biarcs at equal steps of u, tangent lengths equal; where
// no biarc exists LinuxCNC writes nothing (here: a segment, so that the path stays whole).
BiarcFit linuxcnc_rule(const NurbsCurve& c) {
  BiarcFit fit;
  const int div = static_cast<int>(c.points.size()) * 4;
  Vec2 p0 = pt(c, c.u_min()), t0 = normalized(to_plane(nurbs_tangent(c.view(), c.u_min(), true), 2));
  for (int i = 1; i <= div; ++i) {
    const double u = c.u_min() + (c.u_max() - c.u_min()) * i / div;
    const Vec2 p1 = pt(c, u), t1 = normalized(to_plane(nurbs_tangent(c.view(), u, false), 2));
    const double u0 = c.u_min() + (c.u_max() - c.u_min()) * (i - 1) / div;
    std::vector<Arc2> arcs;
    if (const auto b = make_biarc(p0, t0, p1, t1, 1.0)) arcs = {b->first, b->second};
    else arcs = {make_segment(p0, p1)};
    fit.max_deviation_mm = std::max(fit.max_deviation_mm, curve_deviation(c, 2, u0, u, arcs));
    append_biarc(fit.arcs, arcs);
    ++fit.biarcs;
    p0 = p1, t0 = t1;
  }
  return fit;
}

void write_svg(const std::string& path, const NurbsCurve& c, const std::vector<Arc2>& arcs, double r) {
  FILE* f = std::fopen(path.c_str(), "w");
  if (!f) {
    std::fprintf(stderr, "bench_biarc_comp: cannot write %s\n", path.c_str());
    return;
  }
  const double scale = 10.0, x0 = -8, y0 = 34;  // mm -> px, y up
  auto X = [&](double x) { return (x - x0) * scale; };
  auto Y = [&](double y) { return (y0 - y) * scale; };
  std::fprintf(f, "<svg xmlns='http://www.w3.org/2000/svg' width='%d' height='%d' font-family='sans-serif' font-size='14'>\n",
               static_cast<int>(X(90)), static_cast<int>(Y(-14)));
  std::fprintf(f, "<rect width='100%%' height='100%%' fill='white'/>\n");
  // the curve
  std::fprintf(f, "<polyline fill='none' stroke='#bbb' stroke-width='6' points='");
  for (int i = 0; i <= 600; ++i) {
    const Vec2 p = pt(c, c.u_min() + (c.u_max() - c.u_min()) * i / 600);
    std::fprintf(f, "%.2f,%.2f ", X(p.x), Y(p.y));
  }
  std::fprintf(f, "'/>\n");
  // arcs (alternating colours), their centres' joints, and the exact offset of each
  auto path_of = [&](const Arc2& a, const char* colour, double width) {
    if (a.line) {
      std::fprintf(f, "<line x1='%.2f' y1='%.2f' x2='%.2f' y2='%.2f' stroke='%s' stroke-width='%.1f'/>\n", X(a.start.x),
                   Y(a.start.y), X(a.end.x), Y(a.end.y), colour, width);
      return;
    }
    // SVG y points down: a counter-clockwise arc in mm turns clockwise on the screen, which is
    // SVG's positive angle direction (sweep flag 1)
    std::fprintf(f, "<path fill='none' stroke='%s' stroke-width='%.1f' d='M %.2f %.2f A %.2f %.2f 0 %d %d %.2f %.2f'/>\n",
                 colour, width, X(a.start.x), Y(a.start.y), a.radius * scale, a.radius * scale,
                 std::abs(a.sweep) > M_PI ? 1 : 0, a.sweep > 0 ? 1 : 0, X(a.end.x), Y(a.end.y));
  };
  for (std::size_t i = 0; i < arcs.size(); ++i) path_of(arcs[i], i % 2 ? "#d62728" : "#1f77b4", 2.0);
  for (const Arc2& a : arcs)
    std::fprintf(f, "<circle cx='%.2f' cy='%.2f' r='3' fill='black'/>\n", X(a.start.x), Y(a.start.y));
  for (const Arc2& a : offset_chain(arcs, r)) path_of(a, "#2ca02c", 1.5);
  std::fprintf(f, "<text x='10' y='%d'>grey: the NURBS contour; blue/red: its %zu arcs (biarcs within 0.001 mm, "
                  "dots at their ends);</text>\n", static_cast<int>(Y(-10)), arcs.size());
  std::fprintf(f, "<text x='10' y='%d'>green: their exact offset by r = %g mm (radius - r about the same centres)</text>\n",
               static_cast<int>(Y(-12)), r);
  std::fprintf(f, "</svg>\n");
  std::fclose(f);
}

}  // namespace

int main(int argc, char** argv) {
  pcnc::BenchCli app{"bench_biarc_comp: offset error of line segments vs biarcs under cutter compensation (seed paper)"};
  std::string svg;
  double svg_radius = 3.0;
  app.add_option("--svg", svg, "also draw the curve, its biarcs and their offset to this SVG file");
  app.add_option("--svg-radius", svg_radius, "offset radius drawn in the SVG, mm")->show_default();
  if (const int rc = app.parse(argc, argv); rc >= 0) return rc;

  const NurbsCurve c = contour();
  double min_left_radius = 1e300;
  for (int i = 0; i <= 4000; ++i) {
    const NurbsEval e = nurbs_eval(c.view(), c.u_min() + (c.u_max() - c.u_min()) * i / 4000);
    const double turn = cross(e.d1, e.d2)[2];  // > 0: turning left, the offset side
    if (turn > 0) min_left_radius = std::min(min_left_radius, 1.0 / nurbs_curvature(e));
  }
  const double length = nurbs_arc_length(c.view(), c.u_min(), c.u_max());
  std::printf("contour: cubic NURBS, 7 control points, length %.2f mm, smallest radius of a left turn %.2f mm;\n"
              "tool path offset to the left by r as a controller makes it; error = largest distance from the\n"
              "exact offset curve, mm; (a) also: offset segments the controller's cut leaves running backwards\n\n",
              length, min_left_radius);

  BiarcOptions bo;
  bo.tolerance_mm = 0.001;
  const BiarcFit fit = fit_biarcs(c, 2, bo);
  const BiarcFit lcnc = linuxcnc_rule(c);
  const std::vector<double> steps{0.05, 0.1, 0.2, 0.5};
  std::vector<std::vector<Vec2>> polys;
  for (double s : steps) polys.push_back(polyline(c, s));

  std::printf("blocks: ");
  for (std::size_t k = 0; k < steps.size(); ++k) std::printf("segments s=%.2f: %zu; ", steps[k], polys[k].size() - 1);
  std::printf("biarcs: %zu arcs (fit deviation %.6f mm); LinuxCNC rule: %zu arcs (fit deviation %.6f mm)\n\n",
              fit.arcs.size(), fit.max_deviation_mm, lcnc.arcs.size(), lcnc.max_deviation_mm);

  std::printf("%2s", "r");
  for (double s : steps) std::printf(" | (a) s=%.2f: d  2r*eps/s   error back", s);
  std::printf(" | (b) arcs 1e-6 | (b) arcs 0.001 | (c) LinuxCNC\n");
  for (int r = 1; r <= 6; ++r) {
    std::printf("%2d", r);
    for (std::size_t k = 0; k < steps.size(); ++k) {
      const SegmentResult a = segments_error(c, polys[k], r);
      std::printf(" | %8.5f %8.5f %8.5f %4d", a.shift, 2.0 * r * kEps / steps[k], a.error, a.reversed);
    }
    std::printf(" | %13.6f | %14.6f | %11.6f\n", arcs_error(c, rounded(fit.arcs, 1e-6), r),
                arcs_error(c, rounded(fit.arcs, 0.001), r), arcs_error(c, rounded(lcnc.arcs, 1e-6), r));
  }
  std::printf("\n(a) d: the largest shift r tan(alpha) of an offset segment tilted by the rounding, against the\n"
              "    seed's d = 2 r eps / s (eps = %.4f mm, the largest rounding error of 0.001 mm output; a point\n"
              "    rounded in both axes can reach sqrt(2) eps); error: the controller's tool path (offset\n"
              "    segments cut at their intersections, arcs at convex corners) against the exact offset;\n"
              "    back: offset segments that path runs backwards along (the tangles of the seed's figure 6);\n"
              "(b) biarcs within 0.001 mm offset exactly: the error stays the fit's whatever r (rounding the\n"
              "    arcs to 0.001 mm adds the rounding itself, not magnified);\n"
              "(c) LinuxCNC's fixed rule (4 equal-ratio biarcs per control point, equal steps of u): its fit\n"
              "    error, unchecked, carried unchanged into the offset.\n",
              kEps);
  if (!svg.empty()) write_svg(svg, c, fit.arcs, svg_radius);
  return 0;
}
