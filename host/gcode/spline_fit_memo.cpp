// spline_fit_memo.cpp — fits kept between passes (see spline_fit_memo.hpp).
#include "gcode/spline_fit_memo.hpp"

#include <cstdint>
#include <mutex>
#include <unordered_map>
#include <utility>

namespace pcnc {
namespace {

struct Entry {
  std::vector<Vec3> points;
  double tolerance = 0.0;
  SplineFit fit;
  std::size_t bytes = 0;
};

struct Memo {
  std::mutex mutex;
  std::unordered_multimap<std::uint64_t, Entry> entries;
  std::size_t bytes = 0, hits = 0, misses = 0;
};

Memo& memo() {
  static Memo m;
  return m;
}

// FNV-1a over the input's bytes (a sieve: equality is checked in full)
std::uint64_t hash_of(const std::vector<Vec3>& points, double tolerance) {
  std::uint64_t h = 1469598103934665603ull;
  auto mix = [&h](const void* p, std::size_t n) {
    const auto* b = static_cast<const unsigned char*>(p);
    for (std::size_t i = 0; i < n; ++i) h = (h ^ b[i]) * 1099511628211ull;
  };
  mix(points.data(), points.size() * sizeof(Vec3));
  mix(&tolerance, sizeof tolerance);
  return h;
}

std::size_t bytes_of(const std::vector<Vec3>& points, const SplineFit& f) {
  return (points.size() + f.curve.points.size()) * sizeof(Vec3) +
         (f.curve.weights.size() + f.curve.knots.size()) * sizeof(double) + sizeof(Entry);
}

}  // namespace

SplineFit fit_polyline_memo(const std::vector<Vec3>& points, double tolerance) {
  const std::uint64_t h = hash_of(points, tolerance);
  Memo& m = memo();
  {
    std::lock_guard<std::mutex> lock(m.mutex);
    auto [lo, hi] = m.entries.equal_range(h);
    for (auto it = lo; it != hi; ++it) {
      if (it->second.tolerance == tolerance && it->second.points == points) {
        SplineFit fit = std::move(it->second.fit);
        m.bytes -= it->second.bytes;
        m.entries.erase(it);
        ++m.hits;
        return fit;
      }
    }
    ++m.misses;
  }
  SplineFit fit = fit_polyline(points, tolerance);
  Entry e{points, tolerance, fit, bytes_of(points, fit)};
  std::lock_guard<std::mutex> lock(m.mutex);
  if (e.bytes > kSplineFitMemoBytes) return fit;
  if (m.bytes + e.bytes > kSplineFitMemoBytes) {
    m.entries.clear();
    m.bytes = 0;
  }
  m.bytes += e.bytes;
  m.entries.emplace(h, std::move(e));
  return fit;
}

SplineFitMemoStats spline_fit_memo_stats() {
  Memo& m = memo();
  std::lock_guard<std::mutex> lock(m.mutex);
  return {m.entries.size(), m.bytes, m.hits, m.misses};
}

void spline_fit_memo_clear() {
  Memo& m = memo();
  std::lock_guard<std::mutex> lock(m.mutex);
  m.entries.clear();
  m.bytes = 0;
  m.hits = 0;
  m.misses = 0;
}

}  // namespace pcnc
