// probe_contact.hpp — what a touch-trigger probe's ball meets on the simulated machine's table:
// the workpiece's top surface (a plane, optionally with an analytic Gaussian bump on it), a
// reference sphere and a gauge block, all in machine coordinates (mm); and the probe's trigger
// model (ball radius, pre-travel by approach direction). Pure functions, no allocation, no I/O:
// pcnc-rt calls them every cycle (rt/drive/sim_probe.hpp), tests call them directly.
//
// Contact rule (docs/probe.md): the probe triggers once the stylus has deflected by its
// pre-travel δ, that is when the ball centre c comes within R − δ of the nearest object:
//   gap(c) <= R − δ,   gap = signed distance from c to the object (negative inside).
// For the plane and sphere and the box gap is exact; for the bump (a height field) it is the
// first-order estimate (z − f(x, y)) / sqrt(1 + |∇f|²), exact on a plane and off by about
// R²·κ where the surface bends with curvature κ (documented, tested against brute force).
// The same first-order gap serves a B-spline workpiece (a `pcnc surface fit` file) and the
// seed's Wiener machining error added to any workpiece top (issue 15 item 1): both are loaded
// or generated before the rt's loop starts; evaluating them allocates nothing.
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <memory>

#include "geometry/bspline_surface.hpp"
#include "geometry/vec3.hpp"
#include "geometry/wiener_surface.hpp"

namespace pcnc {

/// The table's contents (machine coordinates, mm).
struct TableScene {
  // Workpiece top: z = z_mm + slope_x·x + slope_y·y + bump_height·exp(−r²/(2σ²)), r the
  // horizontal distance from (bump_x, bump_y). has_surface false: no workpiece.
  bool has_surface = false;
  double z_mm = 0.0;
  double slope_x = 0.0, slope_y = 0.0;  // dz/dx, dz/dy
  double bump_x_mm = 0.0, bump_y_mm = 0.0, bump_height_mm = 0.0, bump_sigma_mm = 1.0;
  // Reference sphere (sphere_radius_mm > 0).
  Vec3 sphere_center{};
  double sphere_radius_mm = 0.0;
  // Gauge block: the axis-aligned box gauge_min .. gauge_max (has_gauge).
  bool has_gauge = false;
  Vec3 gauge_min{}, gauge_max{};
  // A B-spline surface as the workpiece top instead of the plane and bump (surface = "bspline").
  std::shared_ptr<const BSplineSurface> bspline;
  // The machining error added to the workpiece top: the seed's symmetrised Wiener surface
  // (eq. 16, smooth_value) over the rectangle error_min .. error_max (X/Y, mm), held at its
  // border outside. Null: none.
  std::shared_ptr<const WienerSurface> error;
  double error_x0_mm = 0.0, error_x1_mm = 1.0, error_y0_mm = 0.0, error_y1_mm = 1.0;
  // The reference artefact for the volumetric calibration: a ball plate, balls of one radius
  // at known centres (their distances are the artefact's known lengths).
  static constexpr int kMaxArtefactBalls = 16;
  int artefact_balls = 0;
  std::array<Vec3, kMaxArtefactBalls> artefact_centres{};
  double artefact_ball_radius_mm = 0.0;
};

/// The touch-trigger probe (mm). Pre-travel for a unit approach direction d (docs/probe.md):
///   δ(d) = axial·d_z² + (lateral + lobe·cos 3θ)·(d_x² + d_y²),  θ = atan2(d_y, d_x),
/// the three-lobed pattern of a kinematic (three-ball) probe seat.
struct ProbeModel {
  double ball_radius_mm = 1.0;
  double pretravel_axial_mm = 0.0;
  double pretravel_lateral_mm = 0.0;
  double pretravel_lobe_mm = 0.0;
  double repeatability_mm = 0.0;  // 1 σ of the trigger point along the approach, per touch
  std::uint64_t seed = 1;         // of the repeatability noise (deterministic)
  double overtravel_mm = 1.0;     // how far the stylus may be pushed past the trigger, harmless
};

constexpr double kNoContact = std::numeric_limits<double>::infinity();

/// Height of the workpiece surface at (x, y) and its gradient (dz/dx, dz/dy).
double surface_height(const TableScene& s, double x, double y, double* dzdx = nullptr, double* dzdy = nullptr);
/// Signed distance from c to each object (negative inside); kNoContact when the object is absent.
double surface_gap(const TableScene& s, const Vec3& c);
double sphere_gap(const TableScene& s, const Vec3& c);
double gauge_gap(const TableScene& s, const Vec3& c);
double artefact_gap(const TableScene& s, const Vec3& c);
/// The smallest of them.
double scene_gap(const TableScene& s, const Vec3& c);
/// True when a ball centred at c with trigger radius r (= R − δ) touches something.
inline bool ball_touches(const TableScene& s, const Vec3& c, double trigger_radius) {
  return scene_gap(s, c) <= trigger_radius;
}
/// Pre-travel δ(d) for the approach direction d (normalised inside; zero d: the axial value).
double pretravel_mm(const ProbeModel& p, const Vec3& d);
/// The fastest probing speed (mm/s) whose stop fits in the overtravel: the rt sees the trigger
/// one cycle after the crossing and then brakes at `accel`, so v·2dt + v²/(2a) <= overtravel.
double probe_speed_limit(double accel, double dt, double overtravel_mm);

}  // namespace pcnc
