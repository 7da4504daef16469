// nurbs_schedule.cpp — dense NURBS feed schedule, its cut into block schedules, and the
// NURBS move turned into ring blocks. See nurbs_schedule.hpp.
#include "gcode/nurbs_schedule.hpp"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cmath>
#include <limits>

#include "geometry/axis_caps.hpp"
#include "geometry/nurbs_arc_samples.hpp"
#include "geometry/tangential_budget.hpp"

namespace pcnc {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// The schedule's own ramps use this share of each sample's tangential acceleration. The rt
// interpolates the schedule linearly in u, not in arc length, so between two points its slope
// can be a little steeper than the ramp it was planned with; the margin lets the follower
// (which accelerates at the full acceleration of the sample) track every decrease.
constexpr double kRampAccelShare = 0.9;

// The tangential acceleration is found at the samples only; between them the tangent and
// curvature turn a little, and the rt's parameter steps add a little of their own. This share
// of what the axes leave keeps every axis within its limit between the samples as well
// (kTangentialAccelMargin, 0.95; 0.9 until 2026-11-26. tests/test_surfacing_limits: the setpoints
// reach at most 0.972 of an axis's acceleration on the curves of LHchips4 and blur_torus; at 0.97
// the rational full circle of test_nurbs_end_to_end at F3000 reached 1.0033 of Y's limit).
constexpr double kTangentialMargin = kTangentialAccelMargin;

struct SampleLimit {
  double speed;
  FeedLimit binding;
};

// Speed limit at one curve point from its tangent and curvature vector.
SampleLimit limit_at(const CurveFrame& f, const NurbsLimits& lim) {
  SampleLimit out{lim.feed_mm_s, FeedLimit::kFeed};
  auto take = [&out](double v, FeedLimit why) {
    if (v < out.speed) {
      out.speed = v;
      out.binding = why;
    }
  };
  if (!f.ok) return out;
  const double kappa = norm(f.k);
  take(axis_cap(f.t, lim.axis_velocity_mm_s), FeedLimit::kAxisVelocity);
  // centripetal: axis i sees v²·|k_i|, within its share of the axis's acceleration
  AxisLimits normal_accel{};
  for (int i = 0; i < kAxes; ++i) normal_accel[i] = lim.normal_accel_share * lim.axis_accel_mm_s2[i];
  take(std::sqrt(axis_cap(f.k, normal_accel)), FeedLimit::kCentripetal);
  if (kappa > 0.0) {
    const double rho = 1.0 / kappa;
    const double d = lim.chord_tolerance_mm;
    const double arg = std::max(2.0 * rho * d - d * d, d * d);
    take(2.0 / lim.period_s * std::sqrt(arg), FeedLimit::kChord);
  }
  return out;
}

// The acceleration a sample allows at speed v: the margin times what the axes leave after the
// normal part (geometry/tangential_budget.hpp); a point without a tangent allows what every
// axis allows in any direction.
double sample_accel(const FeedSample& f, double v, const NurbsLimits& lim) {
  if (!f.has_frame) {
    const AxisLimits& a = lim.axis_accel_mm_s2;
    return kTangentialMargin * std::min({a[0], a[1], a[2]});
  }
  double b = tangential_budget(f.t, f.k, v * v, lim.axis_accel_mm_s2);
  if (f.has_left) b = std::min(b, tangential_budget(f.t_left, f.k_left, v * v, lim.axis_accel_mm_s2));
  return kTangentialMargin * std::max(0.0, b);
}

// The largest v² at sample b reached from sample a (at v2_a) over ds with a ramp of at most
// `share` of the tangential acceleration both samples allow (each at its own speed; the
// budget is linear in v², so both bounds have closed forms).
double ramp_v2(const FeedSample& a, double v2_a, const FeedSample& b, double ds, const NurbsLimits& lim, double share) {
  double x = v2_a + 2.0 * ds * share * sample_accel(a, std::sqrt(v2_a), lim);
  if (b.has_frame) {
    x = std::min(x, reachable_v2(v2_a, ds, b.t, b.k, lim.axis_accel_mm_s2, share * kTangentialMargin));
    if (b.has_left) x = std::min(x, reachable_v2(v2_a, ds, b.t_left, b.k_left, lim.axis_accel_mm_s2, share * kTangentialMargin));
  } else {
    x = std::min(x, v2_a + 2.0 * ds * share * sample_accel(b, 0.0, lim));
  }
  return x;
}

// Forward and backward passes over the dense samples with speeds v: between neighbours the
// speed² changes by at most 2·ds·kRampAccelShare·(the acceleration both samples allow).
void dense_passes(const std::vector<FeedSample>& s, std::vector<double>& v, const NurbsLimits& lim, double v_start,
                  double v_end) {
  const std::size_t n = s.size();
  if (n == 0) return;
  v[0] = std::min(v[0], v_start);
  for (std::size_t j = 1; j < n; ++j) {
    v[j] = std::min(v[j], std::sqrt(ramp_v2(s[j - 1], v[j - 1] * v[j - 1], s[j], s[j].s - s[j - 1].s, lim, kRampAccelShare)));
  }
  v[n - 1] = std::min(v[n - 1], v_end);
  for (std::size_t j = n - 1; j-- > 0;) {
    v[j] = std::min(v[j], std::sqrt(ramp_v2(s[j + 1], v[j + 1] * v[j + 1], s[j], s[j + 1].s - s[j].s, lim, kRampAccelShare)));
  }
}

// The same for a block's kept points: arc lengths s_of(k), accelerations acc[k] (each already
// valid at any speed up to the point's), kRampAccelShare of the smaller of two neighbours.
template <typename GetS>
void block_passes(std::size_t n, GetS s_of, const std::vector<double>& acc, std::vector<double>& v) {
  for (std::size_t j = 1; j < n; ++j) {
    const double a = kRampAccelShare * std::min(acc[j - 1], acc[j]);
    v[j] = std::min(v[j], std::sqrt(v[j - 1] * v[j - 1] + 2.0 * a * (s_of(j) - s_of(j - 1))));
  }
  for (std::size_t j = n - 1; j-- > 0;) {
    const double a = kRampAccelShare * std::min(acc[j], acc[j + 1]);
    v[j] = std::min(v[j], std::sqrt(v[j + 1] * v[j + 1] + 2.0 * a * (s_of(j + 1) - s_of(j))));
  }
}

}  // namespace

NurbsLimits nurbs_limits(const MachineConfig& config, double feed_mm_s) {
  NurbsLimits lim;
  lim.feed_mm_s = feed_mm_s;
  lim.period_s = config.cycle_period_s();
  lim.chord_tolerance_mm = config.gcode.nurbs_chord_tolerance_mm;
  for (std::size_t i = 0; i < static_cast<std::size_t>(kAxes); ++i) {
    lim.axis_velocity_mm_s[i] = config.axes[i].max_velocity_mm_s;
    lim.axis_accel_mm_s2[i] = config.axes[i].max_accel_mm_s2;
  }
  return lim;
}

const char* to_string(FeedLimit limit) {
  switch (limit) {
    case FeedLimit::kFeed: return "feed";
    case FeedLimit::kChord: return "chord error";
    case FeedLimit::kCentripetal: return "centripetal acceleration";
    case FeedLimit::kAxisVelocity: return "axis velocity";
    case FeedLimit::kCorner: return "corner";
  }
  return "?";
}

namespace {
// The speed at which a kink (a tangent turning by at most kTangentKinkTurn at a knot, where
// packed arcs join) steps each axis's velocity by at most kKinkStepShare of its acceleration
// times one period: the rest of the cycle's acceleration stays the ramp's.
double kink_speed(const Vec3& t_before, const Vec3& t_after, const NurbsLimits& lim) {
  double v = kInf;
  for (std::size_t i = 0; i < 3; ++i) {
    const double step = std::abs(t_after[i] - t_before[i]);
    if (step > 1e-12) v = std::min(v, kKinkStepShare * lim.axis_accel_mm_s2[i] * lim.period_s / step);
  }
  return v;
}
}  // namespace

FeedSchedule plan_nurbs_feed(const NurbsCurve& curve, const NurbsLimits& lim, double v_start, double v_end) {
  FeedSchedule out;
  out.limits = lim;
  const NurbsView v = curve.view();
  const std::vector<double> corners = corner_knots(curve);
  const int per_span = std::max(2, lim.samples_per_span);
  // Sample parameters: every distinct knot of the domain and per_span-1 points inside each span.
  std::vector<double> us;
  std::vector<bool> interior_knot;  // the sample is a knot inside the domain
  for (int i = v.degree; i < v.count; ++i) {
    const double a = v.knots[i];
    const double b = v.knots[i + 1];
    if (!(b > a)) continue;
    for (int k = 0; k < per_span; ++k) {
      us.push_back(a + (b - a) * k / per_span);
      interior_knot.push_back(k == 0 && a > v.u_min());
    }
  }
  us.push_back(v.u_max());
  interior_knot.push_back(false);

  out.samples.reserve(us.size());  // each sample written once, as it is made (no zeroing pass first)
  const std::vector<double> arc = nurbs_arc_lengths_at(v, us);
  int span = v.degree;  // the samples go forward: each one's span is tried first
  CurveFrame f, next;  // frames two at a time (nurbs_frame_pair): f at us[j], next at us[j + 1]
  for (std::size_t j = 0; j < us.size(); ++j) {
    FeedSample& fs = out.samples.emplace_back();
    fs.u = us[j];
    if (j % 2 == 1) {
      f = next;
    } else if (j + 1 < us.size()) {
      nurbs_frame_pair(v, us[j], us[j + 1], span, f, next);
    } else {
      f = nurbs_frame(v, fs.u, span);
    }
    fs.has_frame = f.ok;
    fs.t = f.t;
    fs.k = f.k;
    SampleLimit sl = limit_at(f, lim);
    if (f.ok && interior_knot[j]) {
      const CurveFrame left = nurbs_frame(v, fs.u - 1e-12 * (v.u_max() - v.u_min()));
      if (left.ok) {
        fs.has_left = true;
        fs.t_left = left.t;
        fs.k_left = left.k;
        const SampleLimit sl_left = limit_at(left, lim);
        if (sl_left.speed < sl.speed) sl = sl_left;
        const double kink = kink_speed(left.t, f.t, lim);
        if (kink < sl.speed) sl = {kink, FeedLimit::kCorner};
      }
    }
    fs.limit = sl.speed;
    fs.binding = sl.binding;
    if (std::find(corners.begin(), corners.end(), fs.u) != corners.end()) {
      fs.limit = 0.0;
      fs.binding = FeedLimit::kCorner;
    }
    fs.s = arc[j];
  }
  out.length_mm = out.samples.back().s;

  // The limit holds at the samples; take the smaller neighbour as well so that the linear
  // interpolation between samples stays under a limit that varies between them.
  std::vector<double> speed(out.samples.size());
  for (std::size_t j = 0; j < speed.size(); ++j) {
    double m = out.samples[j].limit;
    if (j > 0) m = std::min(m, out.samples[j - 1].limit);
    if (j + 1 < speed.size()) m = std::min(m, out.samples[j + 1].limit);
    speed[j] = m;
  }
  dense_passes(out.samples, speed, lim, v_start, v_end);
  out.accel_mm_s2 = kInf;
  for (std::size_t j = 0; j < speed.size(); ++j) {
    FeedSample& fs = out.samples[j];
    fs.speed = speed[j];
    fs.accel = sample_accel(fs, fs.speed, lim);
    out.accel_mm_s2 = std::min(out.accel_mm_s2, fs.accel);
  }
  if (!std::isfinite(out.accel_mm_s2)) out.accel_mm_s2 = 0.0;
  return out;
}

double schedule_speed_at(const FeedSchedule& schedule, double u) {
  const auto& s = schedule.samples;
  if (s.empty()) return 0.0;
  if (u <= s.front().u) return s.front().speed;
  if (u >= s.back().u) return s.back().speed;
  const auto it = std::upper_bound(s.begin(), s.end(), u, [](double x, const FeedSample& f) { return x < f.u; });
  const FeedSample& b = *it;
  const FeedSample& a = *(it - 1);
  const double f = (u - a.u) / (b.u - a.u);
  return a.speed + f * (b.speed - a.speed);
}

void fill_block_schedule(const FeedSchedule& schedule, double u0, double u1, NurbsGeometry& g) {
  const auto& s = schedule.samples;
  auto lower = std::lower_bound(s.begin(), s.end(), u0, [](const FeedSample& f, double x) { return f.u < x; });
  auto upper = std::upper_bound(s.begin(), s.end(), u1, [](double x, const FeedSample& f) { return x < f.u; });
  const std::size_t first = static_cast<std::size_t>(lower - s.begin());
  const std::size_t count = static_cast<std::size_t>(upper - lower);
  if (count <= static_cast<std::size_t>(kMaxFeedSchedule)) {
    for (std::size_t k = 0; k < count; ++k) {
      g.schedule_u[k] = s[first + k].u;
      g.schedule_speed[k] = s[first + k].speed;
      g.schedule_accel[k] = s[first + k].accel;
      g.schedule_s[k] = s[first + k].s - s[first].s;
    }
    g.schedule_count = static_cast<std::uint16_t>(count);
    return;
  }
  // Too many samples: keep kMaxFeedSchedule of them, chosen greedily where the polyline
  // through the kept ones deviates most from the dense schedule,
  // always the first and the last.
  const std::size_t m = static_cast<std::size_t>(kMaxFeedSchedule);
  const std::size_t last = first + count - 1;
  // The rt interpolates linearly in u between schedule points, so lines are in u here.
  auto line_at = [&](std::size_t a, std::size_t b, double va, double vb, std::size_t i) {
    const double t = (s[i].u - s[a].u) / (s[b].u - s[a].u);
    return va + t * (vb - va);
  };
  // Each interval between two kept points remembers its worst sample (the first of the largest
  // deviations); an insertion rescans only the two intervals it makes. The choice is the one a
  // full rescan makes: the first interval with the largest worst, its first worst sample.
  struct Worst {
    double dev = 0.0;
    std::size_t i = 0;  // 0: none (the interval is on the dense schedule)
  };
  auto worst_of = [&](std::size_t a, std::size_t b) {
    Worst w;
    for (std::size_t i = a + 1; i < b; ++i) {
      const double dev = std::fabs(line_at(a, b, s[a].speed, s[b].speed, i) - s[i].speed);
      if (dev > w.dev) w = Worst{dev, i};
    }
    return w;
  };
  std::vector<std::size_t> pick{first, last};
  std::vector<Worst> worst{worst_of(first, last)};  // worst[k]: interval pick[k] .. pick[k + 1]
  while (pick.size() < m) {
    std::size_t k_best = 0;
    double dev_best = worst[0].dev;  // kept apart: a load through k_best per step was a third of this function
    for (std::size_t k = 1; k < worst.size(); ++k) {
      if (worst[k].dev > dev_best) {
        k_best = k;
        dev_best = worst[k].dev;
      }
    }
    const std::size_t worst_i = worst[k_best].i;
    if (worst_i == 0) break;  // the polyline already is the dense schedule
    pick.insert(pick.begin() + static_cast<std::ptrdiff_t>(k_best) + 1, worst_i);
    worst[k_best] = worst_of(pick[k_best], worst_i);
    worst.insert(worst.begin() + static_cast<std::ptrdiff_t>(k_best) + 1, worst_of(worst_i, pick[k_best + 2]));
  }
  // Lower the kept values where the straight line between two of them passes above the dense
  // schedule (lowering a value never raises a neighbouring line). First try lowering only the
  // higher end, pivoting about the lower one; if that is not enough, scale both ends.
  std::vector<double> speed(pick.size());
  for (std::size_t k = 0; k < pick.size(); ++k) speed[k] = s[pick[k]].speed;
  for (std::size_t k = 0; k + 1 < pick.size(); ++k) {
    const std::size_t a = pick[k];
    const std::size_t b = pick[k + 1];
    // Candidate 1: scale both ends by the worst ratio.
    double factor = 1.0;
    for (std::size_t i = a + 1; i < b; ++i) {
      const double line = line_at(a, b, speed[k], speed[k + 1], i);
      if (line > s[i].speed) factor = std::min(factor, line > 0.0 ? s[i].speed / line : 0.0);
    }
    if (factor >= 1.0) continue;
    double best_left = factor * speed[k];
    double best_right = factor * speed[k + 1];
    // Candidate 2: keep the lower end, lower the higher one (possible when nothing in between
    // is below the lower end).
    const bool left_high = speed[k] > speed[k + 1];
    const double low = std::min(speed[k], speed[k + 1]);
    double high = std::max(speed[k], speed[k + 1]);
    bool possible = true;
    for (std::size_t i = a + 1; i < b && possible; ++i) {
      const double t = (s[i].u - s[a].u) / (s[b].u - s[a].u);
      const double toward_high = left_high ? 1.0 - t : t;
      if (s[i].speed < low) possible = false;
      if (toward_high > 0.0 && low + toward_high * (high - low) > s[i].speed) {
        high = low + (s[i].speed - low) / toward_high;
      }
    }
    if (possible && low + high > best_left + best_right) {
      best_left = left_high ? high : low;
      best_right = left_high ? low : high;
    }
    speed[k] = best_left;
    speed[k + 1] = best_right;
  }
  // Each kept point's acceleration: the smallest that the dense samples it stands for (from its
  // left neighbour's to its right neighbour's) allow at the speed the rt reads there (the line
  // between the kept points, at or below the dense speed: what the axes leave is then at
  // least the dense sample's). The rt uses the smaller of two points between them. After the
  // passes lowered speeds, once more (it can only rise, so the passes still hold).
  // The second time only the intervals with an end the passes lowered change (an interval's
  // value depends on its two ends' speeds alone).
  std::vector<double> acc(pick.size());
  std::vector<double> interval(pick.size(), kInf);  // interval k: pick[k] .. pick[k + 1]
  std::vector<double> planned;                      // the speeds the intervals were found with
  auto kept_accels = [&] {
    auto same = [](double a, double b) { return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b); };
    for (std::size_t k = 0; k + 1 < pick.size(); ++k) {
      if (!planned.empty() && same(planned[k], speed[k]) && same(planned[k + 1], speed[k + 1])) continue;
      interval[k] = kInf;
      for (std::size_t i = pick[k]; i <= pick[k + 1]; ++i) {
        const double v = line_at(pick[k], pick[k + 1], speed[k], speed[k + 1], i);
        interval[k] = std::min(interval[k], sample_accel(s[i], std::min(v, s[i].speed), schedule.limits));
      }
    }
    for (std::size_t k = 0; k < pick.size(); ++k) {
      acc[k] = std::min(k > 0 ? interval[k - 1] : kInf, k + 1 < pick.size() ? interval[k] : kInf);
    }
    planned = speed;
  };
  kept_accels();
  block_passes(pick.size(), [&](std::size_t k) { return s[pick[k]].s; }, acc, speed);
  kept_accels();
  for (std::size_t k = 0; k < pick.size(); ++k) {
    g.schedule_u[k] = s[pick[k]].u;
    g.schedule_speed[k] = speed[k];
    g.schedule_accel[k] = acc[k];
    g.schedule_s[k] = s[pick[k]].s - s[first].s;
  }
  g.schedule_count = static_cast<std::uint16_t>(pick.size());
}

void set_nurbs_block_geometry(Block& b) {
  const NurbsView v = view_of(b.nurbs);
  // The curve is clamped: its ends are its first and last control points.
  b.start = v.points[0];
  b.end = v.points[v.count - 1];
  b.length = nurbs_arc_length(v, v.u_min(), v.u_max());
  b.dir_start = nurbs_tangent(v, v.u_min(), true);
  b.dir_end = nurbs_tangent(v, v.u_max(), false);
  // Motion class and driving axis from the extent of the control polygon.
  Vec3 lo = v.points[0], hi = v.points[0];
  for (int j = 0; j < v.count; ++j) {
    for (std::size_t i = 0; i < 3; ++i) {
      lo[i] = std::min(lo[i], v.points[j][i]);
      hi[i] = std::max(hi[i], v.points[j][i]);
    }
  }
  int moving = 0;
  std::size_t widest = 0;
  for (std::size_t i = 0; i < 3; ++i) {
    if (hi[i] - lo[i] > 1e-12) ++moving;
    if (hi[i] - lo[i] > hi[widest] - lo[widest]) widest = i;
  }
  b.motion_class = moving <= 1 ? MotionClass::kSingleAxis : moving == 2 ? MotionClass::kPlane : MotionClass::kSpace;
  b.driving_axis = static_cast<std::uint8_t>(widest);
  b.driving_dir = b.end[widest] >= b.start[widest] ? 1 : -1;
}

NurbsBlocks plan_nurbs_blocks(const NurbsCurve& curve, const NurbsLimits& limits) {
  NurbsBlocks out;
  out.error = validate(curve);
  if (!out.error.empty()) return out;
  if (!(limits.feed_mm_s > 0.0)) {
    out.error = "NURBS move needs a positive feed";
    return out;
  }
  // The block schedules hold the geometric limits only: the rt's follower ramps from the
  // start speed and to the end speed itself, with the same acceleration.
  out.schedule = plan_nurbs_feed(curve, limits, kInf, kInf);
  const std::vector<double> corners = corner_knots(curve);
  const std::vector<NurbsCurve> pieces = split_for_blocks(curve);
  for (const NurbsCurve& piece : pieces) {
    Block b;
    b.kind = BlockKind::kNurbs;
    if (std::string err = to_geometry(piece, b.nurbs); !err.empty()) {
      out.error = err;
      out.blocks.clear();
      out.corner_after.clear();
      return out;
    }
    fill_block_schedule(out.schedule, piece.u_min(), piece.u_max(), b.nurbs);
    set_nurbs_block_geometry(b);
    double vmax = 0.0;
    for (int k = 0; k < b.nurbs.schedule_count; ++k) vmax = std::max(vmax, b.nurbs.schedule_speed[k]);
    b.speed = std::min(limits.feed_mm_s, vmax);
    // the rt brakes (stop rules, feed hold) at this one value: safe all along the block
    double amin = kInf;
    for (int k = 0; k < b.nurbs.schedule_count; ++k) amin = std::min(amin, b.nurbs.schedule_accel[k]);
    b.accel = amin;
    out.blocks.push_back(b);
    out.corner_after.push_back(std::find(corners.begin(), corners.end(), piece.u_max()) != corners.end());
  }
  return out;
}

}  // namespace pcnc
