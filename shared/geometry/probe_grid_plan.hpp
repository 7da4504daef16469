// probe_grid_plan.hpp — where `pcnc measure` touches the workpiece (issue 15 item 3): a grid
// of nx × ny points over a rectangle, each probed along the estimated surface normal. For every
// point: the expected contact point q on the estimated surface, its unit normal n, the approach
// direction d = −n, the ball centre where the probing move starts (clearance above the ball's
// touching position) and where it ends (the probing distance beyond it):
//   start = q + (R + clearance)·n,   end = q + (R − probe_distance)·n,   R the ball radius.
// Order: the CSV order of issue 15 item 3: rows of constant y, y increasing, x increasing
// within a row. A list of points is planned one point at a time (plan_probe_point).
// Pure mathematics: std and geometry/.
#pragma once

#include <string>
#include <vector>

#include "geometry/bspline_surface.hpp"
#include "geometry/vec3.hpp"

namespace pcnc {

/// What is known of the workpiece before probing: a plane z = z0 + slope_x·x + slope_y·y, or
/// (when `surface` is set) a B-spline surface (a design or an earlier measurement; outside its
/// footprint its edge is used).
struct SurfaceEstimate {
  double z0_mm = 0.0;
  double slope_x = 0.0;
  double slope_y = 0.0;
  const BSplineSurface* surface = nullptr;
};

struct ProbeGridSpec {
  double x0_mm = 0.0, x1_mm = 0.0;   // x0 < x1 (x1 == x0 when nx == 1)
  double y0_mm = 0.0, y1_mm = 0.0;
  int nx = 0, ny = 0;                // points per row, rows (>= 1 each)
  double ball_radius_mm = 1.0;
  double clearance_mm = 1.0;         // the start above the expected touch, along n (> 0)
  double probe_distance_mm = 1.0;    // how far past the expected touch the move may go (> 0)
};

struct ProbePoint {
  int col = 0, row = 0;
  Vec3 expected_contact{};
  Vec3 normal{};                     // unit, outward (the probe's side)
  Vec3 approach{};                   // −normal
  Vec3 start{};                      // ball centre where the probing move starts
  Vec3 end{};                        // ball centre where it ends without contact
};

struct ProbeGridPlan {
  std::vector<ProbePoint> points;    // ny rows of nx, the CSV order
  std::string error;
  bool ok() const { return error.empty(); }
};

/// The height and unit upward normal of the estimate at (x, y).
void estimate_at(const SurfaceEstimate& s, double x, double y, double& z, Vec3& normal);

ProbeGridPlan plan_probe_grid(const ProbeGridSpec& spec, const SurfaceEstimate& estimate);

/// One touch at (x, y) (a list of points: col is its index, row 0), with the spec's ball
/// radius, clearance and probing distance (its rectangle and counts are not used).
ProbePoint plan_probe_point(double x, double y, const ProbeGridSpec& spec, const SurfaceEstimate& estimate);

}  // namespace pcnc
