// minmax_lp.hpp — the point of R³ that minimises the largest of many affine functions,
// min over x of max_j (a_j·x − b_j): a small linear program (4 unknowns, any number of rows),
// solved exactly by the simplex method on its dual (Dantzig's rule, Bland's rule against
// cycling). A value <= 0 means x satisfies every a_j·x <= b_j, with a margin of −value
// (in b's unit when the a_j are unit vectors). The --fit of tool-centre-point programs
// (tcp_fit.hpp) asks it whether an offset keeps every joint within its travel. Pure.
#pragma once

#include <vector>

#include "geometry/vec3.hpp"

namespace pcnc {

struct MinMaxRow {
  Vec3 a{};
  double b = 0.0;
};

struct MinMaxResult {
  bool ok = false;     // false: unbounded (the a_j leave a direction in which every row falls) or no convergence
  Vec3 x{};            // the minimiser (one of them when several)
  double value = 0.0;  // max_j (a_j·x − b_j) at x, evaluated directly
};

/// Needs at least one row. Unbounded unless for every direction d some a_j·d > 0 (rows in
/// opposite pairs, as lower and upper limits give, always bound it).
MinMaxResult minimize_max_affine(const std::vector<MinMaxRow>& rows);

}  // namespace pcnc
