// spline_fit_memo.cpp — fits kept between passes (see spline_fit_memo.hpp).
#include "gcode/spline_fit_memo.hpp"

#include <cstdint>
#include <utility>

#include "gcode/hand_over_memo.hpp"

namespace pcnc {
namespace {

struct FitMemoEntry {
  std::vector<Vec3> points;
  double tolerance = 0.0;
  SplineFit fit;
};

HandOverMemo<FitMemoEntry>& fit_memo() {
  static HandOverMemo<FitMemoEntry> m(kSplineFitMemoBytes);
  return m;
}

std::uint64_t hash_of(const std::vector<Vec3>& points, double tolerance) {
  std::uint64_t h = kFnv1aSeed;  // a sieve: equality is checked in full
  fnv1a_mix(h, points.data(), points.size() * sizeof(Vec3));
  fnv1a_mix(h, &tolerance, sizeof tolerance);
  return h;
}

std::size_t bytes_of(const std::vector<Vec3>& points, const SplineFit& f) {
  return (points.size() + f.curve.points.size()) * sizeof(Vec3) +
         (f.curve.weights.size() + f.curve.knots.size()) * sizeof(double) + sizeof(FitMemoEntry);
}

}  // namespace

SplineFit fit_polyline_memo(const std::vector<Vec3>& points, double tolerance) {
  const std::uint64_t h = hash_of(points, tolerance);
  auto same = [&](const FitMemoEntry& e) { return e.tolerance == tolerance && e.points == points; };
  if (auto e = fit_memo().take(h, same)) return std::move(e->fit);
  SplineFit fit = fit_polyline(points, tolerance);
  const std::size_t bytes = bytes_of(points, fit);
  fit_memo().put(h, FitMemoEntry{points, tolerance, fit}, bytes);
  return fit;
}

SplineFitMemoStats spline_fit_memo_stats() { return fit_memo().stats(); }

void spline_fit_memo_clear() { fit_memo().clear(); }

}  // namespace pcnc
