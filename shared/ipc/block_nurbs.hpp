// block_nurbs.hpp — the NURBS part of a block as a view, and a host curve copied into it.
// The curve mathematics (geometry/nurbs.hpp) knows no blocks; this is where a NurbsCurve
// meets the fixed arrays of a ring slot (NurbsGeometry, ipc/block.hpp).
#pragma once

#include <string>
#include <vector>

#include "geometry/nurbs.hpp"
#include "ipc/block.hpp"

namespace pcnc {

/// View of the curve stored in a block (the rt evaluates this directly, every cycle).
NurbsView view_of(const NurbsGeometry& g);

/// Copies degree, points, weights and knots into `g` (schedule fields untouched). Returns
/// an error sentence when the curve does not fit one block (more than kMaxNurbsPoints).
std::string to_geometry(const NurbsCurve& curve, NurbsGeometry& g);
NurbsCurve from_geometry(const NurbsGeometry& g);

/// split_nurbs into pieces that each fit one block (kMaxNurbsPoints control points).
inline std::vector<NurbsCurve> split_for_blocks(const NurbsCurve& curve) {
  return split_nurbs(curve, kMaxNurbsPoints);
}

}  // namespace pcnc
