// block_ruled.cpp — a RuledModel copied into the fixed arrays of a RuledGeometry, and the
// view back. See block_ruled.hpp.
#include "ipc/block_ruled.hpp"

#include <algorithm>
#include <cmath>

namespace pcnc {

RuledCurves curves_of(const RuledGeometry& g) {
  const int n = std::clamp(g.segment_count, 0, kMaxRuledSegments);  // never past the arrays
  RuledCurves r;
  r.directrix = CurveSource::of(HermiteView{g.directrix, n});
  r.ruling = CurveSource::of(HermiteView{g.ruling, n});
  r.form = static_cast<RulingForm>(g.ruling_form);
  return r;
}

RuledExtent ruled_extent(const RuledGeometry& g) {
  const int n = std::clamp(g.segment_count, 0, kMaxRuledSegments);
  RuledExtent e;
  if (n == 0) return e;
  Vec3 lo = g.directrix[0].p0, hi = lo;
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < 3; ++i) {
      lo[i] = std::min(lo[i], g.directrix[j].p1[i]);
      hi[i] = std::max(hi[i], g.directrix[j].p1[i]);
    }
  }
  for (int i = 0; i < 3; ++i) {
    if (hi[i] - lo[i] > 1e-12) ++e.moving;
    if (hi[i] - lo[i] > hi[e.widest] - lo[e.widest]) e.widest = i;
  }
  return e;
}

double hermite_arc_length(const HermiteView& c) {
  // 8 node pairs of the 16-point Gauss–Legendre rule on [-1, 1] (positive nodes, weights).
  static constexpr double kX[8] = {0.0950125098376374, 0.2816035507792589, 0.4580167776572274,
                                   0.6178762444026438, 0.7554044083550030, 0.8656312023878318,
                                   0.9445750230732326, 0.9894009349916499};
  static constexpr double kW[8] = {0.1894506104550685, 0.1826034150449236, 0.1691565193950025,
                                   0.1495959888165767, 0.1246289712555339, 0.0951585116824928,
                                   0.0622535239386479, 0.0271524594117541};
  double len = 0.0;
  for (int i = 0; i < c.count; ++i) {
    for (int k = 0; k < 8; ++k) {
      for (const double x : {-kX[k], kX[k]}) {
        len += 0.5 * kW[k] * norm(hermite_jet(c.segments[i], 0.5 * (x + 1.0)).d1);
      }
    }
  }
  return len;
}

std::string to_geometry(const RuledModel& model, double feed_mm_s, double accel_mm_s2, double start_speed,
                        double end_speed, RuledGeometry& g) {
  const int n = static_cast<int>(model.directrix.size());
  if (n < 1 || model.ruling.size() != model.directrix.size()) return "a ruled piece needs matching segments";
  if (n > kMaxRuledSegments) {
    return "a ruled piece of " + std::to_string(n) + " segments does not fit one block (at most " +
           std::to_string(kMaxRuledSegments) + ")";
  }
  if (!(feed_mm_s > 0.0) || !std::isfinite(feed_mm_s)) return "the feed of a ruled piece must be positive";
  if (!(accel_mm_s2 > 0.0) || !std::isfinite(accel_mm_s2)) return "the acceleration of a ruled piece must be positive";
  if (!(start_speed >= 0.0) || !(end_speed >= 0.0)) return "start and end speeds must not be negative";
  g = RuledGeometry{};
  g.segment_count = n;
  g.ruling_form = static_cast<std::int32_t>(model.form);
  for (int i = 0; i < n; ++i) {
    g.directrix[i] = model.directrix[i];
    g.ruling[i] = model.ruling[i];
  }
  g.length = hermite_arc_length(HermiteView{g.directrix, n});
  g.accel = accel_mm_s2;
  g.start_speed = start_speed;
  g.end_speed = end_speed;
  g.schedule_count = n + 1;
  for (int i = 0; i <= n; ++i) {
    g.schedule_u[i] = i;
    g.schedule_speed[i] = feed_mm_s;
  }
  return {};
}

std::vector<RuledModel> split_for_blocks(const RuledModel& model) {
  std::vector<RuledModel> parts;
  const std::size_t n = model.directrix.size();
  for (std::size_t i = 0; i < n; i += kMaxRuledSegments) {
    const std::size_t j = std::min(n, i + kMaxRuledSegments);
    RuledModel part;
    part.form = model.form;
    part.directrix.assign(model.directrix.begin() + i, model.directrix.begin() + j);
    part.ruling.assign(model.ruling.begin() + i, model.ruling.begin() + j);
    parts.push_back(std::move(part));
  }
  return parts;
}

}  // namespace pcnc
