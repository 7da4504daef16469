// probe_compensation.hpp — from latched ball centres to points on the part (issue 15 item 3):
// the contact point is the ball centre moved back by the calibrated effective radius along the
// surface normal,  q = p − r_eff(d)·n  (d the approach direction, n the unit outward normal).
//
// The normal comes from the measured data themselves: the ball centres of a grid lie on the
// part's offset surface (at r_eff from it), whose normal at p is the part's normal at q; so a
// B-spline surface interpolating the centres (surface_fit.hpp, e = 1) gives n at each probed
// point without knowing the part. A scattered list uses the plane through each point's nearest
// neighbours (sphere_fit.hpp). Pure mathematics: std and geometry/.
#pragma once

#include <string>
#include <vector>

#include "geometry/probe_calibration.hpp"
#include "geometry/surface_fit.hpp"
#include "geometry/vec3.hpp"

namespace pcnc {

/// q = p − r_eff·n̂ (n normalised here).
Vec3 contact_point(const Vec3& centre, const Vec3& normal, double r_eff);
/// ... with r_eff from the calibration for the approach direction d.
Vec3 contact_point(const Vec3& centre, const Vec3& normal, const Vec3& approach, const ProbeCalibration& cal);

struct GridCompensation {
  PointGrid contacts;         // the compensated points, the centres' grid order
  std::vector<Vec3> normals;  // unit outward normal at each point (against the approach)
  int degree = 0;             // of the B-spline surface the normals came from
  std::string error;
  bool ok() const { return error.empty(); }
};

/// Compensates a grid of latched centres (PointGrid order: rows of constant y). `approaches`
/// holds one direction for every point, or a single one for all. Normals from the surface of
/// degree min(3, cols − 1, rows − 1) interpolating the centres with chord-length parameters;
/// each oriented against its approach direction. Refuses grids below 2 × 2 and sizes that do
/// not match.
GridCompensation compensate_grid(const PointGrid& centres, const std::vector<Vec3>& approaches,
                                 const ProbeCalibration& cal);

struct PointsCompensation {
  std::vector<Vec3> contacts;  // the compensated points, in the centres' order
  std::vector<Vec3> normals;   // unit outward normal at each (local_normal)
  std::string error;
  bool ok() const { return error.empty(); }
};

/// Compensates a scattered list of latched centres, each along the normal of the plane through
/// it and its `neighbours` nearest others (local_normal). `approaches`: one per point or one
/// for all. Refuses fewer than 3 points, sizes that do not match, and a point whose neighbours
/// lie on one line.
PointsCompensation compensate_points(const std::vector<Vec3>& centres, const std::vector<Vec3>& approaches,
                                     const ProbeCalibration& cal, int neighbours = 6);

/// The unit normal at centres[index] of a scattered list: the plane through it and its
/// `neighbours` nearest others (at least 2), oriented against `approach`. Zero when the
/// neighbours lie on one line.
Vec3 local_normal(const std::vector<Vec3>& centres, std::size_t index, int neighbours, const Vec3& approach);

}  // namespace pcnc
