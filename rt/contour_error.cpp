// contour_error.cpp — Newton's method for the nearest point on a path (see contour_error.hpp).
#include "contour_error.hpp"

#include <algorithm>
#include <cmath>

namespace pcnc {

PathDistance distance_to_path(const PreparedBlock& block, const Vec3& p, double s_guess) {
  const double L = block.length;
  if (block.kind == BlockKind::kLine || block.kind == BlockKind::kRapid) {
    // closed form: project onto the segment
    const double s = L > 0.0 ? std::clamp(dot(p - block.start, block.dir_start), 0.0, L) : 0.0;
    return {norm(block.start + s * block.dir_start - p), s};
  }
  double s = std::clamp(s_guess, 0.0, L);
  // f(s) = (c(s) − p)·t(s); f'(s) = t·t + (c − p)·κ = 1 + (c − p)·κ for an arc-length curve.
  bool converged = false;
  PathPoint q = evaluate(block, s);
  for (int it = 0; it < 6; ++it) {
    const Vec3 d = q.p - p;
    const double f = dot(d, q.tangent);
    double fp = 1.0 + dot(d, q.curvature);
    if (fp < 0.1) fp = 0.1;  // far outside an arc's centre of curvature: take a plain step
    const double next = std::clamp(s - f / fp, 0.0, L);
    const bool small = std::abs(next - s) < 1e-9;
    s = next;
    q = evaluate(block, s);
    if (small) {
      converged = true;
      break;
    }
  }
  PathDistance r{norm(q.p - p), s};
  // The ends are candidates too when Newton did not settle inside (clamped there, or
  // wandering between two local minima).
  if (!converged || s <= 0.0 || s >= L) {
    for (const double e : {0.0, L}) {
      const double d = norm(evaluate(block, e).p - p);
      if (d < r.distance) r = {d, e};
    }
  }
  return r;
}

}  // namespace pcnc
