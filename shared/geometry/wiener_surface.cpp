// wiener_surface.cpp — the symmetrised Wiener surface of the seed's eq. 16 (see the header).
#include "geometry/wiener_surface.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

namespace pcnc {
namespace {

// A standard normal from two uniform draws (Box–Muller), the same on every library.
struct Normal {
  std::mt19937_64 gen;
  bool has_spare = false;
  double spare = 0.0;
  double uniform() { return (static_cast<double>(gen() >> 11) + 0.5) * (1.0 / 9007199254740992.0); }
  double next() {
    if (has_spare) {
      has_spare = false;
      return spare;
    }
    const double r = std::sqrt(-2.0 * std::log(uniform())), a = 2.0 * std::numbers::pi * uniform();
    spare = r * std::sin(a);
    has_spare = true;
    return r * std::cos(a);
  }
};

// Uniform cubic B-spline weights for a local parameter t in [0, 1].
void cubic_weights(double t, double w[4]) {
  const double s = 1.0 - t;
  w[0] = s * s * s / 6.0;
  w[1] = (3.0 * t * t * t - 6.0 * t * t + 4.0) / 6.0;
  w[2] = (-3.0 * t * t * t + 3.0 * t * t + 3.0 * t + 1.0) / 6.0;
  w[3] = t * t * t / 6.0;
}

}  // namespace

WienerSurface::WienerSurface(std::uint64_t seed, int cells, double amplitude_mm) : cells_(std::max(1, cells)) {
  const int n = cells_ + 1;
  Normal rng{std::mt19937_64(seed)};
  const double sd = 1.0 / cells_;  // sqrt(dt1 * dt2)
  std::vector<double> w(static_cast<std::size_t>(n * n), 0.0);
  auto at = [n](std::vector<double>& v, int i, int j) -> double& { return v[static_cast<std::size_t>(j * n + i)]; };
  for (int j = 1; j < n; ++j)
    for (int i = 1; i < n; ++i) at(w, i, j) = at(w, i - 1, j) + at(w, i, j - 1) - at(w, i - 1, j - 1) + sd * rng.next();
  aw_.assign(static_cast<std::size_t>(n * n), 0.0);
  double sq = 0.0;
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const double v = 0.25 * (at(w, i, j) + at(w, cells_ - i, j) + at(w, i, cells_ - j) + at(w, cells_ - i, cells_ - j));
      at(aw_, i, j) = v;
      sq += v * v;
    }
  }
  const double rms = std::sqrt(sq / (n * n));
  const double k = rms > 0.0 ? amplitude_mm / rms : 0.0;
  for (double& v : aw_) v *= k;
}

double WienerSurface::value(double t1, double t2) const {
  const double x = std::clamp(t1, 0.0, 1.0) * cells_, y = std::clamp(t2, 0.0, 1.0) * cells_;
  const int i = std::min(static_cast<int>(x), cells_ - 1), j = std::min(static_cast<int>(y), cells_ - 1);
  const double fx = x - i, fy = y - j;
  return (1 - fx) * (1 - fy) * node(i, j) + fx * (1 - fy) * node(i + 1, j) + (1 - fx) * fy * node(i, j + 1) +
         fx * fy * node(i + 1, j + 1);
}

double WienerSurface::smooth_value(double t1, double t2) const {
  const double x = std::clamp(t1, 0.0, 1.0) * cells_, y = std::clamp(t2, 0.0, 1.0) * cells_;
  // node k sits at the centre of its B-spline: the spline over nodes k-1..k+2 for x in [k, k+1]
  const int i = std::min(static_cast<int>(x), cells_ - 1), j = std::min(static_cast<int>(y), cells_ - 1);
  double wx[4], wy[4];
  cubic_weights(x - i, wx);
  cubic_weights(y - j, wy);
  double sum = 0.0;
  for (int b = 0; b < 4; ++b) {
    const int jj = std::clamp(j - 1 + b, 0, cells_);
    double row = 0.0;
    for (int a = 0; a < 4; ++a) row += wx[a] * node(std::clamp(i - 1 + a, 0, cells_), jj);
    sum += wy[b] * row;
  }
  return sum;
}

}  // namespace pcnc
