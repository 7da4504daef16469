// ruled_passes.hpp — planning the passes of a ball-end mill over a part surface as ruled-surface
// pieces (issue 17, item 3; the seed paper's section 6.1): the pass interval P = 2 sqrt(h (2R - h))
// from the cusp height (cusp.hpp), iso-parametric passes at constant u whose contact curves lie
// at most P apart (exactly P at their widest), and along each pass the set points of the tool:
// the contact point, the surface normal n, the tool axis a (n tilted by a lead angle toward the
// direction of the pass) and the tool tip, the point the kinematics (kinematics.hpp) holds:
//   ball centre = contact + R n,   tip = centre - R a   (so tip = contact when a = n).
// Each pass is modelled by ruled_model_through (ruled_model.hpp): the tips are its Ferguson
// directrix, the axes its ruling. Pure: no I/O; the part surface is a value with an evaluation
// function (a B-spline surface, or an analytic one in tests).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "geometry/bspline_surface.hpp"
#include "geometry/ruled_model.hpp"
#include "geometry/vec3.hpp"

namespace pcnc {

/// A parametric part surface: its point and partial derivatives at (u, v) over a rectangle.
struct PartSurface {
  std::function<SurfaceEval(double, double)> eval;
  double u_min = 0.0, u_max = 1.0, v_min = 0.0, v_max = 1.0;
};

/// The B-spline surface as a part surface (the surface is copied into the function).
PartSurface part_surface(const BSplineSurface& s);

/// The seed paper's example (section 6.2; it does not give its coefficients): a size x size
/// freeform with a height difference of size/10, the bicubic z = 4 + 12 (3y^2 - 2y^3) +
/// 16 x(1 - x)(2y - 1) over the unit square (times size/200 everywhere: 200 x 200 x 20 mm at
/// size 200), written exactly as one bicubic Bezier patch. Its corner (x, y, z) = (0, 0, 0)
/// of the formula lands at `origin`; u runs along x, v along y.
BSplineSurface example_surface(double size, const Vec3& origin);

/// The formula itself, z over the unit square at scale 1 (0..20), for tests and benches.
double example_height(double x_unit, double y_unit);

struct PassOptions {
  double tool_radius = 1.0;     // ball radius R, mm
  double cusp_height = 0.005;   // h, mm
  double point_spacing = 1.0;   // set points along a pass about this far apart, mm
  double lead_angle = 0.0;      // rad: the axis tilted from the normal toward the pass's direction
  bool zigzag = true;           // every other pass runs backwards (v decreasing)
  int spacing_samples = 64;     // points per pass where the distance to the next pass is measured
  RulingForm form = RulingForm::kVector;
};

/// One set point of a pass.
struct PassPoint {
  double u = 0.0, v = 0.0;
  Vec3 contact{};  // on the surface
  Vec3 normal{};   // unit, the side with n.z >= 0 (the tool comes from above)
  Vec3 axis{};     // unit tool axis, from the tip into the spindle
  Vec3 tip{};      // tool tip: contact + R n - R axis
};

/// The tool's set point at a surface point moving in direction `dir` (any tangent vector
/// along the pass; only its part across n counts).
PassPoint pass_point(const SurfaceEval& e, const Vec3& dir, double tool_radius, double lead_angle);

struct Pass {
  double u = 0.0;                  // the iso-parameter
  bool reversed = false;           // runs from v_max to v_min
  std::vector<PassPoint> points;   // in the order the tool runs
  RuledModel model;                // through the tips and axes
  double length = 0.0;             // directrix length, mm (of the model, by quadrature)
  double gap_to_next = 0.0;        // measured distance to the next pass's contact curve, mm (0 for the last)
};

struct PassPlan {
  double interval = 0.0;  // P, mm
  std::vector<Pass> passes;
  std::string error;      // empty when planned
};

PassPlan plan_passes(const PartSurface& surface, const PassOptions& options);

/// The largest, over `samples` points of the contact curve at u0 (evenly in v), of the
/// distance from that point to the contact curve at u1 (its nearest point, by Newton in v;
/// where that falls beyond the curve's end, the distance to its end tangent line).
double pass_gap(const PartSurface& surface, double u0, double u1, int samples);

/// How far a pass's ruled piece strays from the exact tool path between its set points: over
/// `per_segment` samples inside every segment, the largest distance of the model's directrix
/// from the exact tip curve (its nearest point, golden section in v), and the largest angle
/// (rad) between the model's ruling and the exact axis at that nearest point.
struct ModelError {
  double tip = 0.0;
  double axis = 0.0;
};
ModelError pass_model_error(const PartSurface& surface, const Pass& pass, const PassOptions& options, int per_segment);

/// The length of a ruled piece's directrix (Gauss-Legendre per segment).
double directrix_length(const RuledModel& model);

}  // namespace pcnc
