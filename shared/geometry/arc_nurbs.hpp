// arc_nurbs.hpp — a chain of circular arcs as one NURBS curve, exactly: each arc a rational
// quadratic (degree 2, pieces of at most 90°, the middle weight cos(half the piece's sweep)).
// An arc whose end radius differs from its start's by a rounding is the conic through its
// ends whose middle point lies at the mean radius: the caller measures how far that is.
//
// The host packs chains of short arcs into one curve so that a ring slot holds many of them
// (host/gcode/arc_packing.hpp); the path stays the programmed arcs, to rounding. Pure
// mathematics: no moves, no blocks.
#pragma once

#include <vector>

#include "geometry/nurbs.hpp"
#include "geometry/vec3.hpp"

namespace pcnc {

/// One arc in a coordinate plane: from `start` about `center` (on the start's level along the
/// normal axis) by the signed `sweep` (rad, > 0 counter-clockwise seen from +normal, the
/// right-hand rule of geometry/plane.hpp), in the plane normal to `normal_axis` (2 = Z, G17).
/// `end` is the end point as the program gives it: at `sweep`, its radius the start's to
/// rounding (the radius between goes linearly with the angle, as the rt runs an arc).
struct PlaneArc {
  Vec3 start{};
  Vec3 end{};
  Vec3 center{};
  double sweep = 0.0;
  int normal_axis = 2;
};

/// The point of the arc at the angle `phi` from its start (0..sweep).
Vec3 plane_arc_point(const PlaneArc& a, double phi);
/// The unit tangent of the arc at the angle `phi`, in the direction of travel.
Vec3 plane_arc_tangent(const PlaneArc& a, double phi);
/// The arc's length (the mean of its start and end radii times |sweep|).
double plane_arc_length(const PlaneArc& a);

/// The NURBS curve that is the chain `arcs` (each one starting where the one before ends;
/// not checked here). Degree 2; an arc's pieces join at knots of multiplicity 2, and each arc's
/// last control point is its `end`, so the curve passes through the programmed end points. The knots are the chain's arc length: the parameter at arc
/// k's start is the length of arcs 0..k-1 (inside a piece the rational parameter is not arc
/// length). `arc_start_u`, if given, receives those parameters.
NurbsCurve arc_chain_nurbs(const std::vector<PlaneArc>& arcs, std::vector<double>* arc_start_u = nullptr);

}  // namespace pcnc
