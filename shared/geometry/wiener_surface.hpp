// wiener_surface.hpp — the seed paper's machining error (eq. 16): a Wiener surface (Brownian
// sheet) W on the unit square, symmetrised
//     AW(t1, t2) = 1/4 (W(t1, t2) + W(1 - t1, t2) + W(t1, 1 - t2) + W(1 - t1, 1 - t2)),
// made from a seed number, for tests and benches (and the simulated workpiece of issue 15).
//
// W is sampled on a lattice of `cells` x `cells` cells: independent normal increments
// (std::mt19937_64 from the seed, Box–Muller, so the numbers are the same with every standard
// library) of variance dt1 * dt2 per cell, summed from the corner (0, 0). AW is taken at the
// lattice nodes and scaled so that its root mean square over the nodes is `amplitude_mm`.
// Between nodes: value() interpolates bilinearly (the sheet itself, rough at the lattice
// scale); smooth_value() is the uniform cubic B-spline over the node values (C2: an error
// whose shortest wavelength is about the lattice spacing, what a fitted surface can follow).
#pragma once

#include <cstdint>
#include <vector>

namespace pcnc {

class WienerSurface {
 public:
  WienerSurface(std::uint64_t seed, int cells, double amplitude_mm);

  /// AW at (t1, t2), each clamped into [0, 1]: bilinear between lattice nodes.
  double value(double t1, double t2) const;
  /// The uniform cubic B-spline over the lattice node values (clamped at the border).
  double smooth_value(double t1, double t2) const;

  int cells() const { return cells_; }
  double node(int i, int j) const { return aw_[static_cast<std::size_t>(j * (cells_ + 1) + i)]; }

 private:
  int cells_;
  std::vector<double> aw_;  // (cells+1)^2 node values, row j of constant t2
};

}  // namespace pcnc
